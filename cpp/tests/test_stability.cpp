#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "interrupt_poll.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/stability.hpp"

using namespace pydrill;
using complex = std::complex<double>;

TEST_CASE("critical deltas put an eigenvalue pair on the imaginary axis", "[stability]") {
  for (int dof : {2, 4, 9, 30}) {
    const Params p = preset("reduced-scale", dof);
    const auto crossings = critical_deltas(p);
    REQUIRE(!crossings.empty());
    CHECK(std::is_sorted(crossings.begin(), crossings.end(),
                         [](const Crossing& a, const Crossing& b) { return a.delta < b.delta; }));
    for (const auto& c : crossings) {
      const auto ev = eigenvalues(p, c.delta);
      const complex target(0.0, c.frequency);
      double best = 1e300;
      for (const auto& z : ev) best = std::min(best, std::abs(z - target));
      CHECK(best < 1e-8 * std::max(1.0, c.frequency));
      // Unstable count changes by the crossing's size.
      auto count = [&](double d) {
        int n = 0;
        for (const auto& z : eigenvalues(p, d)) n += z.real() > 0;
        return n;
      };
      CHECK(count(c.delta * (1 + 1e-7)) - count(c.delta * (1 - 1e-7)) == c.direction * c.multiplicity);
    }
  }
}

TEST_CASE("no crossing is missed: between crossings the eigenvalues agree with the count",
          "[stability]") {
  // The test above checks that each crossing found is real; this one that none is missing.
  // Brute force: the dense eigenvalues at the midpoint of every gap between crossings (and
  // beyond the last) hold exactly as many in the right half-plane as unstable_count says.
  for (int dof : {2, 4, 9, 30}) {
    const Params p = preset("reduced-scale", dof);
    const auto crossings = critical_deltas(p);
    std::vector<double> probes{0.5 * crossings.front().delta};
    for (std::size_t i = 0; i + 1 < crossings.size(); ++i)
      probes.push_back(0.5 * (crossings[i].delta + crossings[i + 1].delta));
    probes.push_back(2.0 * crossings.back().delta);
    for (double d : probes) {
      int n = 0;
      for (const auto& z : eigenvalues(p, d)) n += z.real() > 0;
      INFO("dof " << dof << ", delta " << d);
      CHECK(n == unstable_count(crossings, d));
    }
  }
}

TEST_CASE("the n' = 3 closed form equals the general method", "[stability]") {
  const Params p = preset("reduced-scale", 2);
  const auto closed = hopf_deltas_dof2(p);
  REQUIRE(closed.size() == 1);
  bool found = false;
  for (const auto& c : critical_deltas(p)) {
    if (c.type == CrossingType::Hopf && std::fabs(c.delta - closed[0]) <= 1e-9 * closed[0]) found = true;
  }
  CHECK(found);
  // Δ_2 of the characteristic polynomial vanishes there.
  const auto a = characteristic_polynomial(p, closed[0]);
  const auto h = hurwitz_determinants(a);
  CHECK(std::fabs(h[1]) < 1e-12 * (std::fabs(a[2] * a[1]) + std::fabs(a[0])));
}

TEST_CASE("boundary W_ob(Omega) inverts the Stribeck slope", "[stability]") {
  const Params p = preset("real-string", 2);
  for (double omega : {0.5, 2.0, 8.0}) {
    const double w = boundary_wob(p, 327.0, omega);
    CHECK(stribeck_slope(p, w, omega) == Approx(327.0).epsilon(1e-14));
  }
}

