// Parameters of the lumped torsional drillstring model (DESIGN.md §2, §4).
//
// A string is a chain of `dof` inertias, top drive first, bit last, joined by
// `dof - 1` torsional springs with viscous damping. Everything is SI:
// kg·m², N·m/rad, N·m·s/rad, m, N, N·m, rad/s.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "pydrill/export.hpp"

namespace pydrill {

// What a computation stopped by its `interrupt` callback throws (a cancel button in a program
// that embeds pydrill, a Ctrl-C from Python): Interrupted from a run (which knows where it
// stopped), StabilityInterrupted from a stability computation. Catch Cancelled for both.
class PYDRILL_API Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("interrupted") {}
};

// The fastest rates validate() allows. At every inertia, the frequency (sqrt of the
// stiffnesses acting on it over its inertia, rad/s) at most kMaxRate: the solvers square
// rates, and a double overflows at the square of 1.3e154. The decay rate (the dampings acting
// on it, c_r and c_b included, over its inertia, 1/s) at most kMaxDecay: a stiff decay is
// stepped over by an implicit method, whose Newton matrix I − γhJ keeps its identity part in
// double precision only while γ·h·rate stays below 1/ε ≈ 4.5e15 (measured with BDF: clean at
// 2e15 /s, Newton failing on every other step from 2e16, and a top_damping of 1e40 ground 80 s
// through 5e7 steps to t = 3e-20 s). A real string's rates are below 1e7.
constexpr double kMaxRate = 1e150;
constexpr double kMaxDecay = 1e15;

// Mechanical chain plus bit–rock friction law. Operating inputs (weight on bit,
// surface torque) are not part of it: they are the axes of every study.
// Allowed values (validate() checks them; every number finite, and none subnormal, i.e. none
// in (0, 2.2250738585072014e-308): a run reads those as 0):
struct PYDRILL_API Params {
  std::vector<double> inertias;     // I_0 (top drive) ... I_{N-1} (bit), kg·m²; dof >= 2, each > 0
  std::vector<double> stiffnesses;  // k_i joins inertia i and i+1, N·m/rad; dof − 1 of them, > 0
  std::vector<double> dampings;     // c_i joins inertia i and i+1, N·m·s/rad; dof − 1, >= 0
  double top_damping = 0.0;         // c_r, viscous torque at the top drive, N·m·s/rad, >= 0
  double bit_damping = 0.0;         // c_b, viscous torque at the bit (mud), N·m·s/rad, >= 0
  double bit_radius = 0.0;          // R_b, m, > 0
  double mu_coulomb = 0.0;          // μ_cb, Coulomb (dynamic) friction coefficient, 0 < μ_cb < μ_sb
  double mu_static = 0.0;           // μ_sb, static friction coefficient, > μ_cb
  double stribeck_decay = 0.0;      // γ_b, velocity decrease rate of friction, > 0
  double stribeck_velocity = 1.0;   // v_f, rad/s, makes γ_b·ω/v_f dimensionless, > 0
  double karnopp_band = 1e-6;       // D_v, rad/s, zero-velocity band of Eq. (9), > 0
  // and, at every inertia i, (c_r + c_{i−1} + c_i + c_b)/I_i <= kMaxDecay and
  // sqrt((k_{i−1} + k_i)/I_i) <= kMaxRate (c_r only at the top, c_b only at the bit).

  int dof() const { return static_cast<int>(inertias.size()); }

  // Throws std::invalid_argument naming the parameter, its value and the
  // allowed range. Every entry point calls this before doing any work.
  void validate() const;
};

// Named parameter sets of DESIGN.md §4.
//   "reduced-scale": laboratory-scale string of Eq. (14), 2 <= dof <= 100000.
//   "real-string":   the 2-DOF string of Eq. (53); other dof are refused.
// Throws std::invalid_argument for an unknown name or a dof outside these ranges (the
// cap stops a mistyped size from taking all memory; a hand-built Params has none).
PYDRILL_API Params preset(const std::string& name, int dof);
PYDRILL_API std::vector<std::string> preset_names();  // {"reduced-scale", "real-string"}

// dof of a reduced-scale string with `pipes` drill pipes between the top drive, the
// BHA and the bit: dof = pipes + 3. Throws std::invalid_argument unless
// 1 <= pipes <= 99997 (preset's dof cap minus 3).
PYDRILL_API int pipes_to_dof(int pipes);

// The operating-point check every entry point runs (BitFriction's constructor calls it):
// throws std::invalid_argument unless wob (N) is finite and > 0 and torque (N·m) finite.
PYDRILL_API void check_operating_point(double wob, double torque);

// The bit's friction at a valid wob must fit in a double: its static torque
// mu_static·wob·bit_radius (N·m) and its Stribeck slope at rest
// wob·bit_radius·(mu_static − mu_coulomb)·stribeck_decay/stribeck_velocity (N·m·s/rad); each
// parameter finite is not enough (mu_static = 1e308 made the static torque inf, a run "stuck"
// with an infinite static_torque, and stribeck_slope NaN). Throws std::invalid_argument
// naming wob and the friction parameters. BitFriction's constructor and stribeck_slope call it.
PYDRILL_API void check_bit_friction(const Params& params, double wob);

}  // namespace pydrill
