// simulate's runs: the paper's regimes, the energy ledger, friction switches, the methods'
// agreement, failures, interrupts. Refused options are in test_simulation_options.cpp, the long
// strings (300 inertias, a stiff tally string) in test_long_strings.cpp.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "pydrill/equilibrium.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

namespace {
Result run(double wob, double torque, double t_end, FrictionLaw friction = FrictionLaw::Exact,
           int dof = 4) {
  SimulationOptions o;
  o.t_end = t_end;
  o.friction = friction;
  return simulate(preset("reduced-scale", dof), wob, torque, o);
}
}  // namespace

TEST_CASE("paper regimes, reduced-scale dof 4, u = 8.3 N m, from rest", "[simulator]") {
  SECTION("W_ob = 100 N sticks and slips (Fig. 4)") {
    const Result r = run(100.0, 8.3, 300.0);
    CHECK(r.summary.regime == Regime::StickSlip);
    CHECK(r.summary.stick_events >= 5);
    CHECK(r.summary.period > 0);
  }
  SECTION("W_ob = 160 N stays stuck (Fig. 7)") {
    const Result r = run(160.0, 8.3, 300.0);
    CHECK(r.summary.regime == Regime::Stuck);
    CHECK(r.summary.stuck_fraction == 1.0);
    CHECK(r.switches.empty());
  }
  SECTION("W_ob = 40 N drills steadily at the analytic Omega (Fig. 9)") {
    const Result r = run(40.0, 8.3, 1000.0);
    CHECK(r.summary.regime == Regime::Steady);
    const double omega = equilibrium_velocities(preset("reduced-scale", 4), 40.0, 8.3).back();
    const double wb = r.states.back();
    CHECK(std::fabs(wb - omega) / omega < 1e-6);
  }
}

TEST_CASE("energy balance over a stick-slip run", "[simulator][energy]") {
  const Result r = run(100.0, 8.3, 300.0);
  const double work = r.work_input.back();
  const double out = r.viscous_loss.back() + r.friction_loss.back() + r.energy.back() - r.energy.front();
  CHECK(std::fabs(work - out) / work < 1e-6);
}

TEST_CASE("the ledger balances from a start in motion, where E(0) is not zero", "[simulator][energy]") {
  // The header said the ledger was "all zero at t = 0"; E(0) of a steady start is 445 J.
  SimulationOptions o;
  o.t_end = 50.0;
  o.initial = Initial::Equilibrium;
  for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    o.method = m;
    const Result r = simulate(preset("reduced-scale", 4), 40.0, 8.3, o);
    CHECK(r.stats.method == m);
    CHECK(r.work_input.front() == 0.0);
    CHECK(r.viscous_loss.front() == 0.0);
    CHECK(r.friction_loss.front() == 0.0);
    CHECK(r.energy.front() == Approx(445.2).epsilon(1e-3));
    const double lhs = r.work_input.back() - r.viscous_loss.back() - r.friction_loss.back();
    CHECK(lhs == Approx(r.energy.back() - r.energy.front()).epsilon(1e-6));
  }
}

TEST_CASE("stick holds the bit exactly and switches sit on their roots", "[simulator]") {
  const Result r = run(100.0, 8.3, 300.0);
  const int n = 2 * r.dof - 1;
  const Params p = preset("reduced-scale", 4);
  const double ts = r.summary.static_torque;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.modes[i] != static_cast<int>(Mode::Stick)) continue;
    const double* y = &r.states[i * n];
    CHECK(y[n - 1] == 0.0);
    const double te = p.stiffnesses.back() * y[n - 2] + p.dampings.back() * y[n - 3];
    CHECK(std::fabs(te) <= ts * (1 + 1e-9));
  }
  REQUIRE(r.switches.size() >= 10);
  for (const auto& s : r.switches) {
    CHECK(std::fabs(s.root_residual) < 1e-8 * std::max(1.0, ts));
  }
}

