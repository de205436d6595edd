// Linear stability of the steady states: the names, the Stribeck slope and its inverse
// (boundary_wob), the bit impedance, and the stability of steady drilling at a velocity or a
// torque (stability_at_*), with its margin to the nearest crossing. The Jacobian, its
// eigenvalues and the low-dof closed forms are in stability_jacobian.cpp, the crossings
// (critical_deltas) and the first Lyapunov coefficient in hopf_crossings.cpp.
#include "pydrill/stability.hpp"

#include <algorithm>
#include <utility>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "interrupt_poll.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/friction.hpp"
#include "shortest.hpp"
#include "stability_internal.hpp"

namespace pydrill {

using detail::check_delta;
using detail::impedance;
using detail::stribeck_factor;

const char* crossing_type_name(CrossingType t) noexcept {
  switch (t) {
    case CrossingType::Hopf: return "hopf";
    case CrossingType::Fold: return "fold";
  }
  return "?";
}

CrossingType parse_crossing_type(const std::string& s) {
  if (s == "hopf") return CrossingType::Hopf;
  if (s == "fold") return CrossingType::Fold;
  throw std::invalid_argument("crossing type = '" + s + "' is not allowed: choose 'hopf' or 'fold'");
}

namespace detail {

double stribeck_factor(const Params& p) {
  return p.bit_radius * (p.stribeck_decay / p.stribeck_velocity) * (p.mu_static - p.mu_coulomb);
}

Fraction bit_fraction(const Params& p, complex lambda) {
  const int n = p.dof();
  complex num = p.inertias[0] * lambda + p.top_damping, den = 1.0;
  for (int i = 0; i < n - 1; ++i) {
    // Spring i has impedance (k + cλ)/λ in series with everything above it.
    const complex spring = p.stiffnesses[i] + p.dampings[i] * lambda;
    const complex n_above = spring * num;
    const complex d_above = spring * den + lambda * num;
    const complex own = p.inertias[i + 1] * lambda + (i + 1 == n - 1 ? p.bit_damping : 0.0);
    num = own * d_above + n_above;
    den = d_above;
    // Rescale by a power of two (exact, cheap) before anything can overflow.
    const double big = std::max(std::max(std::fabs(num.real()), std::fabs(num.imag())),
                                std::max(std::fabs(den.real()), std::fabs(den.imag())));
    if (big > 1e100 || (big < 1e-100 && big > 0)) {
      const int e = std::ilogb(big);
      num = complex(std::ldexp(num.real(), -e), std::ldexp(num.imag(), -e));
      den = complex(std::ldexp(den.real(), -e), std::ldexp(den.imag(), -e));
    }
  }
  auto finite = [](complex z) { return std::isfinite(z.real()) && std::isfinite(z.imag()); };
  if (finite(num) && finite(den)) return {num, den};
  // A coefficient near the top of the doubles (valid: an inertia of 1.8e308) overflowed its
  // product with λ before the rescaling could act, and the phase came out NaN (critical_deltas
  // lost four of a string's six crossings). Again as the continued fraction itself, where an
  // element's infinite impedance is the limit it stands for: a spring in series with it
  // passes on the spring's alone (1/inf = 0).
  auto inverse = [](complex z) { return std::isinf(z.real()) || std::isinf(z.imag()) ? complex(0.0) : 1.0 / z; };
  complex z = p.inertias[0] * lambda + p.top_damping;
  for (int i = 0; i < n - 1; ++i) {
    const complex spring = p.stiffnesses[i] + p.dampings[i] * lambda;
    const complex own = p.inertias[i + 1] * lambda + (i + 1 == n - 1 ? p.bit_damping : 0.0);
    z = own + inverse(inverse(z) + lambda * inverse(spring));
  }
  return {z, 1.0};
}

complex impedance(const Params& p, complex lambda) {
  const Fraction f = bit_fraction(p, lambda);
  return f.num / f.den;
}

void check_delta(double delta) {
  if (!std::isfinite(delta)) {
    std::ostringstream o;
    o << "delta = " << detail::shortest(delta) << " is not allowed: the Stribeck slope must be a finite number (N·m·s/rad)";
    throw std::invalid_argument(o.str());
  }
}

}  // namespace detail

double stribeck_slope(const Params& p, double wob, double omega) {
  p.validate();
  check_operating_point(wob, 0.0);
  check_bit_friction(p, wob);  // wob · stribeck_factor = inf times exp(−big) = 0 was NaN
  if (!std::isfinite(omega) || !(omega >= 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: the Stribeck slope is defined at a finite bit velocity >= 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  const double scale = wob * stribeck_factor(p);
  // wob · factor can overflow where check_bit_friction's product, in BitFriction's order, does
  // not (wob 2.2e-308, mu_static 8.7e307, stribeck_decay 1e300): inf × exp(−big) was NaN.
  if (!std::isfinite(scale)) return BitFriction(p, wob).delta(omega);
  return scale * std::exp(-p.stribeck_decay * omega / p.stribeck_velocity);
}

double boundary_wob(const Params& p, double delta, double omega) {
  p.validate();
  check_delta(delta);
  // δ ∝ W_ob > 0: a slope <= 0 has no weight on bit (it came back as W_ob <= 0).
  if (!(delta > 0)) {
    throw std::invalid_argument("delta = " + detail::shortest(delta) +
                                " is not allowed: must be > 0 N·m·s/rad (the Stribeck slope of a weight on bit > 0)");
  }
  if (!std::isfinite(omega) || !(omega >= 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: a boundary is drawn at a finite bit velocity >= 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  return delta * std::exp(p.stribeck_decay * omega / p.stribeck_velocity) / stribeck_factor(p);
}

complex bit_impedance(const Params& p, complex lambda) {
  p.validate();
  if (!std::isfinite(lambda.real()) || !std::isfinite(lambda.imag())) {
    std::ostringstream o;
    o << "lambda = (" << detail::shortest(lambda.real()) << "," << detail::shortest(lambda.imag()) << ")" << " is not allowed: the impedance is evaluated at a finite complex number";
    throw std::invalid_argument(o.str());
  }
  return impedance(p, lambda);
}

namespace {

// From this many inertias on, steady states get the structured eigenvalues (measured: 0.12
// against 0.29 ms at dof 24, 21 against 700 ms at dof 303). Below, both take a fraction of
// a millisecond, far less than the simulation beside them, and the dense solver is kept.
constexpr int kStructuredDof = 24;

// Crossings handed in must be the string's: the unstable counts come from them, and an empty
// or foreign list answered "stable" for every point. Every damped string has its fold at
// δ = c_r + c_b; nothing else in a crossing names its string (the same
// test as Python's, which runs it first, with math.isclose's rel_tol = 1e-9). Every string
// has one fold, at δ = c_r + c_b (at 0 without damping at the ends: it turns freely as one body).
void check_crossings(const Params& p, const std::vector<Crossing>& crossings) {
  const double fold = p.top_damping + p.bit_damping;
  std::vector<double> folds;
  for (const Crossing& c : crossings) {
    if (c.type == CrossingType::Fold) folds.push_back(c.delta);
  }
  const bool ok = folds.size() == 1 && std::fabs(folds[0] - fold) <= 1e-9 * std::max(std::fabs(folds[0]), fold);
  if (!ok) {
    std::ostringstream o;
    o << "crossings are not this string's ("
      << (folds.empty()       ? std::string("no fold")
          : folds.size() == 1 ? "a fold at delta = " + detail::shortest(folds[0])
                              : std::to_string(folds.size()) + " folds")
      << "; its own have one at c_r + c_b = " << detail::shortest(fold)
      << "): give critical_deltas(params) of the same params";
    throw std::invalid_argument(o.str());
  }
}

StabilityPoint point_at(const Params& p, double wob, double omega,
                        const std::vector<Crossing>& crossings,
                        const std::function<bool()>& interrupt) {
  if (!std::isfinite(omega) || !(omega > 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: steady drilling needs a finite omega > 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  StabilityPoint s;
  s.omega = omega;
  s.wob = wob;
  s.torque = equilibrium_torque(p, wob, omega);
  s.delta = stribeck_slope(p, wob, omega);
  s.unstable = unstable_count(crossings, s.delta);
  s.stable = s.unstable == 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& c : crossings) nearest = std::min(nearest, std::fabs(c.delta - s.delta));
  s.delta_margin = s.stable ? nearest : -nearest;
  // Long strings: the roots of Z_b = δ in O(n'²), kept only if as many lie in the right
  // half-plane as the crossings say; else (and on short strings, where it gains nothing)
  // the dense solver.
  detail::InterruptPoll poll(interrupt);
  std::vector<complex> roots;
  if (p.dof() >= kStructuredDof && roots_of_impedance(p, s.delta, roots, interrupt) &&
      std::count_if(roots.begin(), roots.end(), [](complex z) { return z.real() > 0; }) == s.unstable) {
    s.eigenvalues = std::move(roots);
  } else {
    poll.check();  // the dense solver cannot be stopped once started
    s.eigenvalues = eigenvalues(p, s.delta);
  }
  s.spectral_abscissa = s.eigenvalues.front().real();
  return s;
}

}  // namespace

StabilityPoint stability_at_velocity(const Params& p, double wob, double omega,
                                     const std::function<bool()>& interrupt) {
  return point_at(p, wob, omega, critical_deltas(p, interrupt), interrupt);
}

std::vector<StabilityPoint> stability_at_torque(const Params& p, double wob, double torque,
                                                const std::function<bool()>& interrupt) {
  if (equilibrium_velocities(p, wob, std::fabs(torque)).empty()) return {};
  // Once per string.
  return stability_at_torque(p, critical_deltas(p, interrupt), wob, torque, interrupt);
}

std::vector<StabilityPoint> stability_at_torque(const Params& p, const std::vector<Crossing>& crossings,
                                                double wob, double torque,
                                                const std::function<bool()>& interrupt) {
  p.validate();
  check_crossings(p, crossings);
  std::vector<StabilityPoint> out;
  for (double omega : equilibrium_velocities(p, wob, std::fabs(torque))) {
    out.push_back(point_at(p, wob, omega, crossings, interrupt));
  }
  if (torque < 0) {
    // Turning backwards is the mirror image (φ → −φ) of turning forwards at |u|: the same
    // steady states reversed, with the same eigenvalues (the friction's slope is even in Ω).
    std::reverse(out.begin(), out.end());
    for (auto& s : out) s.omega = -s.omega, s.torque = -s.torque;
  }
  return out;
}

}  // namespace pydrill
