// Guards found by a mutation audit of the core (session 32): each test fails on a small change
// to the code that decides results (a flipped comparison, a dropped term, an off-by-one) that
// no other test noticed, and checks against something independent of that code: a brute-force
// scan, eigenvalues, a hand count of a synthetic run, a symmetry or a documented rule.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <vector>

#include "pydrill/equilibrium.hpp"
#include "pydrill/friction.hpp"
#include "pydrill/model.hpp"
#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"
#include "stick_phases.hpp"
#include "summary.hpp"

using namespace pydrill;

namespace {

// Steady states of (W_ob, u) by brute force: sign changes of g(Ω) − u on a fine geometric grid of
// Ω > 0 (g(Ω) = (c_r + c_b) Ω + f_b(Ω), written out here from DESIGN.md §3).
int scanned_steady_states(const Params& p, double wob, double u) {
  const double scale = wob * p.bit_radius, decay = p.stribeck_decay / p.stribeck_velocity;
  auto g = [&](double w) {
    return (p.top_damping + p.bit_damping) * w +
           scale * (p.mu_coulomb + (p.mu_static - p.mu_coulomb) * std::exp(-decay * w));
  };
  int roots = 0;
  double prev = g(1e-9) - u;
  for (double w = 1e-9; w < 1e6; w *= 1.001) {
    const double now = g(w) - u;
    if ((now > 0) != (prev > 0)) ++roots;
    prev = now;
  }
  return roots;
}

int right_half_plane(const Params& p, double delta) {
  int n = 0;
  for (const auto& z : eigenvalues(p, delta)) n += z.real() > 0;
  return n;
}

// A synthetic run for the regime judge: samples of ω_b (top turning steadily at `top`) and the
// modes at their switch times, over the window [t0, t1] with the bit's angle advancing `advance`.
struct Synthetic {
  detail::Trace trace;
  std::vector<detail::ModeChange> modes;
  detail::WindowAngles angles{};
};

Synthetic synthetic(std::vector<detail::ModeChange> modes, double t0, double t1, double top,
                    double advance, double sign = 1.0) {
  Synthetic s;
  s.modes = std::move(modes);
  for (int i = 0; i <= 1000; ++i) {
    const double t = t0 + (t1 - t0) * i / 1000.0;
    Mode m = s.modes.front().mode;
    for (const auto& c : s.modes) {
      if (c.t <= t) m = c.mode;
    }
    const bool held = m == Mode::Stick;
    s.trace.t.push_back(t);
    s.trace.bit.push_back(held ? 0.0 : sign * 3.0 * top * std::fabs(std::sin(0.3 * t)));
    s.trace.top.push_back(sign * top);
  }
  s.angles = {t0, t1, sign * top * t0, sign * top * t1, 0.0, sign * advance};
  return s;
}

}  // namespace

TEST_CASE("mutation guard: no steady rotation at Omega = 0 when u equals T_s exactly", "[mutation]") {
  // g(0+) = T_s, so u = T_s balances the friction only at Ω → 0, which is stick, not rotation.
  // Three shapes of g: falling then rising (the preset), rising from T_s (heavy damping), and
  // falling for ever (no damping at the ends).
  for (const double cr : {0.18, 10.0, 0.0}) {
    Params p = preset("reduced-scale", 4);
    p.top_damping = cr;
    if (cr == 0.0) p.bit_damping = 0.0;
    const double wob = 100.0, ts = BitFriction(p, wob).static_torque();
    const auto omegas = equilibrium_velocities(p, wob, ts);
    INFO("c_r = " << cr);
    CHECK(static_cast<int>(omegas.size()) == scanned_steady_states(p, wob, ts));
    for (double w : omegas) {
      CHECK(w > 1e-6);
      CHECK(equilibrium_torque(p, wob, w) == Approx(ts).epsilon(1e-12));
    }
  }
}

