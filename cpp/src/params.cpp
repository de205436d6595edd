#include "pydrill/params.hpp"
#include "pydrill/version.hpp"

#include "shortest.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pydrill {

const char* version() noexcept { return PYDRILL_VERSION_STRING; }
namespace {

using detail::shortest;

[[noreturn]] void refuse(const std::string& name, double value, const std::string& allowed) {
  throw std::invalid_argument(name + " = " + shortest(value) + " is not allowed: " + allowed);
}

// A subnormal parameter (below 2.2e-308, fewer than 53 bits) is 0 to a run, which flushes
// subnormal numbers (flush_subnormals.hpp), and loses its digits in the stability analysis:
// a stiffness of 5e-324 ran as a broken spring and gave critical_deltas eight spurious Hopf
// points. The doubles' range below and above stays open (a stiffness of 1e-300 is allowed).
bool subnormal(double v) { return v != 0 && std::fabs(v) < std::numeric_limits<double>::min(); }

[[noreturn]] void refuse_subnormal(const std::string& name, double v, bool zero_allowed) {
  refuse(name, v, std::string("a subnormal number is 0 to a simulation (it flushes them) and has lost its digits; give ") +
                      (zero_allowed ? "0 or " : "") + "a number >= 2.2250738585072014e-308");
}

void check_positive(const std::string& name, double v) {
  if (!std::isfinite(v) || !(v > 0)) refuse(name, v, "must be a finite number > 0");
  if (subnormal(v)) refuse_subnormal(name, v, false);
}

void check_nonnegative(const std::string& name, double v) {
  if (!std::isfinite(v) || !(v >= 0)) refuse(name, v, "must be a finite number >= 0");
  if (subnormal(v)) refuse_subnormal(name, v, true);
}

// Every entry point validates, several times a run: the item's name is only built for a
// value that fails (building it for each of 1000 entries cost 0.1 ms a call).
void check_list(const std::string& name, const std::vector<double>& values, bool strictly) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (std::isfinite(v) && (strictly ? v > 0 : v >= 0) && !subnormal(v)) continue;
    const std::string item = name + "[" + std::to_string(i) + "]";
    strictly ? check_positive(item, v) : check_nonnegative(item, v);
  }
}

// The rates of the model: at inertia i the decay rate (c_r + c_{i-1} + c_i + c_b) / I_i (1/s,
// c_r at the top, c_b at the bit) and the squared frequency (k_{i-1} + k_i) / I_i (1/s²), the
// diagonal of M⁻¹C and M⁻¹K, which are the Jacobian's entries. The solvers square rates: the
// error norms square rate × step × state, the starting-step estimates (CVODES, DOP853) and the
// Newton matrix form second derivatives ~ rate² × state. A double overflows at 1.8e308, a rate
// at its square root, 1.3e154 /s; kMaxRate leaves four decades for the state it multiplies.
// Decay rates are held far lower, at kMaxDecay (params.hpp): beyond it BDF's Newton iterations
// fail for want of precision, long before anything overflows.
// Measured before this check: top_damping = 1e300 ground through max_steps at t = 1e-13 s,
// an inertia of 1e-300 failed at t = 0 with CVODES's "h = nan", stiffnesses 1e300 with
// DOP853's "step size fell" at t = 0, bit_damping 1e300 as "chattering". No drill string
// comes near: a real string's rates, element by element down to a 1.5 m stabilizer, are
// below 1e7 /s. Slow rates (an inertia of 1e300, a stiffness of 1e-300) are not refused: the
// string barely moves, and the runs end at once.
void check_rates(const Params& p) {
  const std::size_t N = p.inertias.size();
  static_assert(kMaxRate == 1e150 && kMaxDecay == 1e15, "the messages below write them out");
  const double max_decay = kMaxDecay, max_rate2 = kMaxRate * kMaxRate;
  for (std::size_t i = 0; i < N; ++i) {
    const double I = p.inertias[i];
    const double k_above = i > 0 ? p.stiffnesses[i - 1] : 0.0, k_below = i + 1 < N ? p.stiffnesses[i] : 0.0;
    const double c_above = i == 0 ? p.top_damping : p.dampings[i - 1];
    const double c_below = i + 1 == N ? p.bit_damping : p.dampings[i];
    const double decay = (c_above + c_below) / I, freq2 = (k_above + k_below) / I;
    if (decay <= max_decay && freq2 <= max_rate2) continue;  // (NaN cannot arise: all finite, I > 0)
    // Names: the row's two terms and its inertia; the message starts with whichever of the
    // largest term and the inertia is further from 1 in decades (the absurd one, usually).
    const std::string inertia = "inertias[" + std::to_string(i) + "]";
    auto name = [&](bool above, bool spring) -> std::string {
      if (!spring && above && i == 0) return "top_damping";
      if (!spring && !above && i + 1 == N) return "bit_damping";
      const std::size_t j = above ? i - 1 : i;
      return std::string(spring ? "stiffnesses[" : "dampings[") + std::to_string(j) + "]";
    };
    const bool spring = !(decay > max_decay);
    const bool has_above = spring ? i > 0 : true, has_below = spring ? i + 1 < N : true;
    const double above = spring ? k_above : c_above, below = spring ? k_below : c_below;
    const bool big_is_above = has_above && (!has_below || above >= below);
    const std::string big = name(big_is_above, spring);
    const double big_value = big_is_above ? above : below;
    const std::string sum = has_above && has_below ? name(true, spring) + " + " + name(false, spring) : big;
    const bool inertia_first = std::fabs(std::log10(I)) > std::fabs(std::log10(big_value));
    const std::string first = inertia_first ? inertia : big, second = inertia_first ? big : inertia;
    const double first_value = inertia_first ? I : big_value, second_value = inertia_first ? big_value : I;
    std::ostringstream o;
    o << first << " = " << shortest(first_value) << " is not allowed with " << second << " = "
      << shortest(second_value) << ": ";
    o.precision(3);
    if (!spring) {
      o << "the decay rate at inertia " << i << ", (" << sum << ") / " << inertia << " = " << decay
        << " /s, must be <= 1e15 /s (no step of a double-precision solver resolves a faster "
           "decay; a real string's are below 1e7 /s: check the units)";
    } else {
      o << "the frequency at inertia " << i << ", sqrt(" << (has_above && has_below ? "(" + sum + ")" : sum)
        << " / " << inertia << ") = " << std::sqrt(freq2) << " rad/s, must be <= 1e150 rad/s"
        << " (the solvers square the model's rates, and a double overflows at 1.8e308)";
    }
    throw std::invalid_argument(o.str());
  }
}

}  // namespace

