// What simulate refuses before anything runs: bad options, enums outside their type,
// tolerances beyond what a double resolves or the regimes allow, absurd presets, and runs that
// cannot fit in max_steps.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "pydrill/equilibrium.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

TEST_CASE("bad options are refused before anything runs", "[simulator]") {
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = -1;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("t_end"));
  o.t_end = 10;
  o.initial = Initial::State;
  o.state = {1.0};
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("2*dof-1 = 7"));
  o.state.clear();  // only Initial::State takes one
  o.initial = Initial::Equilibrium;
  CHECK_THROWS_WITH(simulate(p, 160.0, 8.3, o), Catch::Contains("no steady rotation"));
  // Loads so large that the run overflowed at t = 0 ("step size fell to 0"): named instead.
  o.initial = Initial::Rest;
  CHECK_THROWS_WITH(simulate(p, 100.0, 1e300, o), Catch::Contains("torque = 1e+300") && Catch::Contains("1e15"));
  CHECK_THROWS_WITH(simulate(p, 2e15, 8.3, o), Catch::Contains("wob = 2e+15"));
  CHECK(simulate(p, 100.0, -1e15, o).summary.regime != Regime::Stuck);
  o.initial = Initial::Equilibrium;
  // CVODES takes BDF up to order 5 and Adams up to 12; it used to refuse order 8 for BDF
  // itself, as a runtime_error, after the run had started.
  o.initial = Initial::Rest;
  o.method = Method::BDF;
  o.max_order = 8;
  CHECK_THROWS_AS(simulate(p, 100.0, 8.3, o), std::invalid_argument);
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("max_order = 8") && Catch::Contains("1..5"));
  o.method = Method::DOP853;  // a fixed order: the option would be ignored
  o.max_order = 3;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("max_order = 3") && Catch::Contains("dop853"));
  o.method = Method::Auto;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("max_order = 3"));
  o.method = Method::Adams;
  o.max_order = 8;
  o.t_end = 5.0;
  CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
}

TEST_CASE("an enum value outside its type is refused", "[simulator]") {
  // static_cast<Method>(42) ran, and reported stats.method == "?".
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 1.0;
  o.method = static_cast<Method>(42);
  CHECK_THROWS_AS(simulate(p, 100.0, 8.3, o), std::invalid_argument);
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::StartsWith("method = 42 is not a pydrill::Method"));
  o.method = Method::Auto;
  o.friction = static_cast<FrictionLaw>(-1);
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::StartsWith("friction = -1 is not"));
  o.friction = FrictionLaw::Exact;
  o.initial = static_cast<Initial>(7);
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::StartsWith("initial = 7 is not"));
}

TEST_CASE("tolerances finer than a double resolves are refused", "[simulator]") {
  // They were taken, and then CVODES stopped with "h = nan", ARKODE at "t = nan", DOP853
  // with "not smooth" (rtol = atol = 1e-300), or DOP853 claimed success (rtol 1e-17).
  const Params p = preset("reduced-scale", 4);
  for (Method m : {Method::Auto, Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    SimulationOptions o;
    o.method = m;
    o.t_end = 1.0;
    for (double rtol : {1e-300, 1e-17, 2e-16, 9.9e-15, 0.0, 1.0, std::nan("")}) {
      INFO("rtol " << rtol);
      o.rtol = rtol;
      CHECK_THROWS_AS(simulate(p, 100.0, 8.3, o), std::invalid_argument);
    }
    o.rtol = 1e-17;
    CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                      Catch::StartsWith("rtol = 1e-17 is not allowed") && Catch::Contains("1e-14 <= rtol <= 0.01"));
    o.rtol = 1e-8;
    for (double atol : {1e-300, 1e-30, 9.9e-21, 0.0, -1.0, HUGE_VAL}) {
      INFO("atol " << atol);
      o.atol = atol;
      CHECK_THROWS_AS(simulate(p, 100.0, 8.3, o), std::invalid_argument);
    }
    o.atol = 1e-300;
    CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                      Catch::StartsWith("atol = 1e-300 is not allowed") && Catch::Contains("1e-20 <= atol <= 0.001"));
  }
}

