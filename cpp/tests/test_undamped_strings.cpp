// Strings with damping missing at the ends or altogether. Their crossings sit at δ = 0, where
// the search along the impedance's phase cannot see them: an undamped string came back with
// none and was called stable at every δ, and a string with c_r = c_b = 0 lost its fold. The
// references here share nothing with critical_deltas: the free chain's modes in closed form,
// the dense eigenvalues (LAPACK-free Eigen QR), and the limit of a vanishing top damping.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

using namespace pydrill;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A uniform chain of n inertias J and springs k, with the given element dampings.
Params uniform(int n, std::vector<double> dampings, double top = 0.0, double bit = 0.0) {
  Params p = preset("reduced-scale", n);
  p.inertias.assign(static_cast<std::size_t>(n), 0.4);
  p.stiffnesses.assign(static_cast<std::size_t>(n - 1), 2.5);
  p.dampings = std::move(dampings);
  p.top_damping = top;
  p.bit_damping = bit;
  return p;
}

// Eigenvalues in the open right half-plane, from the dense solver. Only asked where every
// real part is far from 0 against the spectrum's size (no crossing nearby).
int dense_unstable(const Params& p, double delta) {
  int n = 0;
  for (const auto& z : eigenvalues(p, delta)) n += z.real() > 0;
  return n;
}

// Every probe between and beyond the crossings' distinct δ, as in test_stability.cpp.
void counts_agree(const Params& p, const std::vector<Crossing>& crossings) {
  std::vector<double> at;
  for (const Crossing& c : crossings)
    if (at.empty() || c.delta > at.back() * (1 + 1e-9)) at.push_back(c.delta);
  std::vector<double> probes;
  for (std::size_t i = 0; i + 1 < at.size(); ++i) probes.push_back(0.5 * (at[i] + at[i + 1]));
  probes.push_back(at.back() > 0 ? 2.0 * at.back() : 1e-3);
  for (double d : probes) {
    INFO("delta " << d);
    CHECK(dense_unstable(p, d) == unstable_count(crossings, d));
  }
}

}  // namespace

TEST_CASE("an undamped string: the fold and every Hopf point at delta = 0, all destabilising",
          "[stability][undamped]") {
  for (int n : {2, 3, 6, 25}) {
    INFO("dof " << n);
    const Params p = uniform(n, std::vector<double>(static_cast<std::size_t>(n - 1), 0.0));
    const auto crossings = critical_deltas(p);
    REQUIRE(crossings.size() == static_cast<std::size_t>(n));
    CHECK(crossings[0].type == CrossingType::Fold);
    int total = 0;
    for (std::size_t j = 0; j < crossings.size(); ++j) {
      const Crossing& c = crossings[j];
      CHECK(c.delta == 0.0);
      CHECK(c.direction == 1);
      total += c.multiplicity;
      if (j == 0) continue;
      // The free uniform chain's modes: ω_j = 2 √(k/J) sin(jπ / 2n).
      CHECK(c.type == CrossingType::Hopf);
      CHECK(c.frequency == Approx(2.0 * std::sqrt(2.5 / 0.4) * std::sin(j * kPi / (2.0 * n))).epsilon(1e-12));
      CHECK(first_lyapunov_coefficient(p, c.delta, c.frequency) == 0.0);  // flat friction at δ = 0
    }
    CHECK(total == 2 * n - 1);  // every eigenvalue
    // Any slope, however small or large, leaves all of them in the right half-plane: none comes
    // back, as Z_b(iω) = iX(ω) is never a real δ > 0.
    for (double d : {1e-6, 1e-2, 1.0, 30.0}) {
      INFO("delta " << d);
      CHECK(unstable_count(crossings, d) == 2 * n - 1);
      CHECK(dense_unstable(p, d) == 2 * n - 1);
    }
    CHECK(unstable_count(crossings, 0.0) == 0);  // at δ = 0 itself they are on the axis
  }
}

TEST_CASE("an undamped string's crossings are the limit of a vanishing top damping", "[stability][undamped]") {
  // With c_r = d > 0 the search along the phase applies: the fold and the Hopf points sit at
  // δ = d (to first order) with the same frequencies, and the restabilising crossings run off
  // to δ ∝ 1/d. Both searches, each on its own path, must meet in the limit. (At d = 1e-9 the
  // search along the phase dropped three of the six Hopf points: its test that Im Z_b is 0
  // there asked 1e-6 of |Z_b| ≈ 1e-9, below what one ulp of ω moves it.)
  const int n = 7;
  const Params p = uniform(n, std::vector<double>(n - 1, 0.0));
  const auto at_zero = critical_deltas(p);
  const Params q = uniform(n, std::vector<double>(n - 1, 0.0), 1e-9);
  std::vector<Crossing> first;
  for (const Crossing& c : critical_deltas(q))
    if (c.direction > 0) first.push_back(c);
  REQUIRE(first.size() == at_zero.size());
  // All at δ ≈ d, in no particular order there: by frequency (the fold's is 0).
  auto by_frequency = [](const Crossing& a, const Crossing& b) { return a.frequency < b.frequency; };
  std::sort(first.begin(), first.end(), by_frequency);
  for (std::size_t j = 0; j < first.size(); ++j) {
    CHECK(first[j].delta == Approx(1e-9).epsilon(1e-3));
    CHECK(first[j].frequency == Approx(at_zero[j].frequency).epsilon(1e-6));
  }
  for (const Crossing& c : critical_deltas(q))
    if (c.direction < 0) CHECK(c.delta > 1e3);
}

