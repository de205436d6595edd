// Edges of the stick/slip switch that no other test reaches (found by the mutation audit of
// session 32): a bit that comes to rest with |T_e| a hair past T_s (Run::falls_back_inside in
// simulator.cpp), and the look inside a step for a switch function that turns back
// (hidden_turn in events.cpp). Each run starts from an explicit state built so that the edge
// is met at once, and its outcome is checked against the physics: DESIGN.md's stick condition
// |T_e| <= T_s, a reference solution of DESIGN.md's dof-2 equations integrated here by a
// fixed-step RK4, and an energy bound on the reaction torque.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pydrill/model.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

namespace {

constexpr double kWob = 100.0;  // N: T_s = μ_sb W_ob R_b = 8 N·m on the reduced-scale string
const Method kMethods[] = {Method::DOP853, Method::BDF, Method::Adams, Method::ERK};

double static_torque(const Params& p) { return p.mu_static * kWob * p.bit_radius; }

// DESIGN.md §2 for dof 2, state (ω_0, θ, ω_b): T_e = k θ + c (ω_0 − ω_b) − c_b ω_b (Eq. 12).
double reaction(const Params& p, const double* y) {
  return p.stiffnesses[0] * y[1] + p.dampings[0] * (y[0] - y[2]) - p.bit_damping * y[2];
}

// The dof-2 equations of motion, written out from DESIGN.md: `slip` = +1 or −1 the bit slips
// with friction slip·f_b(|ω_b|); 0 the rock holds it (ω_b stays 0).
void rhs(const Params& p, double u, int slip, const double* y, double* f) {
  const double spring = p.stiffnesses[0] * y[1] + p.dampings[0] * (y[0] - y[2]);
  f[0] = (u - p.top_damping * y[0] - spring) / p.inertias[0];
  f[1] = y[0] - y[2];
  const double decay = p.stribeck_decay / p.stribeck_velocity;
  const double fb = kWob * p.bit_radius *
                    (p.mu_coulomb + (p.mu_static - p.mu_coulomb) * std::exp(-decay * std::fabs(y[2])));
  f[2] = slip == 0 ? 0.0 : (reaction(p, y) - slip * fb) / p.inertias[1];
}

// Classical RK4 with a fixed step from y0 at t = 0: the states at the times `at` (ascending).
std::vector<std::vector<double>> reference(const Params& p, double u, int slip, std::vector<double> y,
                                           const std::vector<double>& at) {
  const double dt = 1e-5;
  std::vector<std::vector<double>> out;
  double t = 0.0, k1[3], k2[3], k3[3], k4[3], tmp[3];
  for (double target : at) {
    while (t < target - 1e-12) {
      const double h = std::min(dt, target - t);
      rhs(p, u, slip, y.data(), k1);
      for (int i = 0; i < 3; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
      rhs(p, u, slip, tmp, k2);
      for (int i = 0; i < 3; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
      rhs(p, u, slip, tmp, k3);
      for (int i = 0; i < 3; ++i) tmp[i] = y[i] + h * k3[i];
      rhs(p, u, slip, tmp, k4);
      for (int i = 0; i < 3; ++i) y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      t += h;
    }
    out.push_back(y);
  }
  return out;
}

// A bit turning against the reaction torque at 1e-9 rad/s comes to rest ~2e-12 s later, and
// then T_e = k θ + c ω_0 = sign·T_s·(1 + excess) with the top turning at sign·top (so T_e
// moves at about k·top N·m/s outwards for top > 0, inwards for top < 0). sign = −1 is the
// mirror image of sign = +1 (φ → −φ, u → −u).
struct Edge {
  double excess, top, sign;
  std::vector<double> state(const Params& p) const {
    const double theta = (static_torque(p) * (1.0 + excess) - p.dampings[0] * top) / p.stiffnesses[0];
    return {sign * top, sign * theta, -sign * 1e-9};
  }
  // The same moment with the bit exactly at rest (the 2e-12 s before it change T_e by
  // ~1e-13 N·m): where a reference solution starts.
  std::vector<double> at_rest(const Params& p) const {
    auto y = state(p);
    y[2] = 0.0;
    return y;
  }
};

Result run(const Params& p, double u, const Edge& e, Method m, const std::vector<double>& t_out,
           bool tight = true) {
  SimulationOptions o;
  o.method = m;
  o.t_end = t_out.back();
  o.t_out = t_out;
  o.initial = Initial::State;
  // Tight: slipping from rest, the Stribeck instability (ω_b grows like e^{85 t}) amplifies
  // the absolute error allowed on ω_b while it is small; at atol 1e-8 BDF strayed 3e-4 from
  // the reference by t = 0.1 s, at 1e-12 every method stays within 1e-7 of it. A held bit
  // has no such mode: the default tolerances then.
  if (tight) {
    o.rtol = 1e-10;
    o.atol = 1e-12;
  }
  o.state = e.state(p);
  return simulate(p, kWob, e.sign * u, o);
}

// DESIGN.md: the rock holds the bit only while |T_e| <= T_s. Every output in stick obeys it
// (up to the locating noise, 1e-9 of T_s).
void check_stick_condition(const Params& p, const Result& r) {
  const double ts = static_torque(p);
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.modes[i] != static_cast<int>(Mode::Stick)) continue;
    INFO("t = " << r.t[i]);
    CHECK(std::fabs(reaction(p, &r.states[3 * i])) <= ts * (1.0 + 1e-9));
  }
}

// The run follows the reference (bit velocity and top velocity) at every output after t = 0.
void check_follows(const Result& r, const std::vector<std::vector<double>>& ref, double rel) {
  REQUIRE(r.t.size() == ref.size());
  for (std::size_t i = 1; i < r.t.size(); ++i) {
    INFO("t = " << r.t[i]);
    for (int j : {0, 2}) {
      CHECK(r.states[3 * i + j] == Approx(ref[i][j]).epsilon(rel).margin(1e-12));
    }
  }
}

}  // namespace

