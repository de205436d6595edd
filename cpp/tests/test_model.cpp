#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "chain_solver.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/model.hpp"

using namespace pydrill;

namespace {
std::vector<double> random_state(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<double> y(n);
  for (auto& v : y) v = u(gen);
  return y;
}
}  // namespace

TEST_CASE("banded Jacobian equals central finite differences of the RHS", "[model]") {
  for (int dof : {2, 3, 7}) {
    const Params p = preset("reduced-scale", dof);
    const Chain chain(p, 100.0, 8.3);
    const int n = chain.size();
    auto y = random_state(n, 11u + dof);
    for (Mode mode : {Mode::SlipPositive, Mode::SlipNegative, Mode::Stick, Mode::Band}) {
      if (mode == Mode::SlipPositive) y[chain.bit_index()] = 0.7;
      if (mode == Mode::SlipNegative) y[chain.bit_index()] = -0.7;
      if (mode == Mode::Stick) y[chain.bit_index()] = 0.0;
      if (mode == Mode::Band) y[chain.bit_index()] = 3e-7;
      std::vector<double> band(5 * n), fp(n), fm(n);
      chain.jacobian_band(y.data(), mode, band.data());
      for (int c = 0; c < n; ++c) {
        if (mode == Mode::Stick && c == chain.bit_index()) continue;  // ω_b is held at 0
        const double h = 1e-6 * std::max(1.0, std::fabs(y[c]));
        auto yp = y, ym = y;
        yp[c] += h;
        ym[c] -= h;
        if (mode == Mode::Band) {  // stay inside the band
          if (c == chain.bit_index()) continue;
        }
        chain.rhs(yp.data(), mode, fp.data());
        chain.rhs(ym.data(), mode, fm.data());
        for (int r = 0; r < n; ++r) {
          const double fd = (fp[r] - fm[r]) / (2 * h);
          const double an = std::abs(c - r) <= 2 ? band[5 * r + (c - r + 2)] : 0.0;
          INFO("dof " << dof << " mode " << mode_name(mode) << " J(" << r << "," << c << ")");
          CHECK(an == Approx(fd).margin(1e-7).epsilon(1e-6));
        }
      }
    }
  }
}

TEST_CASE("band LU solve of I - gamma J matches a dense solve", "[model]") {
  const Params p = preset("reduced-scale", 9);
  const Chain chain(p, 100.0, 8.3);
  const int n = chain.size();
  auto y = random_state(n, 5u);
  y[chain.bit_index()] = 0.3;
  for (double gamma : {1e-4, 0.1, 10.0, 1e3}) {
    std::vector<double> band(5 * n);
    chain.jacobian_band(y.data(), Mode::SlipPositive, band.data());
    // Dense copy of M = I − γJ.
    std::vector<double> M(n * n, 0.0);
    for (int r = 0; r < n; ++r)
      for (int c = std::max(0, r - 2); c <= std::min(n - 1, r + 2); ++c)
        M[r * n + c] = (r == c ? 1.0 : 0.0) - gamma * band[5 * r + (c - r + 2)];
    const auto b = random_state(n, 7u);
    std::vector<double> x(n);
    REQUIRE(detail::factor_band(band, n, gamma));
    detail::solve_band(band, n, b.data(), x.data());
    for (int r = 0; r < n; ++r) {  // residual of the dense system
      double s = 0.0;
      for (int c = 0; c < n; ++c) s += M[r * n + c] * x[c];
      CHECK(s == Approx(b[r]).margin(1e-10));
    }
  }
}

TEST_CASE("equilibria balance the torque and zero the right-hand side", "[model][equilibrium]") {
  const Params p = preset("reduced-scale", 4);
  // u = c_r Ω + c_b Ω + T_fb(Ω) is convex in Ω with value T_s at 0⁺.
  const auto omegas = equilibrium_velocities(p, 40.0, 8.3);
  REQUIRE(omegas.size() == 1);  // u > T_s = 3.2 N·m: one steady state
  CHECK(equilibrium_torque(p, 40.0, omegas[0]) == Approx(8.3).epsilon(1e-14));
  const Chain chain(p, 40.0, 8.3);
  const auto y = equilibrium_state(p, 40.0, omegas[0]);
  std::vector<double> f(y.size());
  chain.rhs(y.data(), Mode::SlipPositive, f.data());
  for (double v : f) CHECK(std::fabs(v) < 1e-12);

  // Below T_s with strong Stribeck weakening there are two steady states.
  const double wob = 200.0;  // δ(0) = W R γ (μs−μc) = 5.4 > c_r + c_b
  const double ts = 0.8 * wob * 0.1;
  const auto two = equilibrium_velocities(p, wob, ts - 0.5);
  REQUIRE(two.size() == 2);
  CHECK(two[0] < two[1]);
  for (double w : two) CHECK(equilibrium_torque(p, wob, w) == Approx(ts - 0.5).epsilon(1e-13));
  CHECK(equilibrium_velocities(p, wob, 1.0).empty());  // below the minimum of the curve
}

TEST_CASE("the O(1) accelerations and rate of T_e equal the full right-hand side's", "[model]") {
  // The regime judge and the rootfinders read them at every step; the full f is the reference.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 10.0);
  for (int dof : {2, 3, 7}) {
    const Chain chain(preset("reduced-scale", dof), 100.0, 8.3);
    for (Mode mode : {Mode::SlipPositive, Mode::SlipNegative, Mode::Stick, Mode::Band}) {
      std::vector<double> y(static_cast<std::size_t>(chain.size())), f(y.size());
      for (double& v : y) v = normal(rng);
      if (mode == Mode::Stick) y[static_cast<std::size_t>(chain.bit_index())] = 0.0;
      chain.rhs(y.data(), mode, f.data());
      const double scale = 1.0 + std::fabs(chain.reaction_torque(f.data()));
      CHECK(chain.top_acceleration(y.data()) == Approx(f[0]).margin(1e-12 * (1 + std::fabs(f[0]))));
      CHECK(chain.bit_acceleration(y.data(), mode) ==
            Approx(f[static_cast<std::size_t>(chain.bit_index())]).margin(1e-12 * scale));
      CHECK(chain.reaction_rate(y.data(), mode) ==
            Approx(chain.reaction_torque(f.data())).margin(1e-12 * scale));
    }
  }
}
