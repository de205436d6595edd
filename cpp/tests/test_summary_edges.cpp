// The run summary at its edges: a judged window far shorter than an integrator step, and a
// top drive whose mean turn in the window goes against the torque.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "pydrill/simulator.hpp"

using namespace pydrill;

TEST_CASE("a tiny window's means lie within its extremes", "[summary][window]") {
  // The mean of a velocity over a window lies between its least and greatest values there.
  // From the angle turned over the window it is off by about ε·|φ| / T: at window_fraction
  // 1e-15 of a 300 s run (a window of 0.3 ps, φ_b near 5000 rad) the bit's mean came out
  // 19.2 rad/s beside a min and max of 18.30408, the top's 16.0 beside 16.35175.
  const Params p = preset("reduced-scale", 4);
  for (const double wob : {100.0, 40.0}) {  // stick-slip, steady
    for (const double fraction : {1e-15, 3e-15, 1e-14, 1e-13, 1e-12, 1e-10, 1e-8, 1e-6}) {
      SimulationOptions o;
      o.t_end = 300.0;
      o.window_fraction = fraction;
      const Summary s = simulate(p, wob, 8.3, o).summary;
      INFO("W_ob " << wob << " N, window_fraction " << fraction);
      CHECK(s.window_end - s.window_start > 0.0);
      CHECK(s.bit_min <= s.bit_mean);
      CHECK(s.bit_mean <= s.bit_max);
      CHECK(s.top_min <= s.top_mean);
      CHECK(s.top_mean <= s.top_max);
      CHECK(std::isfinite(s.severity));
    }
  }
}

TEST_CASE("a long window's mean is still the angle turned over it", "[summary][window]") {
  // Where the angle advance lies within the extremes it stands, exact whatever the sampling:
  // the same run with 31 and 3001 output times has the same means to the last bit or so.
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 300.0;
  o.n_out = 31;
  const Summary coarse = simulate(p, 100.0, 8.3, o).summary;
  o.n_out = 3001;
  const Summary fine = simulate(p, 100.0, 8.3, o).summary;
  CHECK(coarse.bit_mean == Approx(fine.bit_mean).epsilon(1e-12));
  CHECK(coarse.top_mean == Approx(fine.top_mean).epsilon(1e-12));
  CHECK(coarse.bit_min < coarse.bit_mean);
  CHECK(coarse.bit_mean < coarse.bit_max);
}
