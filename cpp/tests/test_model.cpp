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

namespace {
// A string whose every inertia, spring and damper differs (the presets repeat one pipe, and
// their springs are all k_t: an index off by one between neighbours would pass unseen there).
Params unequal_string(int dof) {
  Params p = preset("reduced-scale", dof);
  for (int i = 0; i < dof; ++i) p.inertias[i] *= 1.0 + 0.37 * std::sin(1.3 * i + 0.2);
  for (int i = 0; i + 1 < dof; ++i) {
    p.stiffnesses[i] *= 1.0 + 0.41 * std::cos(0.7 * i + 0.5);
    p.dampings[i] *= 2.0 + std::sin(2.1 * i);
  }
  p.top_damping = 0.23;
  p.bit_damping = 0.013;
  return p;
}
}  // namespace

TEST_CASE("on a string of unequal parts the model is DESIGN.md's equations", "[model]") {
  const double wob = 100.0, u = 8.3;
  for (int dof : {2, 7, 300}) {
    const Params p = unequal_string(dof);
    const Chain chain(p, wob, u);
    const int N = dof, n = chain.size(), b = chain.bit_index();
    const auto& I = p.inertias;
    const auto& k = p.stiffnesses;
    const auto& c = p.dampings;
    auto y = random_state(n, 3u + static_cast<unsigned>(dof));
    for (Mode mode : {Mode::SlipPositive, Mode::SlipNegative, Mode::Stick}) {
      y[b] = mode == Mode::SlipPositive ? 0.7 : mode == Mode::SlipNegative ? -0.7 : 0.0;
      auto w = [&](int i) { return y[2 * i]; };
      auto th = [&](int i) { return y[2 * i + 1]; };
      // Slip friction T_fb = R_b W_ob μ_b(ω_b) sgn(ω_b), μ_b = μ_cb + (μ_sb − μ_cb) e^{−γ_b|ω|/v_f}.
      const double wb = w(N - 1);
      const double mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) *
                                           std::exp(-p.stribeck_decay * std::fabs(wb) /
                                                    p.stribeck_velocity);
      const double te = k[N - 2] * th(N - 2) + c[N - 2] * (w(N - 2) - wb) - p.bit_damping * wb;
      const double tf = mode == Mode::Stick ? te : p.bit_radius * wob * mu * (wb > 0 ? 1.0 : -1.0);
      // I_i ω̇_i = (torque from above) − (torque to below); θ̇_i = ω_i − ω_{i+1}.
      std::vector<double> expect(static_cast<std::size_t>(n));
      for (int i = 0; i < N; ++i) {
        const double above =
            i == 0 ? u - p.top_damping * w(0) : k[i - 1] * th(i - 1) + c[i - 1] * (w(i - 1) - w(i));
        const double below =
            i == N - 1 ? p.bit_damping * w(i) + tf : k[i] * th(i) + c[i] * (w(i) - w(i + 1));
        expect[2 * i] = (above - below) / I[i];
        if (i < N - 1) expect[2 * i + 1] = w(i) - w(i + 1);
      }
      if (mode == Mode::Stick) expect[b] = 0.0;  // the rock holds the bit
      std::vector<double> f(static_cast<std::size_t>(n));
      double power[3];
      chain.rhs(y.data(), mode, f.data(), power);
      for (int r = 0; r < n; ++r) {
        INFO("dof " << dof << " mode " << mode_name(mode) << " row " << r);
        CHECK(f[r] == Approx(expect[r]).margin(1e-12 * (1.0 + std::fabs(expect[r]))));
      }
      double kinetic = 0.0, elastic = 0.0;
      double viscous = p.top_damping * w(0) * w(0) + p.bit_damping * wb * wb;
      for (int i = 0; i < N; ++i) kinetic += 0.5 * I[i] * w(i) * w(i);
      for (int i = 0; i + 1 < N; ++i) {
        elastic += 0.5 * k[i] * th(i) * th(i);
        viscous += c[i] * (w(i) - w(i + 1)) * (w(i) - w(i + 1));
      }
      CHECK(chain.reaction_torque(y.data()) == Approx(te).epsilon(1e-13));
      CHECK(chain.energy(y.data()) == Approx(kinetic + elastic).epsilon(1e-13));
      CHECK(power[0] == Approx(u * w(0)).epsilon(1e-13));
      CHECK(power[1] == Approx(viscous).epsilon(1e-13));
      CHECK(power[2] == Approx(tf * wb).margin(1e-15));
      // dE/dt = input − viscous − friction power, along f: the ledger the simulator integrates.
      double dE = 0.0;
      for (int i = 0; i < N; ++i) dE += I[i] * w(i) * f[2 * i];
      for (int i = 0; i + 1 < N; ++i) dE += k[i] * th(i) * f[2 * i + 1];
      const double balance = power[0] - power[1] - (mode == Mode::Stick ? 0.0 : power[2]);
      CHECK(dE == Approx(balance).margin(1e-10 * (1.0 + std::fabs(power[0]) + power[1])));
    }
    // Steady drilling at Ω: every ω_i = Ω, θ_i = h(Ω)/k_i with h = c_b Ω + T_fb(Ω), and f = 0.
    const double omega = 3.0;
    const double mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) *
                                         std::exp(-p.stribeck_decay * omega / p.stribeck_velocity);
    const double h = p.bit_damping * omega + p.bit_radius * wob * mu;
    CHECK(equilibrium_torque(p, wob, omega) == Approx(p.top_damping * omega + h).epsilon(1e-14));
    const auto eq = equilibrium_state(p, wob, omega);
    REQUIRE(static_cast<int>(eq.size()) == n);
    for (int i = 0; i < N; ++i) CHECK(eq[2 * i] == Approx(omega).epsilon(1e-15));
    for (int i = 0; i + 1 < N; ++i) CHECK(eq[2 * i + 1] == Approx(h / k[i]).epsilon(1e-14));
  }
}