TEST_CASE("mutation guard: the window's stuck fraction, stick events and period, counted by hand",
          "[mutation]") {
  const Chain chain(preset("reduced-scale", 4), 100.0, 8.3);
  // Window [100, 200]: held 90–110 (10 s of it inside), 130–140, 175–185; onsets at 130 and 175
  // inside it (the one at 90 is before it).
  const auto s = synthetic({{0.0, Mode::SlipPositive},
                            {90.0, Mode::Stick},
                            {110.0, Mode::SlipPositive},
                            {130.0, Mode::Stick},
                            {140.0, Mode::SlipPositive},
                            {175.0, Mode::Stick},
                            {185.0, Mode::SlipPositive}},
                           100.0, 200.0, 5.0, 400.0);
  const Summary r = detail::summarize(chain, s.trace, s.modes, s.angles, false);
  CHECK(r.regime == Regime::StickSlip);
  CHECK(r.stuck_fraction == Approx(0.3).epsilon(1e-12));
  CHECK(r.stick_events == 2);
  CHECK(r.period == Approx(45.0).epsilon(1e-12));
  CHECK(r.bit_mean == Approx(4.0));
}

TEST_CASE("mutation guard: the judge is mirror-symmetric in the torque's sign", "[mutation]") {
  // u < 0 is the mirror image (φ → −φ) of u > 0: the bit's fastest turn is then its minimum.
  const Chain fwd(preset("reduced-scale", 4), 100.0, 8.3), back(preset("reduced-scale", 4), 100.0, -8.3);
  const std::vector<detail::ModeChange> m{{0.0, Mode::SlipPositive}, {130.0, Mode::Stick}, {140.0, Mode::SlipPositive},
                                          {175.0, Mode::Stick}, {185.0, Mode::SlipPositive}};
  std::vector<detail::ModeChange> mirrored = m;
  for (auto& c : mirrored) c.mode = c.mode == Mode::SlipPositive ? Mode::SlipNegative : c.mode;
  const auto a = synthetic(m, 100.0, 200.0, 5.0, 400.0), b = synthetic(mirrored, 100.0, 200.0, 5.0, 400.0, -1.0);
  const Summary ra = detail::summarize(fwd, a.trace, a.modes, a.angles, false);
  const Summary rb = detail::summarize(back, b.trace, b.modes, b.angles, false);
  CHECK(ra.bit_top_ratio > 1.0);
  CHECK(rb.bit_top_ratio == Approx(ra.bit_top_ratio));
  CHECK(rb.bit_mean == Approx(-ra.bit_mean));
  CHECK(rb.severity == Approx(ra.severity));
}

TEST_CASE("mutation guard: simulated runs at u and -u are mirror images", "[mutation]") {
  // The paper's stick-slip case (dof 4, W_ob 100 N, 8.3 N·m) and its mirror, with both friction
  // laws: the slip- friction, the negative break-away and the band's exits all take part.
  for (const FrictionLaw law : {FrictionLaw::Exact, FrictionLaw::Karnopp}) {
    SimulationOptions o;
    o.t_end = 150.0;
    o.n_out = 301;
    o.friction = law;
    const Result f = simulate(preset("reduced-scale", 4), 100.0, 8.3, o);
    const Result b = simulate(preset("reduced-scale", 4), 100.0, -8.3, o);
    REQUIRE(f.summary.regime == Regime::StickSlip);
    CHECK(b.summary.regime == f.summary.regime);
    CHECK(b.switches.size() == f.switches.size());
    CHECK(b.summary.stick_events == f.summary.stick_events);
    CHECK(b.summary.bit_mean == Approx(-f.summary.bit_mean).epsilon(1e-6));
    CHECK(b.summary.bit_min == Approx(-f.summary.bit_max).epsilon(1e-6));
    CHECK(b.summary.bit_top_ratio == Approx(f.summary.bit_top_ratio).epsilon(1e-6));
    CHECK(b.summary.period == Approx(f.summary.period).epsilon(1e-6));
  }
}

TEST_CASE("mutation guard: two stick onsets in the window are stick-slip, not a late stick", "[mutation]") {
  // |u| = 8.3 <= T_s = 12.8 at W_ob 160 N. Stuck 10–20 and again from 90 to the window's end
  // (10 s, not over kCycleEnded times the 10 s before): a repeated stick and slip.
  const Chain chain(preset("reduced-scale", 4), 160.0, 8.3);
  const auto s = synthetic({{0.0, Mode::SlipPositive}, {10.0, Mode::Stick}, {20.0, Mode::SlipPositive}, {90.0, Mode::Stick}},
                           0.0, 100.0, 5.0, 300.0);
  const Summary r = detail::summarize(chain, s.trace, s.modes, s.angles, false);
  CHECK(r.regime == Regime::StickSlip);
  CHECK(r.stick_events == 2);
  CHECK(r.caveat != "late-stick");
}

