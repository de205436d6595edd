// The reduced Jacobian at a Stribeck slope δ, its eigenvalues (dense), the characteristic
// polynomial and its Hurwitz determinants, and the closed form of the Hopf points at dof 2.
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "pydrill/stability.hpp"
#include "shortest.hpp"
#include "stability_internal.hpp"

namespace pydrill {

using detail::check_delta;
using detail::jacobian_entries;

namespace {

using Poly = std::vector<double>;  // ascending powers

Poly times_linear(const Poly& a, double c0, double c1) {  // a·(c0 + c1 λ)
  Poly r(a.size() + 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    r[i] += c0 * a[i];
    r[i + 1] += c1 * a[i];
  }
  return r;
}

Poly add(Poly a, const Poly& b) {
  if (b.size() > a.size()) a.resize(b.size(), 0.0);
  for (std::size_t i = 0; i < b.size(); ++i) a[i] += b[i];
  return a;
}

}  // namespace

std::vector<double> jacobian(const Params& p, double delta) {
  p.validate();
  check_delta(delta);
  const int n = 2 * p.dof() - 1;
  std::vector<double> J(static_cast<std::size_t>(n) * n, 0.0);
  jacobian_entries(p, delta, [&](int r, int c) -> double& { return J[static_cast<std::size_t>(r) * n + c]; });
  return J;
}

std::vector<complex> eigenvalues(const Params& p, double delta) {
  std::vector<double> J = jacobian(p, delta);
  const int n = 2 * p.dof() - 1;
  // A stiff string's Jacobian mixes k/I (a frequency squared) with 1 (θ̇ = Δω), and the
  // unbalanced QR's error, ε·‖J‖, swamped the real parts: at 2.7e8 rad/s (k = 3e8, J_b = 4e-9,
  // valid) a stable point had an eigenvalue of +5.7e8, and from 2.7e7 rad/s some counts of
  // unstable eigenvalues disagreed with the crossings'. The similarity D J D⁻¹ with D =
  // diag(√I_i at ω_i, √k_i at θ_i) keeps the eigenvalues and makes those entries √(k/I), the
  // frequencies themselves. Only where an entry exceeds 1e8, so the usual strings' eigenvalues
  // are those they always were, bit for bit.
  double largest = 0.0;
  for (double v : J) largest = std::max(largest, std::fabs(v));
  if (largest > 1e8) {
    std::vector<double> d(static_cast<std::size_t>(n));
    for (int i = 0; i < p.dof(); ++i) d[2 * static_cast<std::size_t>(i)] = std::sqrt(p.inertias[i]);
    for (int i = 0; i + 1 < p.dof(); ++i) d[2 * static_cast<std::size_t>(i) + 1] = std::sqrt(p.stiffnesses[i]);
    for (std::size_t r = 0; r < d.size(); ++r) {
      for (std::size_t c = 0; c < d.size(); ++c) J[r * d.size() + c] *= d[r] / d[c];
    }
  }
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(
      J.data(), n, n);
  Eigen::EigenSolver<Eigen::MatrixXd> solver(M, false);
  if (solver.info() != Eigen::Success) throw std::runtime_error("eigenvalue solver did not converge");
  std::vector<complex> ev(solver.eigenvalues().data(), solver.eigenvalues().data() + n);
  std::sort(ev.begin(), ev.end(), [](complex a, complex b) {
    return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
  });
  return ev;
}

std::vector<double> characteristic_polynomial(const Params& p, double delta) {
  p.validate();
  check_delta(delta);
  const int N = p.dof();
  if (N > 12) {
    throw std::invalid_argument("dof = " + std::to_string(N) +
                                " is too large for the characteristic polynomial (its coefficients "
                                "lose all accuracy): allowed dof <= 12; use critical_deltas");
  }
  Poly num{p.top_damping, p.inertias[0]}, den{1.0};
  for (int i = 0; i < N - 1; ++i) {
    const Poly n_above = times_linear(num, p.stiffnesses[i], p.dampings[i]);
    const Poly d_above = add(times_linear(den, p.stiffnesses[i], p.dampings[i]), times_linear(num, 0.0, 1.0));
    const double own_c = (i + 1 == N - 1) ? p.bit_damping : 0.0;
    num = add(times_linear(d_above, own_c, p.inertias[i + 1]), n_above);
    den = d_above;
  }
  // det(λI − J) ∝ N_b(λ) − δ D_b(λ); the leading coefficient of N_b is Π I_i.
  Poly c = num;
  for (std::size_t i = 0; i < den.size(); ++i) c[i] -= delta * den[i];
  const double lead = c.back();
  for (double& v : c) v /= lead;
  return c;
}

std::vector<double> hurwitz_determinants(const std::vector<double>& a) {
  const int n = static_cast<int>(a.size()) - 1;
  if (n < 1) {
    // Name what was given: "needs degree >= 1" alone left a caller to guess which list it was.
    throw std::invalid_argument("ascending has " + std::to_string(a.size()) +
                                (a.size() == 1 ? " coefficient" : " coefficients") + ": hurwitz_determinants needs a polynomial of degree >= 1 "
                                "(at least 2 coefficients, in ascending powers)");
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i])) {
      std::ostringstream o;
      o << "ascending[" << i << "] = " << detail::shortest(a[i]) << " is not allowed: coefficients must be finite";
      throw std::invalid_argument(o.str());
    }
  }
  if (!(a.back() > 0)) {
    std::ostringstream o;
    o << "ascending[" << n << "] = " << detail::shortest(a.back())
      << " is not allowed: the leading coefficient (last) must be > 0";
    throw std::invalid_argument(o.str());
  }
  auto b = [&](int k) { return (k < 0 || k > n) ? 0.0 : a[static_cast<std::size_t>(n - k)]; };
  std::vector<double> out;
  for (int m = 1; m < n; ++m) {
    Eigen::MatrixXd H(m, m);
    for (int i = 1; i <= m; ++i)
      for (int j = 1; j <= m; ++j) H(i - 1, j - 1) = b(2 * j - i);
    out.push_back(H.determinant());
  }
  return out;
}

