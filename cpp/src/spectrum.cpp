// Eigenvalues of the reduced Jacobian in O(n'²), from the chain's structure.
//
// The eigenvalues at slope δ are the n' = 2·dof − 1 roots of the polynomial
//     P_δ(λ) = N(λ) − δ D(λ),    Z_b(λ) = N(λ) / D(λ)
// (N, D: the numerator and denominator of the bit impedance's continued
// fraction, of degrees n' and n' − 1). Both, and their derivatives, come from
// the chain's recurrence in O(dof) at any λ, without forming coefficients (which
// span hundreds of decades on a long string). All roots at once by the
// Ehrlich–Aberth iteration, O(n') evaluations and O(n'²) work per sweep,
// started from each mode of the free chain with its own modal damping: near ±iω_k
// for lightly damped modes, on the real axis for overdamped ones (a real string's
// pipes), whose roots bunch by the dozen near −k/c. From there it converges in
// 2 … 15 sweeps. A dense O(n'³) eigensolver takes 0.8 s at dof 303, 0.45 s on a
// 3000 m string of 334 inertias; this takes 20 ms. Every result is checked
// (convergence, the trace of the Jacobian, conjugate symmetry); on any doubt the
// dense solver answers instead.
#include <algorithm>
#include <cmath>
#include <complex>
#include <utility>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>

#include "interrupt_poll.hpp"
#include "pydrill/stability.hpp"
#include "shortest.hpp"