TEST_CASE("exact and Karnopp friction agree on regime and period", "[simulator][karnopp]") {
  const Result exact = run(100.0, 8.3, 300.0);
  const Result karnopp = run(100.0, 8.3, 300.0, FrictionLaw::Karnopp);
  CHECK(karnopp.summary.regime == exact.summary.regime);
  CHECK(karnopp.summary.period == Approx(exact.summary.period).epsilon(0.01));
}

TEST_CASE("BDF with the chain solver, Adams, ERK and DOP853 give one answer", "[simulator][methods]") {
  SimulationOptions o;
  o.t_end = 60.0;
  o.n_out = 61;
  o.method = Method::Adams;
  const Params p = preset("reduced-scale", 6);
  const Result adams = simulate(p, 100.0, 8.3, o);
  for (Method m : {Method::BDF, Method::ERK, Method::DOP853}) {
    o.method = m;
    const Result r = simulate(p, 100.0, 8.3, o);
    CHECK(r.stats.method == m);
    if (m == Method::BDF) CHECK(r.stats.jac_evals > 0);
    REQUIRE(r.states.size() == adams.states.size());
    REQUIRE(r.switches.size() == adams.switches.size());
    // All at rtol 1e-8; switch times carry the local error forward, so compare on the
    // scale of the solution (measured: BDF 7e-6, Adams 4e-7 from an rtol 1e-12 reference).
    double scale = 0.0, diff = 0.0;
    for (std::size_t i = 0; i < r.states.size(); ++i) {
      scale = std::max(scale, std::fabs(adams.states[i]));
      diff = std::max(diff, std::fabs(r.states[i] - adams.states[i]));
    }
    CHECK(diff < 1e-4 * scale);
    for (std::size_t i = 0; i < r.switches.size(); ++i) {
      CHECK(r.switches[i].kind == adams.switches[i].kind);
      CHECK(r.switches[i].t == Approx(adams.switches[i].t).margin(1e-4));
    }
  }
}

TEST_CASE("a root function that crosses zero and back within one step is found", "[simulator][methods]") {
  // dof 2 wound backwards and turning forward: the bit reverses, then sticks at 1.99 s; T_e
  // then climbs past T_s = 8 N·m at 2.278 s and falls back below it inside one of DOP853's
  // long steps. Seen at step ends only, that break-away was missed and the bit stayed stuck
  // with T_e = 8.19 N·m. Every method must see it, and no stick may exceed T_s.
  SimulationOptions o;
  o.t_end = 50.0;
  o.n_out = 5001;
  o.initial = Initial::State;
  o.state = {0.0, -300.0, 2.0};
  const Params p = preset("reduced-scale", 2);
  for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    o.method = m;
    const Result r = simulate(p, 100.0, 0.5, o);
    INFO(method_name(m));
    REQUIRE(r.switches.size() >= 3);
    CHECK(r.switches[0].kind == SwitchKind::Reversal);
    CHECK(r.switches[1].kind == SwitchKind::Stick);
    CHECK(r.switches[2].kind == SwitchKind::Slip);
    CHECK(r.switches[2].t == Approx(2.278).margin(1e-3));
    const double ts = p.mu_static * 100.0 * p.bit_radius;  // T_s = μ_sb W_ob R_b
    for (const Switch& w : r.switches) {
      if (w.kind == SwitchKind::Stick) CHECK(std::fabs(w.reaction) <= ts);
    }
  }
}

TEST_CASE("a slip that starts on a graze of T_s never runs the bit backwards", "[simulator][methods]") {
  // Collars 7000x stiffer than the pipe ring fast: T_e often touches T_s and turns back, so a
  // slip begins with the bit at rest and its velocity root on zero. Every integrator must
  // arm that root (the bit re-sticks at once) rather than follow the bit backwards in slip+,
  // where the analytically continued friction grows without bound.
  Params p = preset("reduced-scale", 4);
  p.stiffnesses = {0.073, 500.0, 500.0};
  for (Method m : {Method::DOP853, Method::ERK, Method::Adams, Method::BDF}) {
    SimulationOptions o;
    o.t_end = 60.0;
    o.n_out = 12001;
    o.method = m;
    const Result r = simulate(p, 100.0, 8.3, o);
    CHECK(r.summary.regime == Regime::StickSlip);
    CHECK(r.switches.size() > 100);
    const int n = 2 * r.dof - 1;
    double lowest = 0.0;
    for (std::size_t i = 0; i < r.t.size(); ++i) {
      if (r.modes[i] == static_cast<int>(Mode::SlipPositive)) lowest = std::min(lowest, r.states[i * n + n - 1]);
    }
    INFO("method " << method_name(m));
    CHECK(lowest > -1e-9);
  }
}