std::vector<double> hopf_deltas_dof2(const Params& p) {
  p.validate();
  if (p.dof() != 2) {
    throw std::invalid_argument("dof = " + std::to_string(p.dof()) +
                                " is not allowed: the closed form of Eq. (51) is for dof = 2 (n' = 3); "
                                "critical_deltas finds the Hopf points of any string");
  }
  const double Jr = p.inertias[0], Jb = p.inertias[1], kt = p.stiffnesses[0], ct = p.dampings[0];
  const double cr = p.top_damping, cb = p.bit_damping, P = Jb * Jr;
  // a_2 = (α2 − J_r δ)/P, a_1 = (α1 − β δ)/P, a_0 = (α0 − k_t δ)/P (Eq. 50 with d_b = −δ).
  const double a2c = Jr * (cb + ct) + Jb * (cr + ct), beta = ct + cr;
  const double a1c = cb * (cr + ct) + ct * cr + kt * (Jb + Jr), a0c = kt * (cb + cr);
  // P²Δ_2 = (α2 − J_r δ)(α1 − β δ) − P(α0 − k_t δ) = A δ² + B δ + C.
  const double A = Jr * beta, B = -(a2c * beta + Jr * a1c - P * kt), C = a2c * a1c - P * a0c;
  std::vector<double> roots;
  const double disc = B * B - 4 * A * C;
  if (A == 0.0) {
    if (B != 0.0) roots.push_back(-C / B);
  } else if (disc >= 0) {
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    roots.push_back(q / A);
    if (q != 0.0) roots.push_back(C / q);
  }
  std::vector<double> hopf;
  for (double d : roots) {
    // A Hopf point needs a_1 > 0 and a_0 > 0 there (the paper's set H_+).
    if (d > 0 && a1c - beta * d > 0 && a0c - kt * d > 0) hopf.push_back(d);
  }
  std::sort(hopf.begin(), hopf.end());
  return hopf;
}

}  // namespace pydrill