namespace pydrill {

// Shorthand for this file only: the public headers spell std::complex<double>.
using complex = std::complex<double>;

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
    // Looked at every 4th step only (at every one, the look cost a sixth of the time): a
    // step multiplies them by far less than 1e50 on any string we know, and an overflow
    // still shows as a non-finite P below, where the dense solver takes over.
    if (i % 4 != 3 && i + 2 < n) continue;
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

// The unit eigenvector of the symmetric tridiagonal matrix (diag, sub) for its eigenvalue
// mu, from a twisted factorisation (Fernando's, as in LAPACK's MRRR): O(N) and stable
// without pivoting, where an eigen-decomposition would cost O(N²) per vector. `fwd`, `bwd`:
// scratch of size N.
void tridiagonal_eigenvector(const Eigen::VectorXd& diag, const Eigen::VectorXd& sub, double mu,
                             std::vector<double>& x, std::vector<double>& fwd,
                             std::vector<double>& bwd) {
  const int N = static_cast<int>(diag.size());
  const double tiny = std::numeric_limits<double>::epsilon() * (std::fabs(mu) + diag.cwiseAbs().maxCoeff());
  auto pivot = [tiny](double v) { return v != 0.0 ? v : tiny; };
  fwd[0] = pivot(diag(0) - mu);
  for (int i = 1; i < N; ++i) fwd[i] = pivot(diag(i) - mu - sub(i - 1) * sub(i - 1) / fwd[i - 1]);
  bwd[N - 1] = pivot(diag(N - 1) - mu);
  for (int i = N - 2; i >= 0; --i) bwd[i] = pivot(diag(i) - mu - sub(i) * sub(i) / bwd[i + 1]);
  int twist = 0;  // where |γ_r| = |D⁺_r + D⁻_r − (d_r − μ)| is least: the vector's bulk
  double least = std::numeric_limits<double>::infinity();
  for (int r = 0; r < N; ++r) {
    const double g = std::fabs(fwd[r] + bwd[r] - (diag(r) - mu));
    if (g < least) {
      least = g;
      twist = r;
    }
  }
  x[twist] = 1.0;
  for (int i = twist - 1; i >= 0; --i) x[i] = -sub(i) * x[i + 1] / fwd[i];
  for (int i = twist + 1; i < N; ++i) x[i] = -sub(i - 1) * x[i - 1] / bwd[i];
  double norm = 0.0;
  for (double v : x) norm += v * v;
  norm = std::sqrt(norm);
  for (double& v : x) v /= norm;
}

// Starting points: for each mode of the free chain (mass-normalised shape φ_k, frequency
// ω_k), the roots of λ² + c_k λ + ω_k² with c_k = φ_kᵀ C φ_k its modal damping. Exact when
// the damping is proportional to the stiffness and the ends add none, close otherwise:
// lightly damped modes start near ±iω_k, overdamped ones (a real string's pipes, c = k/5)
// next to their real roots, which bunch near −k/c, where a start farther off crawls. The
// rigid rotation (ω_0 = 0, φ_0 constant) gives one root, −(c_r + c_b − δ)/ΣJ. δ is left out
// of the other modes' damping: a large δ acts at the bit alone, and spread over every mode
// it would move their starts away from their roots.
std::vector<complex> starting_points(const Params& p, double delta, detail::InterruptPoll& poll) {
  const int N = p.dof();
  Eigen::VectorXd diag(N), sub(N - 1);
  for (int i = 0; i < N; ++i) {
    double k = 0.0;
    if (i > 0) k += p.stiffnesses[i - 1];
    if (i < N - 1) k += p.stiffnesses[i];
    diag(i) = k / p.inertias[i];
    if (i + 1 < N) sub(i) = -p.stiffnesses[i] / std::sqrt(p.inertias[i] * p.inertias[i + 1]);
  }
  const Eigen::VectorXd ev = detail::tridiagonal_eigenvalues(diag, sub, poll);
  double inertia = 0.0;
  for (double j : p.inertias) inertia += j;
  std::vector<complex> z;
  z.reserve(2 * static_cast<std::size_t>(N) - 1);
  z.emplace_back(-(p.top_damping + p.bit_damping - delta) / inertia, 0.0);
  std::vector<double> y(N), fwd(N), bwd(N), root_j(N);
  for (int i = 0; i < N; ++i) root_j[i] = std::sqrt(p.inertias[i]);
  for (int k = 1; k < N; ++k) {
    const double w2 = std::max(ev(k), 0.0);
    poll.tick(N);
    tridiagonal_eigenvector(diag, sub, ev(k), y, fwd, bwd);
    auto phi = [&](int i) { return y[i] / root_j[i]; };
    double c = p.top_damping * phi(0) * phi(0) + p.bit_damping * phi(N - 1) * phi(N - 1);
    for (int i = 0; i + 1 < N; ++i) {
      const double d = phi(i) - phi(i + 1);
      c += p.dampings[i] * d * d;
    }
    if (!std::isfinite(c)) c = 0.0;  // no shape: start undamped, as lightly damped modes are
    const double disc = c * c - 4 * w2;
    if (disc < 0) {
      const double im = 0.5 * std::sqrt(-disc);
      z.emplace_back(-0.5 * c, im);
      z.emplace_back(-0.5 * c, -im);
    } else {
      const double q = -0.5 * (c + std::sqrt(disc));  // c ≥ 0 here: no cancellation
      z.emplace_back(q, 0.0);
      z.emplace_back(q != 0.0 ? w2 / q : 0.0, 0.0);
    }
  }
  // Distinct points, not quite symmetric about the real axis: a conjugate-symmetric start
  // stays so at every step, and a pair could then never become two real roots (past a
  // fold). Each moves by a thousandth of its distance to the nearest other start.
  std::vector<complex> moved = z;
  for (std::size_t i = 0; i < z.size(); ++i) {
    poll.tick(static_cast<long>(z.size()));
    double gap = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < z.size(); ++j) {
      if (j != i) gap = std::min(gap, std::norm(z[i] - z[j]));
    }
    gap = std::sqrt(gap);
    if (!(gap > 0) || !std::isfinite(gap)) gap = 1e-12 * (std::abs(z[i]) + 1.0);
    moved[i] = z[i] + 1e-3 * gap * std::polar(1.0, 2.39996 * static_cast<double>(i + 1));
  }
  return moved;
}