TEST_CASE("mutation guard: cycle_end weighs only the window's phases, by kCycleEnded", "[mutation]") {
  using detail::CycleEnd;
  using M = detail::ModeChange;
  // A 50 s stick that ended before the window opened (t0 = 55) does not count: the 5 s one
  // inside it does, and the last stick (20 s since 70) outlasts it over twice.
  const std::vector<M> stuck{{0.0, Mode::Stick}, {50.0, Mode::SlipPositive}, {60.0, Mode::Stick},
                             {65.0, Mode::SlipPositive}, {70.0, Mode::Stick}};
  const CycleEnd a = detail::cycle_end(stuck, 55.0, 90.0);
  CHECK(a.kind == CycleEnd::Kind::Stuck);
  CHECK(a.longest == 5.0);
  CHECK(a.since == 70.0);
  // Free: slipping since 22 after a slip of 8 s between sticks. 12 s later it is not yet over
  // twice that (None); 17 s later it is (Free).
  const std::vector<M> free{{0.0, Mode::SlipPositive}, {10.0, Mode::Stick}, {12.0, Mode::SlipPositive},
                            {20.0, Mode::Stick}, {22.0, Mode::SlipPositive}};
  CHECK(detail::cycle_end(free, 0.0, 34.0).kind == CycleEnd::Kind::None);
  CHECK(detail::cycle_end(free, 0.0, 34.0).longest == 8.0);
  CHECK(detail::cycle_end(free, 0.0, 39.0).kind == CycleEnd::Kind::Free);
}

TEST_CASE("mutation guard: delta_margin's sign is the stability, its size the nearest crossing",
          "[mutation]") {
  const Params p = preset("reduced-scale", 4);
  const auto crossings = critical_deltas(p);
  int stable = 0, unstable = 0;
  for (const double wob : {40.0, 100.0}) {
    for (const double omega : {0.5, 2.0, 5.0, 20.0}) {
      const StabilityPoint s = stability_at_velocity(p, wob, omega);
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& c : crossings) nearest = std::min(nearest, std::fabs(c.delta - s.delta));
      const bool rhp = right_half_plane(p, s.delta) > 0;  // brute-force eigenvalues
      (rhp ? unstable : stable) += 1;
      CHECK(s.stable == !rhp);
      CHECK(s.delta_margin == Approx(rhp ? -nearest : nearest));
    }
  }
  CHECK(stable > 0);
  CHECK(unstable > 0);
}

TEST_CASE("mutation guard: a negative torque's steady states carry that torque", "[mutation]") {
  const Params p = preset("reduced-scale", 4);
  const auto fwd = stability_at_torque(p, 100.0, 7.0), back = stability_at_torque(p, 100.0, -7.0);
  REQUIRE(fwd.size() == 2);
  REQUIRE(back.size() == fwd.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    CHECK(back[i].torque == Approx(-7.0).epsilon(1e-9));
    CHECK(back[i].omega < 0);
    CHECK(back[i].omega == Approx(-fwd[fwd.size() - 1 - i].omega));
  }
}

TEST_CASE("mutation guard: unstable_count agrees with eigenvalues when the fold restabilises",
          "[mutation]") {
  // With c_r² > k (J_r + J_b) the impedance falls at 0 (Z_b'(0) = J_r + J_b − c_r²/k for dof 2):
  // the real eigenvalue crosses back to the left at the fold, direction −1.
  Params p = preset("reduced-scale", 2);
  p.top_damping = 0.3;
  const auto crossings = critical_deltas(p);
  const double fold = p.top_damping + p.bit_damping;
  for (const auto& c : crossings) {
    if (c.type == CrossingType::Fold) CHECK(c.direction == -1);
  }
  for (const double d : {0.005, 0.1, 0.3, 0.5 * (0.3 + fold), 0.32, 1.0, 5.0}) {
    INFO("delta = " << d);
    CHECK(unstable_count(crossings, d) == right_half_plane(p, d));
  }
}