void Params::validate() const {
  if (inertias.size() < 2) {
    throw std::invalid_argument("dof = " + std::to_string(inertias.size()) +
                                " is not allowed: a string needs dof >= 2 inertias (top drive and bit)");
  }
  const std::size_t springs = inertias.size() - 1;
  if (stiffnesses.size() != springs) {
    throw std::invalid_argument("stiffnesses has " + std::to_string(stiffnesses.size()) +
                                " entries: dof = " + std::to_string(inertias.size()) + " needs " +
                                std::to_string(springs));
  }
  if (dampings.size() != springs) {
    throw std::invalid_argument("dampings has " + std::to_string(dampings.size()) +
                                " entries: dof = " + std::to_string(inertias.size()) + " needs " +
                                std::to_string(springs));
  }
  check_list("inertias", inertias, true);
  check_list("stiffnesses", stiffnesses, true);
  check_list("dampings", dampings, false);
  check_nonnegative("top_damping", top_damping);
  check_nonnegative("bit_damping", bit_damping);
  check_positive("bit_radius", bit_radius);
  check_positive("stribeck_decay", stribeck_decay);
  check_positive("stribeck_velocity", stribeck_velocity);
  check_positive("karnopp_band", karnopp_band);
  // The friction's decay rate γ_b/v_f (s/rad) must be a number: an infinite one made the slip
  // friction at rest inf × 0 = NaN, and boundary_wob inf / inf.
  if (!std::isfinite(stribeck_decay / stribeck_velocity)) {
    refuse("stribeck_decay", stribeck_decay, "with stribeck_velocity = " + shortest(stribeck_velocity) +
                                                 " their ratio, the friction's decay rate, overflows a double");
  }
  if (!std::isfinite(mu_coulomb) || !(mu_coulomb > 0)) {
    refuse("mu_coulomb", mu_coulomb, "need 0 < mu_coulomb < mu_static");
  }
  if (subnormal(mu_coulomb)) refuse_subnormal("mu_coulomb", mu_coulomb, false);
  if (!std::isfinite(mu_static) || !(mu_static > mu_coulomb)) {
    std::ostringstream allowed;
    allowed << "need 0 < mu_coulomb (" << mu_coulomb << ") < mu_static";
    refuse("mu_static", mu_static, allowed.str());
  }
  check_rates(*this);
}

