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

TEST_CASE("bit_top_ratio follows the top drive's mean turn, not the sign of u",
          "[summary][ratio]") {
  // A string thrown backwards at u = 1 N·m > 0 (top and bit at −5 rad/s), which the rock then
  // holds: over the first 0.2 s the top drive turns backwards on average and the bit's
  // fastest turn that way is −5 rad/s. The ratio is that turn over the top's mean (as the
  // header says), the same as for the mirror image at u = −1 thrown forwards; by the sign of
  // u it would be max ω_b / mean ω_top = 0 / (< 0), saying nothing of the overshoot.
  const Params p = preset("reduced-scale", 2);
  SimulationOptions o;
  o.t_end = 0.2;
  o.window_fraction = 1.0;
  o.initial = Initial::State;
  o.state = {-5.0, 0.0, -5.0};
  const Summary back = simulate(p, 100.0, 1.0, o).summary;
  REQUIRE(back.top_mean < 0.0);
  CHECK(back.bit_min == -5.0);
  CHECK(back.bit_max == 0.0);
  CHECK(back.bit_top_ratio == back.bit_min / back.top_mean);
  CHECK(back.bit_top_ratio > 1.0);  // the bit's backward turn outruns the top's mean
  o.state = {5.0, 0.0, 5.0};
  const Summary mirror = simulate(p, 100.0, -1.0, o).summary;
  CHECK(mirror.top_mean == -back.top_mean);
  CHECK(mirror.bit_top_ratio == back.bit_top_ratio);
}

TEST_CASE("bit_top_ratio of a stuck window is its mirror image's", "[summary][ratio]") {
  // A bit slipping backwards at 1e-10 rad/s as the window opens, held by the rock from then on
  // (stuck, 1 − 8e-13 of the window), its top drive swinging back at u = 1: the ratio is the
  // bit's fastest turn the top's way over the top's mean, 2.2e-10, as for the mirror image at
  // u = −1. A stuck window with max ω_b = 0 had its ratio set to 0, and so this one's, while
  // the mirror image, whose min ω_b is 0, kept 2.2e-10.
  const Params p = preset("reduced-scale", 2);
  SimulationOptions o;
  o.t_end = 0.5;
  o.window_fraction = 1.0;
  o.initial = Initial::State;
  o.state = {-1.0, 0.0, -1e-10};
  const Summary back = simulate(p, 100.0, 1.0, o).summary;
  o.state = {1.0, 0.0, 1e-10};
  const Summary mirror = simulate(p, 100.0, -1.0, o).summary;
  REQUIRE(back.regime == Regime::Stuck);
  REQUIRE(mirror.regime == Regime::Stuck);
  CHECK(back.bit_min == -1e-10);
  CHECK(back.bit_max == 0.0);
  CHECK(back.bit_top_ratio == back.bit_min / back.top_mean);
  CHECK(back.bit_top_ratio > 0.0);
  CHECK(mirror.bit_top_ratio == back.bit_top_ratio);
}