TEST_CASE("every method runs at the tolerance floors", "[simulator][methods]") {
  // The paper's dof-4 case: each method works down to rtol 2.3e-16 (CVODES and ARKODE
  // give up at 1e-16); the floor 1e-14 keeps a margin.
  const Params p = preset("reduced-scale", 4);
  for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    SimulationOptions o;
    o.method = m;
    o.t_end = 50.0;
    o.rtol = kMinRtol;
    o.atol = kMinRtol;
    const Result r = simulate(p, 100.0, 8.3, o);
    CHECK(r.summary.regime == Regime::StickSlip);
    // A steady start with atol at its floor: DOP853's first step, weighted by the
    // quadratures that start at 0, fell below its floor (real string, atol 1e-18).
    o.rtol = 1e-8;
    o.atol = kMinAtol;
    o.t_end = 10.0;
    o.initial = Initial::Equilibrium;
    CHECK_NOTHROW(simulate(preset("real-string", 2), 1e5, 1e4, o));
    CHECK_NOTHROW(simulate(p, 40.0, 8.3, o));
  }
}

TEST_CASE("a solver failure reports the last time reached, never NaN", "[simulator][methods]") {
  // ω_0 = 1e150 overflows the energy ledger: ARKODE's step went to NaN, and the error said
  // "ARKODE failed at t = nan s" with t_reached() = NaN.
  const Params p = preset("reduced-scale", 4);
  for (Method m : {Method::DOP853, Method::BDF, Method::Adams, Method::ERK}) {
    INFO("method " << method_name(m));
    SimulationOptions o;
    o.method = m;
    o.t_end = 10.0;
    o.initial = Initial::State;
    o.state.assign(7, 0.0);
    o.state[0] = 1e150;
    try {
      simulate(p, 100.0, 8.3, o);
      FAIL("an overflowing state cannot be integrated");
    } catch (const SolverError& e) {
      INFO(e.what());
      CHECK(std::isfinite(e.t_reached()));
      CHECK(std::string(e.what()).find("t = nan") == std::string::npos);
    }
  }
}

TEST_CASE("DOP853's shortest step does not depend on how long the run is", "[simulator]") {
  // The floor used to be 1e-14 of t_end: at t_end = 1e10 s a step of 1e-4 s, which the
  // first stick of the bit needs to go below, so the run stopped at t = 0 with "step size
  // fell". Now a long run goes as far as max_steps lets it, and says so.
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.method = Method::DOP853;
  o.t_end = 1e10;
  o.max_steps = 20000;
  o.t_out = {0.0, 1e10};
  try {
    simulate(p, 100.0, 8.3, o);
    FAIL("20000 steps cannot reach t = 1e10 s in stick-slip");
  } catch (const SolverError& e) {
    CHECK(std::string(e.what()).find("max_steps = 20000") != std::string::npos);
    CHECK(e.t_reached() > 100.0);  // well past the first stick-slip cycles
  }
  // A run shorter than the floor is a single short step, not a failure.
  o.t_end = 1e-20;
  o.t_out.clear();
  o.max_steps = 50'000'000;
  const Result r = simulate(p, 100.0, 8.3, o);
  CHECK(r.t.back() == 1e-20);
  CHECK(r.stats.steps >= 1);
}