TEST_CASE("crossings found once serve every operating point of the string", "[stability]") {
  const Params p = preset("reduced-scale", 4);
  const auto crossings = critical_deltas(p);
  int points = 0;
  for (double wob : {40.0, 100.0, 200.0}) {
    for (double factor : {0.7, 0.95, 1.2}) {
      const double torque = factor * p.bit_radius * p.mu_static * wob;
      const auto alone = stability_at_torque(p, wob, torque);
      const auto shared = stability_at_torque(p, crossings, wob, torque);
      REQUIRE(alone.size() == shared.size());
      for (std::size_t k = 0; k < alone.size(); ++k) {
        ++points;
        CHECK(shared[k].omega == alone[k].omega);
        CHECK(shared[k].unstable == alone[k].unstable);
        CHECK(shared[k].delta_margin == alone[k].delta_margin);
        CHECK(shared[k].eigenvalues == alone[k].eigenvalues);
      }
    }
  }
  CHECK(points >= 6);  // steady states exist at most of these points
}

TEST_CASE("crossings that cannot be the string's are refused", "[stability]") {
  // An empty list (what stability_at_torque(p, wob, u, {}) could once mean) counted no
  // unstable eigenvalue anywhere and called every steady state stable.
  const Params p = preset("reduced-scale", 4);
  CHECK_THROWS_WITH(stability_at_torque(p, std::vector<Crossing>{}, 100.0, 8.3),
                    Catch::StartsWith("crossings are not this string's (no fold; its own have one at "
                                      "c_r + c_b = 0.19)"));
  Params other = p;
  other.top_damping = 0.3;
  CHECK_THROWS_WITH(stability_at_torque(p, critical_deltas(other), 100.0, 8.3),
                    Catch::Contains("a fold at delta = 0.31"));
  // Free ends (c_r = c_b = 0): the fold is at δ = 0, and the string's own crossings pass.
  Params undamped = p;
  undamped.top_damping = undamped.bit_damping = 0.0;
  CHECK_NOTHROW(stability_at_torque(undamped, critical_deltas(undamped), 40.0, 3.0));
  CHECK_THROWS_WITH(stability_at_torque(undamped, critical_deltas(p), 40.0, 3.0),
                    Catch::StartsWith("crossings are not this string's (a fold at delta = 0.19; its own have one at "
                                      "c_r + c_b = 0)"));
  std::vector<Crossing> two = critical_deltas(p);
  two.push_back(*std::find_if(two.begin(), two.end(), [](const Crossing& c) { return c.type == CrossingType::Fold; }));
  std::sort(two.begin(), two.end(), [](const Crossing& a, const Crossing& b) { return a.delta < b.delta; });
  CHECK_THROWS_WITH(stability_at_torque(p, two, 100.0, 8.3), Catch::Contains("(2 folds; its own"));
}

namespace {
// The O(n'²) path answers at slope delta, with the dense solver's eigenvalues: every dense one
// has a structured twin within 1e-12 of the largest, the leading one first in both. Returns
// the dense eigenvalues.
std::vector<complex> check_structured_equals_dense(const Params& p, double delta) {
  std::vector<complex> fast;
  REQUIRE(roots_of_impedance(p, delta, fast));
  const auto dense = eigenvalues(p, delta);
  REQUIRE(fast.size() == dense.size());
  double scale = 0.0;
  for (const auto& z : dense) scale = std::max(scale, std::abs(z));
  for (const auto& z : dense) {
    double best = 1e300;
    for (const auto& f : fast) best = std::min(best, std::abs(f - z));
    CHECK(best <= 1e-12 * scale);
  }
  CHECK(std::abs(fast.front() - dense.front()) <= 1e-12 * scale);
  return dense;
}
}  // namespace

TEST_CASE("structured eigenvalues equal the dense solver's on long strings", "[stability]") {
  for (int dof : {30, 80}) {
    const Params p = preset("reduced-scale", dof);
    std::vector<double> deltas = {0.0, 0.002, 0.3, 5.0};
    for (const auto& c : critical_deltas(p)) {
      if (deltas.size() < 8) deltas.push_back(c.delta * 1.001);
    }
    for (double delta : deltas) check_structured_equals_dense(p, delta);
  }
}

