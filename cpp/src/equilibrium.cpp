#include "pydrill/equilibrium.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "pydrill/friction.hpp"
#include "shortest.hpp"

namespace pydrill {
namespace {

// g(Ω) = (c_r + c_b) Ω + f_b(Ω): the surface torque that holds Ω.
struct TorqueCurve {
  double C;
  BitFriction f;
  double operator()(double omega) const { return C * omega + f.magnitude(omega); }
};

// Bisection on a bracket where g − u changes sign; runs until the bracket
// cannot shrink any further in floating point, so the root is exact to the ulp.
double bisect(const TorqueCurve& g, double u, double lo, double hi) {
  double glo = g(lo) - u;
  for (int it = 0; it < 2000; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double gm = g(mid) - u;
    if (gm == 0.0) return mid;
    if ((gm < 0) == (glo < 0)) {
      lo = mid;
      glo = gm;
    } else {
      hi = mid;
    }
  }
  return std::fabs(g(lo) - u) <= std::fabs(g(hi) - u) ? lo : hi;
}

}  // namespace

double equilibrium_torque(const Params& params, double wob, double omega) {
  params.validate();
  check_operating_point(wob, 0.0);
  if (!std::isfinite(omega) || !(omega > 0)) {
    throw std::invalid_argument("omega = " + detail::shortest(omega) +
                                " is not allowed: steady drilling needs a finite omega > 0 rad/s");
  }
  const BitFriction f(params, wob);
  return (params.top_damping + params.bit_damping) * omega + f.magnitude(omega);
}

std::vector<double> equilibrium_velocities(const Params& params, double wob, double torque) {
  params.validate();
  check_operating_point(wob, torque);
  const TorqueCurve g{params.top_damping + params.bit_damping, BitFriction(params, wob)};
  const double ts = g.f.static_torque();
  const double slope0 = g.f.delta(0.0);  // −d f_b/dΩ at 0⁺
  std::vector<double> roots;

  // Turning point Ω_m where δ(Ω_m) = C (g is convex, so this is its minimum).
  double omega_min = 0.0;
  if (g.C <= 0.0) {
    omega_min = std::numeric_limits<double>::infinity();
  } else if (slope0 > g.C) {
    // log(δ(0)/C) as a sum of logs: δ(0) = W R (μ_s − μ_c) γ/v_f itself overflows for an
    // extreme friction (μ_s = 1e308), and Ω_m came out inf, as if there were no damping.
    const double log_ratio = std::log(g.f.scale) + std::log(g.f.mu_s - g.f.mu_c) +
                             std::log(g.f.decay) - std::log(g.C);
    omega_min = log_ratio / g.f.decay;
  }

  if (std::isinf(omega_min)) {
    // No damping: g falls from T_s towards the Coulomb level W R μ_c.
    if (torque < ts && torque > g.f.scale * g.f.mu_c) {
      double hi = 1.0;
      // Bounded by the doubles' range: a curve that never comes down to the torque there has
      // no steady state a double can hold (the search used to double hi to inf for ever).
      while (g(hi) > torque && std::isfinite(hi)) hi *= 2.0;
      if (std::isfinite(hi)) roots.push_back(bisect(g, torque, 0.0, hi));
    }
    return roots;
  }
  // The steady state on g's rising branch, if a double holds it: as with no damping above, a
  // curve that reaches the torque only beyond the doubles has none (it returned 2^1023 rad/s,
  // where g is 1e306 N·m, as the root for a torque of 1.8e308 N·m and c_r + c_b = 0.011).
  auto push_right_root = [&](double lo) {
    double hi = std::max(1.0, 2.0 * lo);
    while (g(hi) <= torque && std::isfinite(hi)) {  // g grows at least like C·Ω: ends
      lo = hi;
      hi *= 2.0;
    }
    if (std::isfinite(hi)) roots.push_back(bisect(g, torque, lo, hi));
  };
  if (omega_min == 0.0) {
    // g increases from T_s: one steady state iff the torque exceeds T_s.
    if (torque > ts) push_right_root(0.0);
    return roots;
  }
  const double gmin = g(omega_min);
  if (torque == gmin) {
    roots.push_back(omega_min);  // fold: the two branches meet
  } else if (torque > gmin) {
    if (torque < ts) roots.push_back(bisect(g, torque, 0.0, omega_min));
    push_right_root(omega_min);
  }
  return roots;
}

std::vector<double> equilibrium_state(const Params& params, double wob, double omega) {
  const double u = equilibrium_torque(params, wob, omega);  // validates
  const double h = u - params.top_damping * omega;          // torque every spring carries
  const int N = params.dof();
  std::vector<double> y(static_cast<std::size_t>(2 * N - 1));
  for (int i = 0; i < N; ++i) y[2 * i] = omega;
  for (int i = 0; i < N - 1; ++i) y[2 * i + 1] = h / params.stiffnesses[i];
  return y;
}

}  // namespace pydrill
