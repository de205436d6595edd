// How stiff a string is (Gershgorin bounds and the fundamental), and the method "auto" picks
// from it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "pydrill/simulator.hpp"

namespace pydrill {

StiffnessEstimate estimate_stiffness(const Params& p) {
  p.validate();
  const int N = p.dof();
  StiffnessEstimate e;
  // Gershgorin bounds on M⁻¹K (squared frequencies) and M⁻¹C (decay rates).
  double w2max = 0.0;
  for (int i = 0; i < N; ++i) {
    double ksum = 0.0, csum = (i == 0 ? p.top_damping : 0.0) + (i == N - 1 ? p.bit_damping : 0.0);
    if (i > 0) { ksum += p.stiffnesses[i - 1]; csum += p.dampings[i - 1]; }
    if (i < N - 1) { ksum += p.stiffnesses[i]; csum += p.dampings[i]; }
    w2max = std::max(w2max, 2.0 * ksum / p.inertias[i]);
    e.fastest_decay = std::max(e.fastest_decay, 2.0 * csum / p.inertias[i]);
  }
  e.fastest_frequency = std::sqrt(w2max);
  // Fundamental: the string clamped at a still bit, lumped as one spring
  // (series compliance) and the inertia above it (Rayleigh quotient).
  double compliance = 0.0, inertia = 0.0;
  for (int i = 0; i < N - 1; ++i) { compliance += 1.0 / p.stiffnesses[i]; inertia += p.inertias[i]; }
  const double product = compliance * inertia;
  if (std::isfinite(product) && product >= std::numeric_limits<double>::min()) {
    e.fundamental = std::sqrt(1.0 / product);
  } else {
    // The product (or 1/k of a subnormal stiffness) overflowed, on valid strings the
    // fundamental of which is tiny but a double (an inertia of 1.8e308: the product was inf,
    // the fundamental 0, stiffness_ratio inf, and critical_deltas' frequency grid NaN). Sums
    // of ratios to the extremes, each in [1, dof], cannot overflow.
    double k_min = p.stiffnesses[0], i_max = p.inertias[0];
    for (int i = 0; i < N - 1; ++i) k_min = std::min(k_min, p.stiffnesses[i]), i_max = std::max(i_max, p.inertias[i]);
    double flex = 0.0, mass = 0.0;
    for (int i = 0; i < N - 1; ++i) flex += k_min / p.stiffnesses[i], mass += p.inertias[i] / i_max;
    e.fundamental = std::sqrt(k_min) / std::sqrt(flex) / (std::sqrt(i_max) * std::sqrt(mass));
  }
  return e;
}

double stiffness_ratio(const Params& p) {
  const StiffnessEstimate e = estimate_stiffness(p);
  return e.fastest_decay / e.fundamental;
}

Method choose_method(const Params& p, std::string* reason) {
  // Stiff means fast modes that decay: BDF steps over them once they have died.
  // Otherwise every method must resolve the fast modes, and the cheapest steps
  // win: DOP853, which restarts at full order after each friction switch and
  // spends almost nothing besides the right-hand side. Measured by
  // benchmarks/bench_methods.py on soft, real, stiff and refined strings:
  // DOP853 is the fastest up to a decay/fundamental ratio of ~1e4 even with
  // overdamped fast modes (3x BDF at 1.8e3); BDF wins only beyond.
  const StiffnessEstimate e = estimate_stiffness(p);
  const double zeta = e.fastest_decay / (2.0 * e.fastest_frequency);
  const double ratio = e.fastest_decay / e.fundamental;
  constexpr double zeta_stiff = 0.5, ratio_stiff = 1e4;
  Method m = Method::DOP853;
  const char* why = "non-stiff: explicit Runge-Kutta DOP853";
  if (zeta > zeta_stiff && ratio > ratio_stiff) {
    m = Method::BDF;
    why = "stiff (fast modes die quickly): BDF with the banded chain solver";
  }
  if (reason) {
    std::ostringstream o;
    o.precision(3);
    o << why << " (fastest decay " << e.fastest_decay << "/s = " << ratio
      << "x the fundamental with the bit held " << e.fundamental
      << " rad/s; damping ratio of the fastest modes "
      << zeta << ")";
    *reason = o.str();
  }
  return m;
}

}  // namespace pydrill