TEST_CASE("a preset of an absurd size is refused before it is allocated", "[params]") {
  CHECK_THROWS_WITH(preset("reduced-scale", 1'000'000'000), Catch::Contains("at most 100000"));
  CHECK(preset("reduced-scale", 100'000).dof() == 100'000);
}

TEST_CASE("a run that cannot fit in max_steps is refused before it starts, and only then",
          "[simulator][methods]") {
  // stiffnesses[0] = 1e6 on the paper's dof-4 string: inertia 1 rings at 6325 rad/s. Measured
  // before: at 1e12, DOP853 took max_steps = 2e6 to reach t = 0.54 s of 60.
  Params p = preset("reduced-scale", 4);
  p.stiffnesses[0] = 1e6;
  const double w = std::sqrt((p.stiffnesses[0] + p.stiffnesses[1]) / p.inertias[1]);
  SimulationOptions o;
  o.n_out = 11;
  const std::pair<Method, double> radii[] = {{Method::DOP853, 6.8}, {Method::ERK, 5.01}, {Method::Adams, 3.65}};
  for (const auto& [m, radius] : radii) {
    INFO("method " << method_name(m));
    o.method = m;
    // The bound is a lower bound: a run takes more steps than it.
    o.t_end = 10.0;
    o.max_steps = 50'000'000;
    const Result r = simulate(p, 100.0, 8.3, o);
    CHECK(static_cast<double>(r.stats.steps) >= o.t_end * w / radius);
    // A run that would grind (2.8e5 .. 5.2e5 steps at least, over 1e6 state updates), one
    // step short of it: refused at once, with what to change.
    o.t_end = 300.0;
    const double bound = o.t_end * w / radius;
    o.max_steps = static_cast<long>(std::floor(bound)) - 1;
    try {
      simulate(p, 100.0, 8.3, o);
      FAIL("refused before integrating");
    } catch (const SolverError& e) {
      CHECK(e.t_reached() == 0.0);
      CHECK_THAT(e.what(), Catch::StartsWith("max_steps = " + std::to_string(o.max_steps) +
                                             " internal steps cannot take method '" + method_name(m) +
                                             "' to t_end = 300 s (refused before integrating)") &&
                               Catch::Contains("the string's fastest mode, at inertias[1] (frequency >= 6.32e+03 rad/s)") &&
                               Catch::Contains("needs at least " + std::to_string(o.max_steps + 2) + " steps") &&
                               Catch::EndsWith("; raise max_steps or shorten t_end"));
    }
    // At the bound, it is tried: it reaches max_steps on the way (it needs more).
    o.max_steps = static_cast<long>(std::ceil(bound));
    try {
      simulate(p, 100.0, 8.3, o);
      FAIL("the run needs more steps than the bound");
    } catch (const SolverError& e) {
      CHECK(e.t_reached() > 0.0);
      CHECK_THAT(e.what(), Catch::Contains("internal steps reached"));
    }
    // A small max_steps fails fast by itself, and says how far it got.
    o.max_steps = 100;
    try {
      simulate(p, 100.0, 8.3, o);
      FAIL("100 steps are too few");
    } catch (const SolverError& e) {
      CHECK(e.t_reached() > 0.0);
    }
  }
  // BDF is not held to the bound: it may step over fast modes that have died.
  o.method = Method::BDF;
  o.t_end = 10.0;
  o.max_steps = 1'000'000;
  CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
  // max_step bounds every method: t_end / max_step steps at least.
  o.max_step = 1e-5;
  o.max_steps = 999'999;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                    Catch::StartsWith("max_steps = 999999 internal steps cannot reach t_end = 10 s in steps of at "
                                      "most max_step = 1e-05 s (refused before integrating): it needs at least "
                                      "1000000; raise max_steps or shorten t_end"));
}

TEST_CASE("tolerances looser than the regimes allow are refused", "[simulator]") {
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 2.0;
  o.n_out = 5;
  for (Method m : {Method::Auto, Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    o.method = m;
    for (double rtol : {0.0101, 0.5, 0.999, HUGE_VAL}) {
      INFO("rtol " << rtol);
      o.rtol = rtol;
      CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("is not allowed: need 1e-14 <= rtol <= 0.01"));
    }
    o.rtol = 1e-2;
    CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
    for (double atol : {0.0011, 1.0, 1e300, HUGE_VAL, std::nan("")}) {
      INFO("atol " << atol);
      o.atol = atol;
      CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("is not allowed: need 1e-20 <= atol <= 0.001"));
    }
    o.atol = 1e-3;
    CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
    o.rtol = o.atol = 1e-8;
  }
}