TEST_CASE("a bit at rest with T_e a hair past T_s and rising breaks away with it", "[simulator][switch-edges]") {
  // T_e passes T_s by 5e-10 of it (inside the locating noise that falls_back_inside weighs)
  // and still rises at 0.073 N·m/s: the stick condition fails from then on, so the bit must
  // slip in the direction of T_e. A reversal into slip; the reference slip keeps ω_b on the
  // side of T_e all along (so that mode is the consistent one) and the run follows it.
  const Params p = preset("reduced-scale", 2);
  const std::vector<double> t_out = {0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3};
  for (double sign : {1.0, -1.0}) {
    const Edge e{5e-10, 1.0, sign};
    const auto ref = reference(p, sign * 8.3, static_cast<int>(sign), e.at_rest(p), t_out);
    for (std::size_t i = 1; i < ref.size(); ++i) REQUIRE(sign * ref[i][2] > 0.0);
    REQUIRE(sign * ref.back()[2] > 1.0);  // well under way, not a flicker
    for (Method m : kMethods) {
      INFO(method_name(m) << ", sign " << sign);
      const Result r = run(p, 8.3, e, m, t_out);
      REQUIRE(!r.switches.empty());
      CHECK(r.switches[0].t < 1e-9);
      CHECK(r.switches[0].kind == SwitchKind::Reversal);
      CHECK(r.switches[0].direction == static_cast<int>(sign));
      check_stick_condition(p, r);
      check_follows(r, ref, 1e-6);
    }
  }
}

TEST_CASE("a bit at rest with T_e a hair past T_s and falling back stays held", "[simulator][switch-edges]") {
  // T_e passes T_s by a0 = 5e-10 of it (4e-9 N·m) and falls at r = 0.073 N·m/s. Slipping on,
  // the bit would gain J_b ω̇_b = a0 − r t + (δ − c − c_b) ω_b with δ = 2.7 N·m·s/rad the
  // Stribeck slope: as r > a0 (δ − c − c_b)/J_b = 3.4e-7 it turns back within 2 a0/r ≈ 1e-7 s,
  // at most a0²/(2 r J_b) ≈ 3e-15 rad/s. So the rock holds it; with the top drive at u = 8.3
  // N·m the clamped top swings T_e down to 7.96 N·m and back to T_s only at 2.71 s. Held over
  // [0, 2] s, the bit does not move, friction does no work, and the top follows the clamped
  // reference.
  const Params p = preset("reduced-scale", 2);
  std::vector<double> t_out;
  for (int i = 0; i <= 20; ++i) t_out.push_back(0.1 * i);
  for (double sign : {1.0, -1.0}) {
    const Edge e{5e-10, -1.0, sign};
    const auto ref = reference(p, sign * 8.3, 0, e.at_rest(p), t_out);
    for (std::size_t i = 1; i < ref.size(); ++i) REQUIRE(std::fabs(reaction(p, ref[i].data())) < static_torque(p));
    for (Method m : kMethods) {
      INFO(method_name(m) << ", sign " << sign);
      Result r;
      REQUIRE_NOTHROW(r = run(p, 8.3, e, m, t_out, false));
      for (std::size_t i = 1; i < r.t.size(); ++i) {
        INFO("t = " << r.t[i]);
        CHECK(r.modes[i] == static_cast<int>(Mode::Stick));
        CHECK(std::fabs(r.states[3 * i + 2]) < 1e-12);
        CHECK(std::fabs(r.friction_loss[i]) < 1e-12);  // J: a held bit takes no friction work
      }
      CHECK(r.switches.back().kind == SwitchKind::Stick);
      CHECK(r.switches.back().t < 1e-6);
      check_stick_condition(p, r);
      check_follows(r, ref, 1e-6);
    }
  }
}