TEST_CASE("a run asks options.interrupt and stops when it says so", "[simulator]") {
  // 300 pipes sticking and slipping for 20000 s: over half a second here, several polls.
  const Params p = preset("reduced-scale", 303);
  SimulationOptions o;
  o.t_end = 20000.0;
  o.n_out = 11;
  int asked = 0;
  o.interrupt = [&asked] {
    ++asked;
    return false;
  };
  const auto t0 = std::chrono::steady_clock::now();
  const Result whole = simulate(p, 100.0, 8.3, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO("run took " << seconds << " s, asked " << asked << " times");
  REQUIRE(seconds > 0.25);
  CHECK(asked >= 1);
  CHECK(asked <= static_cast<int>(seconds / 0.1) + 1);  // about every 0.1 s, not every step
  // Saying yes at the first question stops the run there, well before t_end.
  o.interrupt = [] { return true; };
  try {
    simulate(p, 100.0, 8.3, o);
    FAIL("the run was not interrupted");
  } catch (const Interrupted& e) {
    CHECK(e.t_reached() > 0.0);
    CHECK(e.t_reached() < 0.9 * o.t_end);
  }
  CHECK(whole.summary.regime == simulate(p, 100.0, 8.3, [&] {
          SimulationOptions plain = o;
          plain.interrupt = nullptr;
          return plain;
        }()).summary.regime);
}

TEST_CASE("an extreme static friction ends: the bit stays stuck", "[simulator][equilibrium]") {
  // μ_s = 1e308 overflowed δ(0) = W R (μ_s − μ_c) γ/v_f to inf: equilibrium_velocities took the
  // string for an undamped one and doubled its search bound to inf for ever (found by fuzzing;
  // every method hung in the run's summary).
  Params p = preset("reduced-scale", 4);
  p.mu_static = 1e308;
  p.top_damping = 0.0;
  // Below T_s = 5e306 N·m the falling branch crosses u = 8.3 where the friction has decayed
  // to the Coulomb level: two steady states, each balancing the torque.
  for (double w : equilibrium_velocities(p, 0.5, 8.3)) {
    CHECK(equilibrium_torque(p, 0.5, w) == Approx(8.3).epsilon(1e-9));
  }
  SimulationOptions o;
  o.t_end = 1.0;
  o.method = Method::DOP853;
  CHECK(simulate(p, 0.5, 8.3, o).summary.regime == Regime::Stuck);  // from rest: held
  // Far above the Coulomb level too.
  const auto roots = equilibrium_velocities(p, 0.5, 1e300);
  CHECK(roots.size() == 2);
  for (double w : roots) CHECK(equilibrium_torque(p, 0.5, w) == Approx(1e300).epsilon(1e-9));
}

TEST_CASE("DOP853 at a loose tolerance does not run away at a break-away", "[simulator][methods]") {
  // The step of a bit held for seconds carried over to its break-away, where the Stribeck
  // instability ran away inside it and the error test, scaled by the new state, accepted it:
  // 8 of 147 runs (dof 2 ... 50, W_ob 60 ... 130 N, rtol 1e-2 ... 1e-6) had a bit velocity of
  // 7e5 ... 1e12 rad/s. Against a run at rtol 1e-10 (itself checked against the paper).
  const struct {
    int dof;
    double rtol;
  } cases[] = {{2, 1e-2}, {2, 3e-3}, {3, 1e-2}, {3, 3e-3}, {4, 1e-3}, {6, 3e-4}, {10, 3e-4}, {10, 1e-4}};
  for (const auto& c : cases) {
    INFO("dof " << c.dof << ", rtol " << c.rtol);
    const Params p = preset("reduced-scale", c.dof);
    SimulationOptions o;
    o.method = Method::DOP853;
    o.rtol = o.atol = 1e-10;
    const Summary ref = simulate(p, 100.0, 8.3, o).summary;
    o.rtol = c.rtol;
    o.atol = 1e-8;
    const Summary s = simulate(p, 100.0, 8.3, o).summary;
    CHECK(s.regime == ref.regime);
    CHECK(s.bit_max < 1.1 * ref.bit_max);
    CHECK(s.bit_min >= ref.bit_min - 0.1 * ref.bit_max);
  }
}
