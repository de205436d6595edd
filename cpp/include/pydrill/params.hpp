// Parameters of the lumped torsional drillstring model (DESIGN.md §2, §4).
//
// A string is a chain of `dof` inertias, top drive first, bit last, joined by
// `dof - 1` torsional springs with viscous damping. Everything is SI:
// kg·m², N·m/rad, N·m·s/rad, m, N, N·m, rad/s.
#pragma once

#include <string>
#include <vector>

namespace pydrill {

// Mechanical chain plus bit–rock friction law. Operating inputs (weight on bit,
// surface torque) are not part of it: they are the axes of every study.
struct Params {
  std::vector<double> inertias;     // I_0 (top drive) ... I_{N-1} (bit), kg·m²
  std::vector<double> stiffnesses;  // k_i joins inertia i and i+1, N·m/rad
  std::vector<double> dampings;     // c_i joins inertia i and i+1, N·m·s/rad
  double top_damping = 0.0;         // c_r, viscous torque at the top drive
  double bit_damping = 0.0;         // c_b, viscous torque at the bit (mud)
  double bit_radius = 0.0;          // R_b, m
  double mu_coulomb = 0.0;          // μ_cb, Coulomb (dynamic) friction coefficient
  double mu_static = 0.0;           // μ_sb, static friction coefficient
  double stribeck_decay = 0.0;      // γ_b, velocity decrease rate of friction
  double stribeck_velocity = 1.0;   // v_f, rad/s, makes γ_b·ω/v_f dimensionless
  double karnopp_band = 1e-6;       // D_v, rad/s, zero-velocity band of Eq. (9)

  int dof() const { return static_cast<int>(inertias.size()); }

  // Throws std::invalid_argument naming the parameter, its value and the
  // allowed range. Every entry point calls this before doing any work.
  void validate() const;
};

// Named parameter sets of DESIGN.md §4.
//   "reduced-scale": laboratory-scale string of Eq. (14), any dof >= 2.
//   "real-string":   the 2-DOF string of Eq. (53); other dof are refused.
Params preset(const std::string& name, int dof);
std::vector<std::string> preset_names();

// dof of a reduced-scale string with `pipes` drill pipes between the top drive, the
// BHA and the bit: dof = pipes + 3. Throws std::invalid_argument unless
// 1 <= pipes <= 99997 (preset's dof cap minus 3).
int pipes_to_dof(int pipes);

// Validation helpers shared by the simulator and the analysis code.
void check_operating_point(double wob, double torque);

}  // namespace pydrill
