// Guards found by a second mutation audit of the simulation side (session 37): each test fails
// on a small change to the code that decides what a run returns (an option's range shifted by
// one, a switch function's rate dropped, an integrator's root report lost) that no other test
// noticed, and checks against something independent of that code: the ranges documented in
// simulator.hpp and pydrill.simulate, the run of another integrator, or the physics of DESIGN.md.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "pydrill/simulator.hpp"
#include "stick_phases.hpp"
#include "swing.hpp"

using namespace pydrill;

namespace {

constexpr double kWob = 100.0;  // N: T_s = 8 N·m on the reduced-scale string

bool accepted(const SimulationOptions& o) {
  try {
    o.validate(4);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace

TEST_CASE("mutation guard: the options' documented ranges include their edges", "[mutation]") {
  // simulator.hpp: rtol <= kMaxRtol, 0 < window_fraction <= 1, max_steps >= 1, |perturbation|
  // < 1, max_switch_rate > 0, BDF orders 1..5. Each edge on both sides.
  SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = kMaxRtol;
  CHECK(accepted(o));
  o.rtol = 1e-8;
  o.window_fraction = 1.0;
  CHECK(accepted(o));
  o.window_fraction = 0.5;
  o.max_steps = 1;
  CHECK(accepted(o));
  o.max_steps = 0;
  CHECK_FALSE(accepted(o));
  o.max_steps = 1000;
  o.perturbation = 1.0;
  CHECK_FALSE(accepted(o));
  o.perturbation = -1.0;
  CHECK_FALSE(accepted(o));
  o.perturbation = std::nextafter(1.0, 0.0);
  CHECK(accepted(o));
  o.perturbation = 1e-3;
  o.max_switch_rate = 0.0;
  CHECK_FALSE(accepted(o));
  o.max_switch_rate = 1e4;
  o.method = Method::BDF;
  o.max_order = 5;
  CHECK(accepted(o));
  o.max_order = 6;
  CHECK_THROWS_WITH(o.validate(4), Catch::Contains("max_order = 6") && Catch::Contains("1..5"));
}

TEST_CASE("mutation guard: a crossing of -T_s and back within one step is found, the way T_e pulls",
          "[mutation]") {
  // The mirror image (φ -> −φ) of test_simulator.cpp's dof-2 run whose break-away at 2.278 s
  // hides inside one step: wound forwards, turning backwards, u = −0.5 N·m. Here T_e dips
  // below −T_s and comes back inside the step, so the hidden crossing is that of the negative
  // limit, and the break-away must send the bit backwards (its mirror, forwards): each
  // integrator reports which root it found inside the step, and the bit slips that way.
  const Params p = preset("reduced-scale", 2);
  for (const double sign : {1.0, -1.0}) {
    SimulationOptions o;
    o.t_end = 5.0;
    o.n_out = 501;
    o.initial = Initial::State;
    o.state = {0.0, -sign * 300.0, sign * 2.0};
    for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
      o.method = m;
      const Result r = simulate(p, kWob, sign * 0.5, o);
      INFO(method_name(m) << " sign " << sign);
      REQUIRE(r.switches.size() >= 3);
      CHECK(r.switches[1].kind == SwitchKind::Stick);
      CHECK(r.switches[2].kind == SwitchKind::Slip);
      CHECK(r.switches[2].t == Approx(2.278).margin(1e-3));
      CHECK(r.switches[2].direction == static_cast<int>(sign));
      CHECK(r.switches[2].reaction == Approx(sign * p.mu_static * kWob * p.bit_radius).epsilon(1e-6));
    }
  }
}

TEST_CASE("mutation guard: a sampled mean is the trapezoid rule, exact on a straight line",
          "[mutation]") {
  // The judge compares the bit's mean over the window's halves (swing.cpp, sampled_mean): the
  // samples joined by straight lines, integrated. On a velocity that is a straight line
  // v = 3 + 2 t, sampled unevenly, that is exact: the mean over [a, b] is 3 + (a + b), also
  // for ends between samples.
  detail::Trace tr;
  for (double t : {0.0, 0.3, 1.1, 1.2, 2.7, 4.0, 5.5}) {
    tr.t.push_back(t);
    tr.bit.push_back(3.0 + 2.0 * t);
  }
  CHECK(detail::sampled_mean(tr, 0.0, 5.5) == Approx(3.0 + 5.5).epsilon(1e-12));
  CHECK(detail::sampled_mean(tr, 0.7, 4.6) == Approx(3.0 + 0.7 + 4.6).epsilon(1e-12));
}

TEST_CASE("mutation guard: the swing's period is its longest cycle only after four of them",
          "[mutation]") {
  // summary.cpp (mean_moves): the period is the longest of the swing's cycles in the window
  // if it made four or more (five upward crossings of the level), else the string's slowest.
  // Cycles of 2 s, then one of 3 s: counted by hand.
  auto trace = [](const std::vector<double>& ups) {
    detail::Trace tr;
    for (double u : ups) {  // a sample just below the level, then one just above
      tr.t.push_back(u - 0.1);
      tr.bit.push_back(-1.0);
      tr.t.push_back(u + 0.1);
      tr.bit.push_back(1.0);
    }
    return tr;
  };
  const double slowest = 30.0;
  CHECK(detail::longest_cycle(trace({1, 3, 5, 7}), 0.0, 0.0, 20.0, slowest) == slowest);
  CHECK(detail::longest_cycle(trace({1, 3, 5, 7, 10}), 0.0, 0.0, 20.0, slowest) == Approx(3.0));
  // Only crossings inside the window count.
  CHECK(detail::longest_cycle(trace({1, 3, 5, 7, 10}), 0.0, 2.0, 20.0, slowest) == slowest);
}

TEST_CASE("mutation guard: the Karnopp band holds the bit as stick does", "[mutation]") {
  // stick_phases.hpp: the rock holds the bit in stick and, with Karnopp friction, in the band
  // (held while |T_e| <= T_s, creeping through it beyond): a held phase runs from the first
  // of them to the next slip, however often it passes between the two. Counted by hand.
  using M = Mode;
  const std::vector<detail::ModeChange> modes = {{0.0, M::SlipPositive}, {10.0, M::Stick}, {19.0, M::Band},
                                                 {20.0, M::SlipPositive}, {30.0, M::Band}, {30.5, M::Stick},
                                                 {35.0, M::Band}, {36.0, M::SlipNegative}};
  const auto phases = detail::held_phases(modes, 50.0);
  REQUIRE(phases.size() == 2);
  CHECK(phases[0] == std::make_pair(10.0, 20.0));
  CHECK(phases[1] == std::make_pair(30.0, 36.0));
}