TEST_CASE("an overdamped string's eigenvalues come from the structured solver too", "[stability]") {
  // Damping proportional to stiffness, c = beta k, as a tally builds a real string (beta
  // 0.2 s there, and its pipes' modes overdamped by the hundred): the high modes' roots
  // bunch on the real axis near -1/beta.
  for (int dof : {40, 120}) {
    for (double beta : {1.0, 5.0, 20.0}) {
      Params p = preset("reduced-scale", dof);
      for (std::size_t i = 0; i < p.dampings.size(); ++i) p.dampings[i] = beta * p.stiffnesses[i];
      for (double delta : {0.0, 0.01, 1.0}) {
        const auto dense = check_structured_equals_dense(p, delta);
        const auto real = std::count_if(dense.begin(), dense.end(), [](complex z) { return z.imag() == 0.0; });
        CHECK(real > dof);  // overdamped indeed: most of the 2 dof - 1 roots are real
      }
    }
  }
}

TEST_CASE("where the iteration crawls, the dense solver answers", "[stability]") {
  // Every spring damped 60 times past critical, c = 120 sqrt(k J): as c = beta k on this
  // uniform string but for the bit's spring, which puts dozens of roots within 1e-9 of one
  // another near -k/c, away from where the modes start them. The iteration gives up after
  // 60 sweeps (it would need 69).
  Params p = preset("reduced-scale", 40);
  for (std::size_t i = 0; i < p.dampings.size(); ++i) {
    p.dampings[i] = 120.0 * std::sqrt(p.stiffnesses[i] * std::min(p.inertias[i], p.inertias[i + 1]));
  }
  std::vector<complex> unused;
  CHECK_FALSE(roots_of_impedance(p, 0.01, unused));
  CHECK(unused.empty());
  CHECK(structured_eigenvalues(p, 0.01) == eigenvalues(p, 0.01));
}

