// The first Lyapunov coefficient at a Hopf point (sub- or supercritical: whether stick-slip
// appears abruptly or grows from nothing as δ passes it), by the normal-form formula on the
// Jacobian's banded solves.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "band_lu.hpp"
#include "pydrill/stability.hpp"
#include "shortest.hpp"
#include "stability_internal.hpp"

namespace pydrill {

using detail::check_delta;
using detail::jacobian_entries;

namespace {
// How far iω may lie from the eigenvalue, relative to ω, for (δ, ω) to pass as a Hopf point.
constexpr double kHopfReach = 1e-2;
}  // namespace

double first_lyapunov_coefficient(const Params& p, double delta, double w) {
  if (!std::isfinite(w) || !(w > 0)) {
    std::ostringstream o;
    o << "frequency = " << detail::shortest(w) << " is not allowed: a Hopf point needs a finite frequency > 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  p.validate();
  check_delta(delta);
  // At δ = 0 the friction is flat about Ω to every order (its Taylor terms are all ∝ δ), so
  // the normal form has no cubic term: 0, a degenerate Hopf point. An undamped string has its
  // Hopf points there, at its fold too, where the solves below would refuse.
  if (delta == 0.0) return 0.0;
  // Where a banded matrix below is exactly singular there is no coefficient: at the fold
  // (δ = c_r + c_b, A itself singular; an undamped string's at δ = 0 threw BandLU's bare
  // runtime_error "band LU: the matrix is singular"), or on a string whose scales a double
  // cannot separate. A Hopf point of critical_deltas is never at the fold.
  auto refuse = [&] {
    std::ostringstream o;
    o << "delta = " << detail::shortest(delta) << " is not allowed with frequency = " << detail::shortest(w)
      << ": the linearisation there is singular (the fold is at delta = c_r + c_b = "
      << detail::shortest(p.top_damping + p.bit_damping) << "), so no first Lyapunov coefficient exists";
    throw std::invalid_argument(o.str());
  };
  if (delta == p.top_damping + p.bit_damping) refuse();
  // (δ, ω) must be a Hopf point: iω an eigenvalue at δ, a root of Z_b(λ) = δ. Elsewhere the
  // normal form below still gives a number, which belongs to no Hopf point (δ = 0.01, ω = 1 on
  // the 4-DOF laboratory string: 0.036, "subcritical", its nearest eigenvalue 0.27 rad/s from
  // i). The distance to the root, by a Newton step from iω: a crossing of critical_deltas lies
  // within rounding of it (every one of 12000 crossings of 2100 random strings, lightly to
  // heavily damped, inertias 1e-23 to 1e23), and a pair typed to six digits near enough (every
  // crossing of the laboratory string at 2 to 1000 DOF); beyond 1 % of ω it is none.
  // Near a pole of Z_b (where Z_b is far from δ and steep) the step on Z_b − δ is far too
  // short, and the one on 1/Z_b − 1/δ, |Z_b / δ| times longer, is the right one: the longer of
  // the two. (At a Hopf point Z_b = δ and they agree.)
  const complex at(0.0, w);
  const complex z = detail::impedance(p, at), mismatch = z - delta;
  const double away = mismatch == complex(0.0)
                          ? 0.0
                          : std::abs(mismatch / detail::impedance_slope(p, at)) *
                                std::max(1.0, std::abs(z) / std::fabs(delta));
  if (!(away <= kHopfReach * w)) {
    std::ostringstream o;
    o << "delta = " << detail::shortest(delta) << " and frequency = " << detail::shortest(w)
      << " are not a Hopf point of this string: i*frequency is no eigenvalue at slope delta";
    o.precision(2);  // (an estimate: two digits)
    if (std::isfinite(away)) o << " (a Newton step towards the nearest goes " << away << " rad/s)";
    o << ": allowed within 1 % of frequency (" << kHopfReach * w
      << " rad/s); give a Hopf crossing of critical_deltas(params)";
    throw std::invalid_argument(o.str());
  }
  const int n = 2 * p.dof() - 1, b = n - 1;
  // The Jacobian's band alone, J(r, c) at band[5r + c − r + 2]: built dense, it cost O(n'²)
  // time and memory (1.1 s and 1.2 GB at 6000 pipes).
  std::vector<double> band(static_cast<std::size_t>(n) * 5, 0.0);
  jacobian_entries(p, delta, [&](int r, int c) -> double& { return band[static_cast<std::size_t>(r) * 5 + (c - r + 2)]; });
  auto J = [&](int r, int c) { return band[static_cast<std::size_t>(r) * 5 + (c - r + 2)]; };
  using CVec = std::vector<complex>;
  const complex iw(0.0, w);
  // Every matrix below is s·A (or s·Aᵀ) + shift·I: banded like A (two neighbours either
  // side in the interleaved coordinates), so each solve is O(n'), not a dense O(n'³) LU
  // (2.6 s at 500 pipes).
  auto banded = [&](bool transpose, double scale, complex shift) {
    BandLU<complex> lu(n, 2, 2);
    for (int r = 0; r < n; ++r) {
      for (int c = std::max(0, r - 2); c <= std::min(n - 1, r + 2); ++c) {
        const double a = transpose ? J(c, r) : J(r, c);
        lu.at(r, c) = scale * a + (r == c ? shift : complex(0.0));
      }
    }
    try {
      lu.factor();
    } catch (const std::runtime_error&) {  // an exactly zero pivot, BandLU's only error
      refuse();
    }
    return lu;
  };
  auto dot = [](const CVec& x, const CVec& y) {  // x̄ᵀy
    complex s(0.0);
    for (std::size_t i = 0; i < x.size(); ++i) s += std::conj(x[i]) * y[i];
    return s;
  };
  // Null vectors of A − iω and Aᵀ + iω by inverse iteration (the shift is an exact
  // eigenvalue up to rounding; a tiny offset keeps the LU regular).
  const complex offset(1e-10 * std::max(1.0, w), 0.0);
  auto null_vector = [&](const BandLU<complex>& lu) {
    CVec v(static_cast<std::size_t>(n), complex(1.0));
    for (int it = 0; it < 3; ++it) {
      lu.solve(v);
      const double norm = std::sqrt(std::real(dot(v, v)));
      for (auto& x : v) x /= norm;
    }
    return v;
  };
  const CVec q = null_vector(banded(false, 1.0, -iw - offset));
  CVec pv = null_vector(banded(true, 1.0, iw - offset));
  const complex norm = std::conj(dot(pv, q));  // ⟨p, q⟩ = p̄ᵀq = 1
  for (auto& x : pv) x /= norm;
  const double g = p.stribeck_decay / p.stribeck_velocity;
  // The friction's nonlinearity acts on the bit's velocity alone (the last state):
  // B(x, y) = β x_b y_b e_b and C(x, y, z) = κ x_b y_b z_b e_b.
  const double beta = -delta * g / p.inertias.back();
  const double kappa = delta * g * g / p.inertias.back();
  const complex qb = q[static_cast<std::size_t>(b)], pb = std::conj(pv[static_cast<std::size_t>(b)]);
  auto along_bit = [&](complex value) {
    CVec e(static_cast<std::size_t>(n), complex(0.0));
    e[static_cast<std::size_t>(b)] = value;
    return e;
  };
  CVec a1 = along_bit(beta * qb * std::conj(qb));  // A⁻¹ B(q, q̄)
  banded(false, 1.0, complex(0.0)).solve(a1);
  CVec a2 = along_bit(beta * qb * qb);  // (2iω − A)⁻¹ B(q, q)
  banded(false, -1.0, 2.0 * iw).solve(a2);
  const complex s = pb * kappa * qb * qb * std::conj(qb) - 2.0 * pb * beta * qb * a1[static_cast<std::size_t>(b)] +
                    pb * beta * std::conj(qb) * a2[static_cast<std::size_t>(b)];
  return std::real(s) / (2.0 * w);
}

}  // namespace pydrill