TEST_CASE("a string without damping at its ends has its fold at delta = 0", "[stability][undamped]") {
  // c_r = c_b = 0 with damped elements: the string turns freely as one body, and any slope
  // δ > 0 sets that motion accelerating. The fold was left out (it was pushed only for
  // c_r + c_b > 0), and every count above 0 was one short.
  const Params p = uniform(5, {0.01, 0.01, 0.01, 0.01});
  const auto crossings = critical_deltas(p);
  REQUIRE(!crossings.empty());
  CHECK(crossings[0].type == CrossingType::Fold);
  CHECK(crossings[0].delta == 0.0);
  CHECK(crossings[0].direction == 1);
  for (std::size_t j = 1; j < crossings.size(); ++j) CHECK(crossings[j].delta > 0);
  CHECK(unstable_count(crossings, 1e-9) == 1);
  counts_agree(p, crossings);
  // The steady states see it too: one eigenvalue in Re > 0 even at a slope far below every Hopf point.
  const StabilityPoint s = stability_at_velocity(p, 0.5, 1.0);  // δ ≈ 0.0055
  CHECK(s.delta < crossings[1].delta);
  CHECK_FALSE(s.stable);
  CHECK(s.unstable == 1);
  CHECK(s.unstable == dense_unstable(p, s.delta));
}

TEST_CASE("a mode that strains no damper stays undamped: its Hopf point is at delta = 0", "[stability][undamped]") {
  // A symmetric chain of six with one damper in the middle spring: the modes symmetric about
  // the middle (j = 2, 4 of the free chain) do not twist that spring, so no damping acts on
  // them, while j = 1, 3, 5 are damped. The search along the phase missed the two undamped
  // ones (their impedance is 0 there, with no phase to follow), and counted two pairs short.
  const Params p = uniform(6, {0.0, 0.0, 0.05, 0.0, 0.0});
  const auto crossings = critical_deltas(p);
  std::vector<double> at_zero;
  for (const Crossing& c : crossings)
    if (c.type == CrossingType::Hopf && c.delta == 0.0) at_zero.push_back(c.frequency);
  REQUIRE(at_zero.size() == 2);
  for (int k = 0; k < 2; ++k)
    CHECK(at_zero[k] == Approx(2.0 * std::sqrt(2.5 / 0.4) * std::sin((2 * k + 2) * kPi / 12.0)).epsilon(1e-12));
  for (const Crossing& c : crossings)
    if (c.delta == 0.0) CHECK(c.direction == 1);
  counts_agree(p, crossings);
  // Moved to the top spring, the damper strains every mode (x_0 − x_1 = cos(jπ/12) −
  // cos(3jπ/12) ≠ 0 for j = 1 ... 5): no Hopf point at 0, only the fold.
  const Params off = uniform(6, {0.05, 0.0, 0.0, 0.0, 0.0});
  const auto moved = critical_deltas(off);
  int zeros = 0;
  for (const Crossing& c : moved) zeros += c.delta == 0.0;
  CHECK(zeros == 1);
  counts_agree(off, moved);
}

TEST_CASE("a top held nearly still by its damping keeps the Hopf points of the held string", "[stability]") {
  // Found by comparing with the dense eigenvalues on random strings: c_r = 320 N·m·s/rad on
  // inertias of 0.098 kg·m² (2000 times the top's critical damping) moves the zeros of Im Z_b
  // to those of the string held at the top, and two of them, at 2.88 and 2.93 rad/s, fell in
  // one interval of the frequency grid seeded with the free top's modes: a Hopf point and its
  // return were lost, and the count was 6 where the eigenvalues say 8.
  Params p = uniform(5, {3.2781211513934589e-4, 3.2781211513934589e-4, 3.2781211513934589e-4, 3.7855152492586302e-6});
  p.inertias.assign(5, 0.098343634541803754);
  p.stiffnesses.assign(4, 0.23930284405172247);
  p.top_damping = 320.09029380700611;
  p.bit_damping = 1e-14;
  const auto crossings = critical_deltas(p);
  int hopf = 0;
  for (const Crossing& c : crossings) hopf += c.type == CrossingType::Hopf;
  CHECK(hopf == 7);  // four destabilising, three back
  CHECK(unstable_count(crossings, 0.032781211513934587) == 8);
  counts_agree(p, crossings);
}