TEST_CASE("on a string of unequal parts the banded Jacobian is the RHS's derivative", "[model]") {
  const Params p = unequal_string(9);
  const Chain chain(p, 100.0, 8.3);
  const int n = chain.size(), b = chain.bit_index();
  auto y = random_state(n, 21u);
  for (Mode mode : {Mode::SlipPositive, Mode::SlipNegative, Mode::Stick}) {
    y[b] = mode == Mode::SlipPositive ? 0.7 : mode == Mode::SlipNegative ? -0.7 : 0.0;
    std::vector<double> band(static_cast<std::size_t>(5 * n)), fp(static_cast<std::size_t>(n)), fm(fp);
    chain.jacobian_band(y.data(), mode, band.data());
    for (int c = 0; c < n; ++c) {
      if (mode == Mode::Stick && c == b) continue;  // ω_b is held at 0
      const double h = 1e-6 * std::max(1.0, std::fabs(y[c]));
      auto yp = y, ym = y;
      yp[c] += h;
      ym[c] -= h;
      chain.rhs(yp.data(), mode, fp.data());
      chain.rhs(ym.data(), mode, fm.data());
      for (int r = 0; r < n; ++r) {
        const double fd = (fp[r] - fm[r]) / (2 * h);
        const double an = std::abs(c - r) <= 2 ? band[5 * r + (c - r + 2)] : 0.0;
        INFO("mode " << mode_name(mode) << " J(" << r << "," << c << ")");
        CHECK(an == Approx(fd).margin(1e-7).epsilon(1e-6));
      }
    }
  }
}

TEST_CASE("the chain's Newton solve of I - gamma J matches a dense solve", "[model]") {
  // BDF's linear solver eliminates the twists and factors the velocities' tridiagonal system
  // top down, with the bit's row refreshed per state and mode: checked against the residual
  // of the full pentadiagonal system in every mode, over 10 decades of γ, on equal and
  // unequal strings (dof 2 has no row between the top drive and the bit).
  for (const Params& p : {preset("reduced-scale", 9), unequal_string(2), unequal_string(3),
                          unequal_string(40)}) {
    const Chain chain(p, 100.0, 8.3);
    const int n = chain.size(), b = chain.bit_index();
    auto y = random_state(n, 5u + static_cast<unsigned>(n));
    for (Mode mode : {Mode::SlipPositive, Mode::SlipNegative, Mode::Stick, Mode::Band}) {
      y[b] = mode == Mode::SlipPositive ? 0.3 : mode == Mode::SlipNegative ? -0.3 : mode == Mode::Band ? 3e-7 : 0.0;
      for (double gamma : {1e-6, 1e-4, 0.1, 10.0, 1e3, 1e4}) {
        std::vector<double> band(static_cast<std::size_t>(5 * n));
        chain.jacobian_band(y.data(), mode, band.data());
        detail::ChainNewtonMatrix M;
        REQUIRE(M.factor(chain, gamma));
        if (!M.set_bit_row(chain, y.data(), mode)) {
          // Only a slipping bit's Stribeck weakening can make I − γJ singular there.
          CHECK((mode == Mode::SlipPositive || mode == Mode::SlipNegative));
          continue;
        }
        const auto rhs = random_state(n, 7u);
        std::vector<double> x(static_cast<std::size_t>(n)), x2 = rhs;
        M.solve(rhs.data(), x.data());
        M.solve(x2.data(), x2.data());  // in place
        double scale = 0.0;
        for (int r = 0; r < n; ++r) {  // residual of M x = rhs, row by row
          double s = x[r], size = std::fabs(x[r]);
          for (int c = std::max(0, r - 2); c <= std::min(n - 1, r + 2); ++c) {
            s -= gamma * band[5 * r + (c - r + 2)] * x[c];
            size += std::fabs(gamma * band[5 * r + (c - r + 2)] * x[c]);
          }
          scale = std::max(scale, size);
          INFO("dof " << p.dof() << " mode " << mode_name(mode) << " gamma " << gamma << " row " << r);
          CHECK(s == Approx(rhs[r]).margin(1e-13 * (size + std::fabs(rhs[r]))));
          CHECK(x2[r] == x[r]);
        }
        CHECK(scale > 0.0);
      }
    }
  }
}
