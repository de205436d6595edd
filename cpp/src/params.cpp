#include "pydrill/params.hpp"
#include "pydrill/version.hpp"

#include "shortest.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pydrill {

const char* version() noexcept { return PYDRILL_VERSION_STRING; }
namespace {

using detail::shortest;

[[noreturn]] void refuse(const std::string& name, double value, const std::string& allowed) {
  throw std::invalid_argument(name + " = " + shortest(value) + " is not allowed: " + allowed);
}

void check_positive(const std::string& name, double v) {
  if (!std::isfinite(v) || !(v > 0)) refuse(name, v, "must be a finite number > 0");
}

void check_nonnegative(const std::string& name, double v) {
  if (!std::isfinite(v) || !(v >= 0)) refuse(name, v, "must be a finite number >= 0");
}

// Every entry point validates, several times a run: the item's name is only built for a
// value that fails (building it for each of 1000 entries cost 0.1 ms a call).
void check_list(const std::string& name, const std::vector<double>& values, bool strictly) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (std::isfinite(v) && (strictly ? v > 0 : v >= 0)) continue;
    const std::string item = name + "[" + std::to_string(i) + "]";
    strictly ? check_positive(item, v) : check_nonnegative(item, v);
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
  if (!std::isfinite(mu_coulomb) || !(mu_coulomb > 0)) {
    refuse("mu_coulomb", mu_coulomb, "need 0 < mu_coulomb < mu_static");
  }
  if (!std::isfinite(mu_static) || !(mu_static > mu_coulomb)) {
    std::ostringstream allowed;
    allowed << "need 0 < mu_coulomb (" << mu_coulomb << ") < mu_static";
    refuse("mu_static", mu_static, allowed.str());
  }
}

void check_operating_point(double wob, double torque) {
  check_positive("wob", wob);
  if (!std::isfinite(torque)) refuse("torque", torque, "must be a finite number");
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
