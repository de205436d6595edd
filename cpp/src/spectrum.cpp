// Eigenvalues of the reduced Jacobian in O(n'²), from the chain's structure.
//
// The eigenvalues at slope δ are the n' = 2·dof − 1 roots of the polynomial
//     P_δ(λ) = N(λ) − δ D(λ),    Z_b(λ) = N(λ) / D(λ)
// (N, D: the numerator and denominator of the bit impedance's continued
// fraction, of degrees n' and n' − 1). Both, and their derivatives, come from
// the chain's recurrence in O(dof) at any λ, without forming coefficients (which
// span hundreds of decades on a long string). All roots at once by the
// Ehrlich–Aberth iteration, O(n') evaluations and O(n'²) work per sweep,
// started next to the undamped chain's natural frequencies ±iω_k, near which
// the lightly damped modes lie. A dense O(n'³) eigensolver takes 0.8 s at
// dof 303; this takes milliseconds. Every result is checked (convergence, the
// trace of the Jacobian, conjugate symmetry); on any doubt the dense solver
// answers instead.
#include <algorithm>
#include <cmath>
#include <complex>
#include <utility>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>

#include "pydrill/stability.hpp"

namespace pydrill {

namespace {

// P_δ and its derivative at λ, rescaled together by a power of two (their
// ratio, the Newton step, is all the iteration needs).
struct NewtonStep {
  complex step;  // P/P'
  bool ok;
};

NewtonStep newton_step(const Params& p, double delta, complex lambda) {
  const int n = p.dof();
  complex num = p.inertias[0] * lambda + p.top_damping, dnum = p.inertias[0];
  complex den = 1.0, dden = 0.0;
  for (int i = 0; i < n - 1; ++i) {
    const complex spring = p.stiffnesses[i] + p.dampings[i] * lambda;
    const double dspring = p.dampings[i];
    const complex n_above = spring * num;
    const complex dn_above = dspring * num + spring * dnum;
    const complex d_above = spring * den + lambda * num;
    const complex dd_above = dspring * den + spring * dden + num + lambda * dnum;
    const complex own = p.inertias[i + 1] * lambda + (i + 1 == n - 1 ? p.bit_damping : 0.0);
    const double down = p.inertias[i + 1];
    num = own * d_above + n_above;
    dnum = down * d_above + own * dd_above + dn_above;
    den = d_above;
    dden = dd_above;
    double big = 0.0;
    for (const complex& z : {num, dnum, den, dden}) {
      big = std::max({big, std::fabs(z.real()), std::fabs(z.imag())});
    }
    if (big > 1e100 || (big < 1e-100 && big > 0)) {
      const int e = std::ilogb(big);
      auto scale = [e](complex z) { return complex(std::ldexp(z.real(), -e), std::ldexp(z.imag(), -e)); };
      num = scale(num);
      dnum = scale(dnum);
      den = scale(den);
      dden = scale(dden);
    }
  }
  const complex P = num - delta * den, dP = dnum - delta * dden;
  if (!std::isfinite(std::abs(P)) || !std::isfinite(std::abs(dP))) return {0.0, false};
  if (P == 0.0) return {0.0, true};  // on a root
  if (dP == 0.0) return {0.0, false};
  return {P / dP, true};
}

double jacobian_trace(const Params& p, double delta) {
  const int N = p.dof();
  double t = 0.0;
  for (int i = 0; i < N; ++i) {
    double d = (i == 0 ? -p.top_damping : 0.0) + (i == N - 1 ? -p.bit_damping + delta : 0.0);
    if (i > 0) d -= p.dampings[i - 1];
    if (i < N - 1) d -= p.dampings[i];
    t += d / p.inertias[i];
  }
  return t;
}

// Starting points: the rigid rotation's real eigenvalue, and ±iω_k for the free
// chain's natural frequencies, nudged into the left half-plane, where lightly damped
// modes lie.
std::vector<complex> starting_points(const Params& p, double delta) {
  const int N = p.dof();
  Eigen::VectorXd diag(N), sub(N - 1);
  for (int i = 0; i < N; ++i) {
    double k = 0.0;
    if (i > 0) k += p.stiffnesses[i - 1];
    if (i < N - 1) k += p.stiffnesses[i];
    diag(i) = k / p.inertias[i];
    if (i + 1 < N) sub(i) = -p.stiffnesses[i] / std::sqrt(p.inertias[i] * p.inertias[i + 1]);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
  es.computeFromTridiagonal(diag, sub, Eigen::EigenvaluesOnly);
  double inertia = 0.0;
  for (double j : p.inertias) inertia += j;
  std::vector<complex> z;
  z.reserve(2 * static_cast<std::size_t>(N) - 1);
  // The smallest of the free chain's eigenvalues is the rigid rotation (0).
  z.emplace_back(-(p.top_damping + p.bit_damping - delta) / inertia, 0.0);
  for (int k = 1; k < N; ++k) {
    const double w = std::sqrt(std::max(es.eigenvalues()(k), 0.0));
    const double sigma = 1e-3 * w + 1e-6;
    z.emplace_back(-sigma, w);
    z.emplace_back(-sigma, -w);
  }
  // Distinct points, not quite symmetric about the real axis: a conjugate-symmetric start
  // stays so at every step, and a pair could then never become two real roots (past a
  // fold).
  const double eps = std::numeric_limits<double>::epsilon();
  for (std::size_t i = 0; i < z.size(); ++i) {
    const double size = std::abs(z[i]) + 1e-12;
    z[i] = z[i] * std::polar(1.0, 1e-3) + complex(0.0, 1e3 * eps * size * static_cast<double>(i % 7));
  }
  return z;
}

// The largest damping ratio of a spring of the string, c / (2 sqrt(k J)), J the lighter of
// the inertias it joins. Past ~1 its high modes are overdamped and their roots bunch on
// the real axis near -k/c (a real string's pipes, with c = k/5, put ~50 of them within
// 1e-3 of -5): the iteration crawls there, so such strings go straight to the dense
// solver. (The dampings at the ends touch one mode each and do not matter.)
double largest_damping_ratio(const Params& p) {
  double most = 0.0;
  for (int i = 0; i + 1 < p.dof(); ++i) {
    const double j = std::min(p.inertias[i], p.inertias[i + 1]);
    most = std::max(most, p.dampings[i] / (2 * std::sqrt(p.stiffnesses[i] * j)));
  }
  return most;
}

bool converged_roots(const Params& p, double delta, std::vector<complex>& z) {
  const int n = static_cast<int>(z.size());
  const double eps = std::numeric_limits<double>::epsilon();
  std::vector<char> done(n, 0);
  std::vector<double> last(n, std::numeric_limits<double>::infinity());
  for (int sweep = 0; sweep < 60; ++sweep) {
    // Roots are known to eps relative to the largest (as from a dense solver), so a small
    // one (0, at a fold) converges in absolute terms.
    double rho = 0.0;
    for (const complex& r : z) rho = std::max(rho, std::abs(r));
    int moving = 0;
    for (int i = 0; i < n; ++i) {
      if (done[i]) continue;
      const NewtonStep s = newton_step(p, delta, z[i]);
      if (!s.ok) return false;
      complex repel = 0.0;
      for (int j = 0; j < n; ++j) {
        if (j != i) repel += 1.0 / (z[i] - z[j]);
      }
      const complex w = s.step / (1.0 - s.step * repel);
      const double size = std::abs(w), near = std::abs(z[i]) + rho;
      if (!std::isfinite(size)) return false;
      z[i] -= w;  // Gauss–Seidel: the others see the new value at once
      // Done at the last bits, or where the steps stop shrinking while tiny: rounding
      // noise in P (convergence is cubic, so a real step always shrinks by far more).
      if (size <= 4 * eps * near || (size <= 64 * eps * near && size >= 0.5 * last[i])) {
        done[i] = 1;
      } else {
        ++moving;
      }
      last[i] = size;
    }
    if (moving == 0) return true;
  }
  return false;
}

}  // namespace

bool roots_of_impedance(const Params& p, double delta, std::vector<complex>& out) {
  p.validate();
  if (largest_damping_ratio(p) > 0.5) return false;
  std::vector<complex> z = starting_points(p, delta);
  bool ok = converged_roots(p, delta, z);
  if (ok) {
    // Sum of the eigenvalues = trace of the Jacobian: a lost or doubled root shows.
    complex sum = 0.0;
    double scale = 0.0;
    for (const complex& r : z) {
      sum += r;
      scale += std::abs(r);
    }
    const double tr = jacobian_trace(p, delta);
    ok = std::fabs(sum.real() - tr) <= 1e-9 * (scale + std::fabs(tr)) &&
         std::fabs(sum.imag()) <= 1e-9 * scale;
  }
  if (ok) {
    // A real matrix: its eigenvalues are real or pairs of conjugates. Pair every root
    // below the axis with one above; the pairs are then made exact conjugates.
    double rho = 0.0;
    for (const complex& r : z) rho = std::max(rho, std::abs(r));
    std::vector<complex> real, above, below;
    for (const complex& r : z) {
      if (std::fabs(r.imag()) <= 1e-12 * std::abs(r) + 1e-14 * rho) {
        real.emplace_back(r.real(), 0.0);
      } else {
        (r.imag() > 0 ? above : below).push_back(r);
      }
    }
    ok = above.size() == below.size();
    std::vector<char> taken(above.size(), 0);
    for (std::size_t b = 0; ok && b < below.size(); ++b) {
      std::size_t best = above.size();
      double dist = std::numeric_limits<double>::infinity();
      for (std::size_t a = 0; a < above.size(); ++a) {
        const double d = std::abs(std::conj(above[a]) - below[b]);
        if (!taken[a] && d < dist) {
          dist = d;
          best = a;
        }
      }
      ok = best < above.size() && dist <= 1e-8 * std::abs(below[b]) + 1e-14 * rho;
      if (ok) taken[best] = 1;
    }
    if (ok) {
      z = real;
      for (const complex& r : above) {
        z.push_back(r);
        z.push_back(std::conj(r));
      }
    }
  }
  if (!ok) return false;
  std::sort(z.begin(), z.end(), [](complex a, complex b) {
    return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
  });
  out = std::move(z);
  return true;
}

std::vector<complex> structured_eigenvalues(const Params& p, double delta) {
  std::vector<complex> z;
  if (roots_of_impedance(p, delta, z)) return z;
  return eigenvalues(p, delta);  // the dense solver, O(n'³)
}

}  // namespace pydrill