bool converged_roots(const Params& p, double delta, std::vector<complex>& z,
                     detail::InterruptPoll& poll) {
  const int n = static_cast<int>(z.size());
  const double eps = std::numeric_limits<double>::epsilon();
  std::vector<char> done(n, 0);
  std::vector<double> last(n, std::numeric_limits<double>::infinity());
  // From the modal starts, 2 … 15 sweeps (measured on preset strings of 24 … 400 inertias
  // and real tallies to 5000 m, δ from 0 to 1e7), and up to ~40 on a tally's string with a
  // bit damped a hundred times more than usual. Past 60 the iteration is crawling through a
  // cluster (e.g. a uniform string damped 60× past critical: dozens of roots within 1e-9,
  // 69 sweeps), and the dense solver is the quicker answer.
  for (int sweep = 0; sweep < 60; ++sweep) {
    // Roots are known to eps relative to the largest (as from a dense solver), so a small
    // one (0, at a fold) converges in absolute terms.
    double rho = 0.0;
    for (const complex& r : z) rho = std::max(rho, std::abs(r));
    int moving = 0;
    for (int i = 0; i < n; ++i) {
      if (done[i]) continue;
      poll.tick(p.dof() + n);  // a Newton step along the chain, then n − 1 differences
      const NewtonStep s = newton_step(p, delta, z[i]);
      if (!s.ok) return false;
      // Σ 1/(z_i − z_j) as conj(d)/|d|²: the library's careful complex division (scaled
      // against overflow, which differences of roots never near) took 60 % of the time.
      double re = 0.0, im = 0.0;
      for (int j = 0; j < n; ++j) {
        if (j == i) continue;
        const double dr = z[i].real() - z[j].real(), di = z[i].imag() - z[j].imag();
        const double inv = 1.0 / (dr * dr + di * di);
        re += dr * inv;
        im -= di * inv;
      }
      const complex repel(re, im);
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

// roots_of_impedance, asking `poll` as it goes.
bool find_roots(const Params& p, double delta, std::vector<complex>& out, detail::InterruptPoll& poll) {
  p.validate();
  if (!std::isfinite(delta)) {
    std::ostringstream o;
    o << "delta = " << detail::shortest(delta) << " is not allowed: the Stribeck slope must be a finite number (N·m·s/rad)";
    throw std::invalid_argument(o.str());
  }
  std::vector<complex> z = starting_points(p, delta, poll);
  bool ok = converged_roots(p, delta, z, poll);
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
    // below the axis with one above; the pairs are then made exact conjugates. A root is
    // real when its imaginary part is within what the iteration resolves: ~64 eps of the
    // largest root (the convergence test above), i.e. 1e-13 of it. (In a cluster of real
    // roots 1e-10 apart, as near -1/beta on a long string, one can come out with an
    // imaginary part of 1.1e-14 of the largest.)
    double rho = 0.0;
    for (const complex& r : z) rho = std::max(rho, std::abs(r));
    std::vector<complex> real, above, below;
    for (const complex& r : z) {
      if (std::fabs(r.imag()) <= 1e-12 * std::abs(r) + 1e-13 * rho) {
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
        const double d = std::norm(std::conj(above[a]) - below[b]);
        if (!taken[a] && d < dist) {
          dist = d;
          best = a;
        }
      }
      ok = best < above.size() && std::sqrt(dist) <= 1e-8 * std::abs(below[b]) + 1e-13 * rho;
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

}  // namespace

bool roots_of_impedance(const Params& p, double delta, std::vector<complex>& out,
                        const std::function<bool()>& interrupt) {
  detail::InterruptPoll poll(interrupt);
  return find_roots(p, delta, out, poll);
}

std::vector<complex> structured_eigenvalues(const Params& p, double delta,
                                            const std::function<bool()>& interrupt) {
  detail::InterruptPoll poll(interrupt);
  std::vector<complex> z;
  if (find_roots(p, delta, z, poll)) return z;
  poll.check();  // the dense solver, O(n'³), cannot be stopped once started
  return eigenvalues(p, delta);
}

}  // namespace pydrill