TEST_CASE("mutation guard: the dof-2 closed form gives the Hopf points of H+ that the phase search finds",
          "[mutation]") {
  // Eq. (51) keeps the points with a_1 > 0 and a_0 > 0 (the paper's H+), i.e. below the fold
  // δ = c_r + c_b. On this string the phase search finds two Hopf points, both above the fold:
  // the closed form has none.
  std::vector<Params> strings{preset("reduced-scale", 2), preset("real-string", 2)};
  Params q = preset("reduced-scale", 2);
  q.inertias = {1.9357097937073138, 0.010146544398270231};
  q.stiffnesses = {0.21685107636708736};
  q.dampings = {0.07694140798003772};
  q.top_damping = 0.006319282554652413;
  q.bit_damping = 0.6851916891429525;
  strings.push_back(q);
  for (const Params& p : strings) {
    std::vector<double> below;
    for (const auto& c : critical_deltas(p)) {
      if (c.type == CrossingType::Hopf && c.delta < p.top_damping + p.bit_damping) below.push_back(c.delta);
    }
    const auto closed = hopf_deltas_dof2(p);
    REQUIRE(closed.size() == below.size());
    for (std::size_t i = 0; i < closed.size(); ++i) CHECK(closed[i] == Approx(below[i]).epsilon(1e-7));
  }
}

TEST_CASE("mutation guard: the decay-rate and load limits sit where documented", "[mutation]") {
  // A decay rate (c_r + c_0) / I_0 of exactly 1e15 /s is allowed, twice it refused.
  Params p = preset("reduced-scale", 2);
  p.dampings = {0.0};
  p.top_damping = 1e15 * p.inertias[0];
  REQUIRE(p.top_damping / p.inertias[0] <= 1e15);
  CHECK_NOTHROW(p.validate());
  p.top_damping *= 2.0;
  CHECK_THROWS_AS(p.validate(), std::invalid_argument);
  // A simulation takes W_ob up to 1e15 N, not beyond.
  SimulationOptions o;
  o.t_end = 1.0;
  CHECK_THROWS_AS(simulate(preset("reduced-scale", 4), 2e15, 8.3, o), std::invalid_argument);
}

TEST_CASE("mutation guard: the chattering guard trips on 50 switches within 50 / max_switch_rate",
          "[mutation]") {
  // The documented rule (simulator.hpp): a run fails when a switch comes within less than
  // 50 / max_switch_rate s of the switch 50 before it. The tightest such span of a free run
  // sets the rate that just trips it, and one just above that does not.
  SimulationOptions o;
  o.t_end = 600.0;
  o.n_out = 11;
  const Params p = preset("reduced-scale", 4);
  const Result free_run = simulate(p, 100.0, 8.3, o);
  const auto& sw = free_run.switches;
  REQUIRE(sw.size() > 60);
  double tightest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 50; i < sw.size(); ++i) tightest = std::min(tightest, sw[i].t - sw[i - 50].t);
  o.max_switch_rate = 0.95 * 50.0 / tightest;
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o), Catch::Contains("chattering: 50 friction switches"));
  o.max_switch_rate = 1.05 * 50.0 / tightest;
  CHECK_NOTHROW(simulate(p, 100.0, 8.3, o));
}

TEST_CASE("mutation guard: karnopp_band must be a finite number > 0", "[mutation]") {
  for (const double bad : {0.0, -1e-6, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Params p = preset("reduced-scale", 4);
    p.karnopp_band = bad;
    CHECK_THROWS_WITH(p.validate(), Catch::Contains("karnopp_band"));
  }
}

TEST_CASE("mutation guard: a still bit with T_e exactly T_s starts held by the rock", "[mutation]") {
  // DESIGN.md §2: the bit sticks while |T_e| <= T_s. With k = 1 and θ = T_s, T_e = T_s exactly;
  // with no torque at the top the twist relaxes, T_e falls, and the bit never moves.
  Params p = preset("reduced-scale", 2);
  p.stiffnesses = {1.0};
  const double wob = 100.0, ts = BitFriction(p, wob).static_torque();
  SimulationOptions o;
  o.t_end = 1.0;
  o.n_out = 11;
  o.initial = Initial::State;
  o.state = {0.0, ts, 0.0};
  const Chain chain(p, wob, 0.0);
  REQUIRE(chain.reaction_torque(o.state.data()) == ts);
  const Result r = simulate(p, wob, 0.0, o);
  CHECK(r.modes.front() == static_cast<int>(Mode::Stick));
  CHECK(r.switches.empty());
}