namespace {

// The string's angular momentum L = Σ J_i ω_i at each output time (twist coordinates: the
// velocities sit at the even places of a state).
std::vector<double> angular_momentum(const Params& p, const Result& r) {
  const std::size_t width = 2 * p.inertias.size() - 1;
  std::vector<double> L;
  for (std::size_t k = 0; k < r.t.size(); ++k) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.inertias.size(); ++i) sum += p.inertias[i] * r.states[k * width + 2 * i];
    L.push_back(sum);
  }
  return L;
}

}  // namespace

TEST_CASE("no damping at the ends and |u| above the Coulomb torque: the bit runs away",
          "[summary][undamped]") {
  // With c_r = c_b = 0 nothing grows with speed to balance u: dL/dt = u − T_fb(ω_b), and the
  // slip friction falls to T_c = μ_cb R_b W_ob = 2.5 N m at W_ob = 50 N (T_s = 4). Once fast,
  // the string gains momentum at the rate u − T_c: a rigid-body balance the summary does not
  // use, against which its "run-away" is checked. It once called u = 3.25 "steady".
  Params p = preset("reduced-scale", 4);
  p.top_damping = p.bit_damping = 0.0;
  SimulationOptions o;
  o.t_end = 300.0;
  o.n_out = 301;
  for (double u : {3.25, 4.4, -4.4}) {
    INFO("u " << u);
    const Result r = simulate(p, 50.0, u, o);
    const auto L = angular_momentum(p, r);
    const double rate = (L.back() - L[150]) / (r.t.back() - r.t[150]);
    const double expected = u - std::copysign(2.5, u);
    CHECK(std::fabs(rate - expected) < 0.01 * std::fabs(expected));
    CHECK(r.summary.regime == Regime::Oscillation);
    CHECK(r.summary.caveat == "run-away");
    CHECK_THAT(r.summary.note, Catch::Contains("speeds up without bound"));
    CHECK(std::fabs(r.summary.bit_mean) > 200.0);
  }
  // Below T_c the friction wins: the bit sticks for good, no run-away.
  const Result slow = simulate(p, 50.0, 2.4, o);
  CHECK(slow.summary.regime == Regime::Stuck);
  CHECK(slow.summary.caveat.empty());
  // A damping at the bit bounds the speed (steady at (u − T_c)/c_b = 15 rad/s).
  p.bit_damping = 0.05;
  const Result held = simulate(p, 50.0, 3.25, o);
  CHECK(held.summary.regime == Regime::Steady);
  CHECK(held.summary.caveat.empty());
  CHECK(std::fabs(held.summary.bit_mean - 15.0) < 1e-3);
}

TEST_CASE("a bit damped only by a trace of c_b is steady on its way: caveat approaching",
          "[summary][undamped]") {
  // c_b = 1e-3 alone holds the bit at Ω = (u − T_c)/c_b = 750 rad/s (the friction's excess over
  // T_c is e^-750 there), a stable steady state reached at the rate c_b/ΣJ: the mean closes its
  // distance to 750 by the factor e^(−c_b·75 s/ΣJ) between the window's half-centres, 75 s
  // apart. Judged steady without a word at 238 rad/s once.
  Params p = preset("reduced-scale", 4);
  p.top_damping = 0.0;
  p.bit_damping = 1e-3;
  double total = 0.0;
  for (double J : p.inertias) total += J;
  SimulationOptions o;
  o.t_end = 300.0;
  const Result r = simulate(p, 50.0, 3.25, o);
  CHECK(r.summary.regime == Regime::Steady);
  CHECK(r.summary.caveat == "approaching");
  CHECK_THAT(r.summary.note, Catch::Contains("on its way to the steady state at 750 rad/s"));
  // The half-window means the note gives, against the exponential approach.
  const Result first = [&] {
    SimulationOptions half = o;
    half.t_end = 225.0;
    half.window_fraction = 75.0 / 225.0;
    return simulate(p, 50.0, 3.25, half);
  }();
  const double before = first.summary.bit_mean;  // the mean over [150, 225]
  const double after = 2.0 * r.summary.bit_mean - before;  // over [225, 300]
  CHECK((750.0 - after) / (750.0 - before) ==
        Approx(std::exp(-p.bit_damping * 75.0 / total)).epsilon(0.01));
  // Settled: no caveat.
  o.t_end = 30000.0;
  const Result settled = simulate(p, 50.0, 3.25, o);
  CHECK(settled.summary.regime == Regime::Steady);
  CHECK(settled.summary.caveat.empty());
  CHECK(settled.summary.bit_mean == Approx(750.0).epsilon(1e-6));
}