TEST_CASE("output times a run cannot tell from 0 are refused", "[simulator]") {
  // A run flushes subnormal numbers to 0: t_end = 5e-324 s was judged "steady" from rest
  // with every output time 0, and t_out = {0, 1e-320, 1} came back as times {0, 0, 1}.
  const Params p = preset("reduced-scale", 2);
  SimulationOptions o;
  o.t_end = 5e-324;
  o.n_out = 2;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::StartsWith("t_end = 4.94066e-324 is not allowed with n_out = 2: its output times would be"));
  o.t_end = 1e-305;  // normal, but 3001 times 3.3e-309 s apart
  o.n_out = 3001;
  CHECK_THROWS_WITH(o.validate(2), Catch::Contains("below the smallest normal float"));
  o.n_out = 2;
  CHECK_NOTHROW(o.validate(2));
  const Result r = simulate(p, 100.0, 8.3, o);  // the smallest run allowed still moves on
  CHECK(r.t.back() == 1e-305);
  CHECK(r.t.front() == 0.0);
  o.t_end = 1.0;
  o.t_out = {0.0, 1e-320, 1.0};
  CHECK_THROWS_WITH(o.validate(2), Catch::StartsWith("t_out[1] = 9.99989e-321 is not allowed: an output time is 0 or at least 2.23e-308 s"));
  o.t_out = {0.0, 1e-300, 1.0};
  CHECK_NOTHROW(o.validate(2));
  o.t_end = 1e-310;
  o.t_out = {0.0};
  CHECK_THROWS_WITH(o.validate(2), Catch::StartsWith("t_end = 1e-310 is not allowed: below the smallest normal float"));
}

TEST_CASE("a max_step a run cannot tell from 0 is refused by name", "[simulator]") {
  // A run flushes subnormals to 0: max_step = 1e-320 s reached each integrator as a zero
  // step bound, and the run failed with a SolverError about NaN step sizes (CVODES "h = nan",
  // ARKODE "the state or its error estimate overflowed") that named neither max_step nor why.
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 10.0;
  o.max_steps = 100'000;  // small enough not to be refused as a grind first
  for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    o.method = m;
    o.max_step = 1e-320;
    CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                      Catch::StartsWith("max_step = 9.99989e-321 is not allowed: 0 (no limit) or at least 2.23e-308 s"));
    o.max_step = std::numeric_limits<double>::denorm_min();
    CHECK_THROWS_AS(o.validate(4), std::invalid_argument);
  }
  // The smallest normal bound is a bound (the run grinds into max_steps, as any tiny step
  // would), and 0 is still "no limit".
  o.method = Method::DOP853;
  o.max_step = std::numeric_limits<double>::min();
  CHECK_NOTHROW(o.validate(4));
  o.max_step = 0.0;
  CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
}

TEST_CASE("a state that the run would ignore is refused", "[simulator]") {
  // options.state was read only with Initial::State: a program that filled it and left
  // initial at its default (Rest) ran from rest with no word, as a max_order on an explicit
  // method would (refused above). The independent judge: a run from the state given differs
  // from the run from rest.
  const Params p = preset("reduced-scale", 2);
  SimulationOptions o;
  o.t_end = 20.0;
  o.n_out = 21;
  o.state = {5.0, 0.0, 5.0};  // turning at 5 rad/s, untwisted
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                    Catch::StartsWith("state has 3 entries but initial = 'rest' does not use it: set initial = Initial::State"));
  o.initial = Initial::Equilibrium;
  CHECK_THROWS_WITH(o.validate(2), Catch::Contains("initial = 'equilibrium' does not use it"));
  o.initial = Initial::State;
  const Result from_state = simulate(p, 100.0, 8.3, o);
  CHECK(from_state.states[0] == 5.0);
  o.initial = Initial::Rest;
  o.state.clear();
  const Result from_rest = simulate(p, 100.0, 8.3, o);
  CHECK(from_rest.states[0] == 0.0);
  CHECK(from_rest.states != from_state.states);
}

TEST_CASE("a window_fraction whose window rounds to nothing is refused", "[simulator]") {
  // The run judges [t_end·(1 − window_fraction), t_end]: at 1e-17 that is [300, 300] s, and
  // the empty window was judged "steady" with a mean bit velocity of 0 beside a min and max of
  // 18.3 rad/s (the mean is the angle advance over the window's length, 0 / 0).
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 300.0;
  o.window_fraction = 1e-17;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                    Catch::StartsWith("window_fraction = 1e-17 is not allowed with t_end = 300 s: the judged window") &&
                        Catch::Contains("need window_fraction >= 1.2e-16"));
  // The smallest fraction the message names opens a window at every t_end (2^-53 <= 1.2e-16).
  o.window_fraction = 1.2e-16;
  for (double t_end : {1.0, 300.0, 256.0, 1e10, 3e-300}) {
    o.t_end = t_end;
    CHECK_NOTHROW(o.validate(4));
    CHECK(t_end * (1.0 - o.window_fraction) < t_end);
  }
}