TEST_CASE("a slope or frequency or coefficient that is not a number is refused by name", "[stability]") {
  // Before, a NaN δ came back as "eigenvalue solver did not converge", a NaN spectrum, or
  // an unstable count of 0 (stable); an infinite frequency as a NaN Lyapunov coefficient.
  const Params p = preset("reduced-scale", 4);
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const auto names_delta = Catch::Contains("delta = nan");
  CHECK_THROWS_WITH(jacobian(p, nan), names_delta);
  CHECK_THROWS_WITH(eigenvalues(p, nan), names_delta);
  CHECK_THROWS_WITH(structured_eigenvalues(p, nan), names_delta);
  std::vector<complex> out;
  CHECK_THROWS_WITH(roots_of_impedance(p, nan, out), names_delta);
  CHECK_THROWS_WITH(characteristic_polynomial(p, nan), names_delta);
  CHECK_THROWS_WITH(boundary_wob(p, nan, 1.0), names_delta);
  CHECK_THROWS_WITH(unstable_count(critical_deltas(p), nan), names_delta);
  CHECK_THROWS_WITH(first_lyapunov_coefficient(p, nan, 1.0), names_delta);
  CHECK_THROWS_WITH(jacobian(p, inf), Catch::Contains("delta = inf"));
  CHECK_THROWS_WITH(first_lyapunov_coefficient(p, 0.01, inf), Catch::Contains("frequency = inf"));
  CHECK_THROWS_WITH(first_lyapunov_coefficient(p, 0.01, 0.0), Catch::Contains("frequency = 0"));
  CHECK_THROWS_WITH(stribeck_slope(p, 100.0, -5.0), Catch::Contains("omega = -5"));
  CHECK_THROWS_WITH(boundary_wob(p, 0.01, -1.0), Catch::Contains("omega = -1"));
  // Numbers in messages are the shortest that read back, as everywhere else (std::to_string
  // wrote "omega = -0.000000", the streams six digits).
  CHECK_THROWS_WITH(equilibrium_torque(p, 100.0, -1e-9), Catch::StartsWith("omega = -1e-09 is not allowed"));
  CHECK_THROWS_WITH(stribeck_slope(p, 100.0, -0.1234567891), Catch::StartsWith("omega = -0.1234567891 is not"));
  CHECK_THROWS_WITH(first_lyapunov_coefficient(p, 0.01, -1.0000001), Catch::StartsWith("frequency = -1.0000001 is"));
  CHECK_THROWS_WITH(hurwitz_determinants({1.0, 2.0, -1.0000001}), Catch::Contains("ascending[2] = -1.0000001 is"));
  // δ <= 0 has no weight on bit: it came back as W_ob = -91.1 N or 0 N.
  CHECK_THROWS_AS(boundary_wob(p, -1.0, 1.0), std::invalid_argument);
  CHECK_THROWS_WITH(boundary_wob(p, -1.0, 1.0), Catch::StartsWith("delta = -1 is not allowed: must be > 0"));
  CHECK_THROWS_WITH(boundary_wob(p, 0.0, 1.0), Catch::StartsWith("delta = 0 is not allowed"));
  CHECK_THROWS_WITH(boundary_wob(p, -0.0, 1.0), Catch::Contains("must be > 0 N·m·s/rad"));
  CHECK_THROWS_WITH(bit_impedance(p, complex(nan, 1.0)), Catch::Contains("lambda"));
  CHECK_THROWS_WITH(hurwitz_determinants({1.0, nan, 1.0}), Catch::Contains("ascending[1] = nan"));
  CHECK_THROWS_WITH(hurwitz_determinants({1.0, 2.0, -1.0}), Catch::Contains("ascending[2] = -1"));
  // The edges that are allowed still answer: δ = 0 (no Stribeck effect) and Ω = 0.
  CHECK(unstable_count(critical_deltas(p), 0.0) == 0);
  CHECK(stribeck_slope(p, 100.0, 0.0) == Approx(100.0 * 0.1 * 0.9 * 0.3));
  CHECK(boundary_wob(p, stribeck_slope(p, 100.0, 2.0), 2.0) == Approx(100.0));
}