TEST_CASE("a bit at rest with T_e past T_s beyond the locating noise slips even if T_e falls", "[simulator][switch-edges]") {
  // T_e passes T_s by 1e-4 of it (8e-4 N·m, far beyond the noise of locating a switch) while
  // falling at 0.0073 N·m/s. The stick condition fails, so the bit cannot be held; slipping,
  // J_b ω̇_b = a0 − r t + (δ − c − c_b) ω_b grows without turning back since
  // a0 (δ − c − c_b)/J_b = 0.068 > r: the bit breaks away with T_e. The reference slip
  // confirms it (ω_b on T_e's side throughout) and the run must follow it.
  const Params p = preset("reduced-scale", 2);
  const std::vector<double> t_out = {0.0, 0.025, 0.05, 0.1, 0.15, 0.2, 0.25};
  for (double sign : {1.0, -1.0}) {
    const Edge e{1e-4, -0.1, sign};
    const auto ref = reference(p, sign * 8.3, static_cast<int>(sign), e.at_rest(p), t_out);
    for (std::size_t i = 1; i < ref.size(); ++i) REQUIRE(sign * ref[i][2] > 0.0);
    REQUIRE(sign * ref.back()[2] > 1.0);
    for (Method m : kMethods) {
      INFO(method_name(m) << ", sign " << sign);
      const Result r = run(p, 8.3, e, m, t_out);
      REQUIRE(!r.switches.empty());
      CHECK(r.switches[0].kind == SwitchKind::Reversal);
      CHECK(r.switches[0].direction == static_cast<int>(sign));
      check_stick_condition(p, r);
      check_follows(r, ref, 1e-6);
    }
  }
}

TEST_CASE("switch functions are looked at inside a step only where they turn near zero", "[simulator][switch-edges]") {
  // A stuck dof-2 bit with the top spun at 1 rad/s and no surface torque: the top swings on
  // the clamped string with energy E0 = J_r/2 at most, so |k θ| <= sqrt(k J_r) = 0.19 N·m and
  // |T_e| <= 0.195 N·m, never near T_s = 8 N·m: T_e ∓ T_s turn at every swing but each turn
  // stays 7.8 N·m from zero, farther than half its end values (<= 8.2 N·m). No such turn
  // calls for a look at the interpolant, so the switch functions are evaluated only at the
  // (re)start and at each step's end: once there for DOP853, twice for the SUNDIALS
  // integrators (their rootfinder's and the hidden-crossing watch's; measured: exactly that).
  // Light top damping makes ~12 turns in 100 s; a look at each would add as many (a filter
  // that let every turn through left every result of 28 runs bit-identical and cost 5 to
  // 1186 evaluations more: only this count shows it).
  Params p = preset("reduced-scale", 2);
  p.top_damping = 0.002;
  for (Method m : kMethods) {
    INFO(method_name(m));
    SimulationOptions o;
    o.method = m;
    o.t_end = 100.0;
    o.n_out = 2001;
    o.initial = Initial::State;
    o.state = {1.0, 0.0, 0.0};
    const Result r = simulate(p, kWob, 0.0, o);
    REQUIRE(r.switches.empty());
    double temax = 0.0;
    for (std::size_t i = 0; i < r.t.size(); ++i) temax = std::max(temax, std::fabs(reaction(p, &r.states[3 * i])));
    CHECK(std::count(r.modes.begin(), r.modes.end(), static_cast<int>(Mode::Stick)) ==
          static_cast<long>(r.modes.size()));
    CHECK(temax <= std::sqrt(p.stiffnesses[0] * p.inertias[0]) + p.dampings[0] * 1.0);
    CHECK(temax > 0.15);  // it does swing: the bound is nearly reached
    const long per_step = m == Method::DOP853 ? 1 : 2;
    CHECK(r.stats.root_evals <= per_step * r.stats.steps + 1);
  }
}