void check_operating_point(double wob, double torque) {
  check_positive("wob", wob);
  if (!std::isfinite(torque)) refuse("torque", torque, "must be a finite number");
}

void check_bit_friction(const Params& p, double wob) {
  const double scale = wob * p.bit_radius;
  const bool torque_fits = std::isfinite(scale * p.mu_static);
  if (torque_fits && std::isfinite(scale * (p.mu_static - p.mu_coulomb) * (p.stribeck_decay / p.stribeck_velocity))) return;
  std::ostringstream o;
  o << "wob = " << shortest(wob) << " is not allowed with bit_radius = " << shortest(p.bit_radius)
    << ", mu_static = " << shortest(p.mu_static);
  if (torque_fits) {
    o << ", mu_coulomb = " << shortest(p.mu_coulomb) << ", stribeck_decay = " << shortest(p.stribeck_decay)
      << " and stribeck_velocity = " << shortest(p.stribeck_velocity)
      << ": the friction's Stribeck slope at rest, wob * bit_radius * (mu_static - mu_coulomb) * "
         "stribeck_decay / stribeck_velocity, overflows a double (N·m·s/rad)";
  } else {
    o << ": the static torque mu_static * wob * bit_radius overflows a double (N·m)";
  }
  throw std::invalid_argument(o.str());
}

namespace {
constexpr int kMaxPresetDof = 100'000;
}  // namespace

int pipes_to_dof(int pipes) {
  if (pipes < 1 || pipes > kMaxPresetDof - 3) {
    throw std::invalid_argument("pipes = " + std::to_string(pipes) + " is not allowed: need 1 <= pipes <= " +
                                std::to_string(kMaxPresetDof - 3) + " (dof = pipes + 3)");
  }
  return pipes + 3;
}

std::vector<std::string> preset_names() { return {"reduced-scale", "real-string"}; }

Params preset(const std::string& name, int dof) {
  // A preset allocates its string: a mistyped size (1e9) would take all memory first.
  if (dof > kMaxPresetDof) {
    throw std::invalid_argument("dof = " + std::to_string(dof) + " is not allowed: at most " +
                                std::to_string(kMaxPresetDof) + " inertias");
  }
  if (dof < 2) {
    throw std::invalid_argument("dof = " + std::to_string(dof) +
                                " is not allowed: a string needs dof >= 2 (pipes >= 1 means dof = pipes + 3)");
  }
  Params p;
  if (name == "reduced-scale") {
    // Eq. (14): laboratory-scale string; J_l = J_b, all springs k_t, c_t.
    const double J_r = 0.518, J_b = 0.0318, J = 0.025, J_l = J_b;
    const double k_t = 0.073, c_t = 1e-4;
    p.inertias.push_back(J_r);
    if (dof >= 4) p.inertias.insert(p.inertias.end(), static_cast<std::size_t>(dof - 3), J);
    if (dof >= 3) p.inertias.push_back(J_l);
    p.inertias.push_back(J_b);
    p.stiffnesses.assign(static_cast<std::size_t>(dof - 1), k_t);
    p.dampings.assign(static_cast<std::size_t>(dof - 1), c_t);
    p.top_damping = 0.18;
    p.bit_damping = 0.01;
    p.bit_radius = 0.1;
    p.mu_coulomb = 0.5;
    p.mu_static = 0.8;
    p.stribeck_decay = 0.9;
    p.stribeck_velocity = 1.0;
    p.karnopp_band = 1e-6;
  } else if (name == "real-string") {
    // Eq. (53): 100 pipes of 5 in drill pipe and a BHA lumped into two inertias.
    if (dof != 2) {
      throw std::invalid_argument("dof = " + std::to_string(dof) +
                                  " is not allowed for preset 'real-string': it is the paper's 2-DOF "
                                  "string (Eq. 53); use dof = 2, or give a longer string element by "
                                  "element (Params::inertias, stiffnesses, dampings; in Python, "
                                  "from a pipe tally)");
    }
    p.inertias = {2122.0, 471.9698};
    p.stiffnesses = {861.5336};
    p.dampings = {172.3067};
    p.top_damping = 425.0;
    p.bit_damping = 50.0;
    p.bit_radius = 0.155575;
    p.mu_coulomb = 0.5;
    p.mu_static = 0.8;
    p.stribeck_decay = 0.9;
    p.stribeck_velocity = 1.0;
    p.karnopp_band = 1e-6;
  } else {
    throw std::invalid_argument("preset '" + name +
                                "' is unknown: choose 'reduced-scale' or 'real-string'");
  }
  p.validate();
  return p;
}

}  // namespace pydrill