TEST_CASE("the O(dof²) analyses ask their interrupt and stop when it says so", "[stability]") {
  // 2000 pipes: critical_deltas and the roots of Z_b = δ take over half a second each here.
  const Params p = preset("reduced-scale", 2003);
  using clock = std::chrono::steady_clock;
  auto seconds_since = [](clock::time_point t0) {
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  int asked = 0;
  const std::function<bool()> no = [&asked] {
    ++asked;
    return false;
  };
  const std::function<bool()> yes = [&asked] {
    ++asked;
    return true;
  };
  auto t0 = clock::now();
  const auto crossings = critical_deltas(p, no);
  double seconds = seconds_since(t0);
  INFO("critical_deltas took " << seconds << " s, asked " << asked << " times");
  REQUIRE(seconds > 0.25);
  CHECK(asked >= 1);
  CHECK(asked <= static_cast<int>(seconds / 0.1) + 1);  // about every 0.1 s, not every step
  const auto plain = critical_deltas(p);
  REQUIRE(crossings.size() == plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) CHECK(crossings[i].delta == plain[i].delta);
  // Saying yes at the first question stops it there, long before it would end.
  asked = 0;
  t0 = clock::now();
  CHECK_THROWS_AS(critical_deltas(p, yes), StabilityInterrupted);
  CHECK(asked == 1);
  CHECK(seconds_since(t0) < 0.5 * seconds);
  // One type catches it and a stopped run's Interrupted alike (a cancel button's handler).
  CHECK_THROWS_AS(critical_deltas(p, yes), Cancelled);
  CHECK_THROWS_WITH(critical_deltas(p, yes), "interrupted");

  // The structured eigenvalues alike, and the stability of a steady state through both.
  const double delta = crossings.front().delta;
  asked = 0;
  t0 = clock::now();
  std::vector<complex> roots;
  REQUIRE(roots_of_impedance(p, delta, roots, no));
  seconds = seconds_since(t0);
  INFO("roots_of_impedance took " << seconds << " s, asked " << asked << " times");
  REQUIRE(seconds > 0.25);
  CHECK(asked >= 1);
  CHECK(asked <= static_cast<int>(seconds / 0.1) + 1);
  asked = 0;
  t0 = clock::now();
  std::vector<complex> untouched;
  CHECK_THROWS_AS(roots_of_impedance(p, delta, untouched, yes), StabilityInterrupted);
  CHECK(untouched.empty());
  CHECK_THROWS_AS(structured_eigenvalues(p, delta, yes), StabilityInterrupted);
  CHECK(asked == 2);
  CHECK(seconds_since(t0) < seconds);
  asked = 0;
  CHECK_THROWS_AS(stability_at_velocity(p, 100.0, 5.0, yes), StabilityInterrupted);
  CHECK_THROWS_AS(stability_at_torque(p, 100.0, 8.3, yes), StabilityInterrupted);
  CHECK_THROWS_AS(stability_at_torque(p, crossings, 100.0, 8.3, yes), StabilityInterrupted);
  CHECK(asked == 3);
  // Short computations end before the first question, and an empty callback is never asked.
  asked = 0;
  const Params short_string = preset("reduced-scale", 13);
  CHECK(critical_deltas(short_string, yes).size() == critical_deltas(short_string).size());
  CHECK(stability_at_torque(short_string, 100.0, 8.3, yes).size() ==
        stability_at_torque(short_string, 100.0, 8.3).size());
  CHECK(asked == 0);
  CHECK(critical_deltas(short_string, std::function<bool()>{}).size() ==
        critical_deltas(short_string).size());
}

TEST_CASE("the tridiagonal eigenvalues that can be interrupted are Eigen's, bit for bit", "[stability]") {
  // Eigen's solver is one uninterrupted O(n²) piece (1.5 s at 6000 inertias); ours runs its
  // loop and QR step with a poll between steps, and must change no crossing and no root.
  const std::function<bool()> no = [] { return false; };
  detail::InterruptPoll poll(no);
  auto same_as_eigen = [&](const Eigen::VectorXd& diag, const Eigen::VectorXd& sub) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
    es.computeFromTridiagonal(diag, sub, Eigen::EigenvaluesOnly);
    REQUIRE(es.info() == Eigen::Success);
    CHECK(detail::tridiagonal_eigenvalues(diag, sub, poll) == es.eigenvalues());
  };
  for (int dof : {2, 3, 13, 303, 2003}) {
    // The free chain's mass-normalised stiffness, and without its last row (a clamped bit).
    const Params p = preset("reduced-scale", dof);
    Eigen::VectorXd diag(dof), sub(dof - 1);
    for (int i = 0; i < dof; ++i) {
      diag(i) = ((i > 0 ? p.stiffnesses[i - 1] : 0.0) + (i < dof - 1 ? p.stiffnesses[i] : 0.0)) / p.inertias[i];
      if (i + 1 < dof) sub(i) = -p.stiffnesses[i] / std::sqrt(p.inertias[i] * p.inertias[i + 1]);
    }
    INFO("dof " << dof);
    same_as_eigen(diag, sub);
    same_as_eigen(diag.head(dof - 1), sub.head(dof - 2));
  }
  // Blocks that split apart (zeros below the diagonal), a repeated eigenvalue, one row.
  Eigen::VectorXd diag(7), sub(6);
  diag << 4.0, -1.0, 2.5, 2.5, 0.0, 3.0, 1e-3;
  sub << 1.0, 0.0, 0.5, 1e-300, 2.0, 0.0;
  same_as_eigen(diag, sub);
  same_as_eigen(Eigen::VectorXd::Constant(1, 2.0), Eigen::VectorXd(0));
}
