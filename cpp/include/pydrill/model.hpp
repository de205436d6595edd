// Equations of motion of the chain in twist coordinates (DESIGN.md §2).
//
// State layout (n = 2·dof − 1):  y = (ω_0, θ_0, ω_1, θ_1, …, θ_{N−2}, ω_{N−1})
// with ω_i at index 2i and the twist θ_i = φ_i − φ_{i+1} at index 2i+1.
// Twists rather than absolute angles: the angles grow like Ω·t and would eat
// the digits of the differences that drive the dynamics. With this order the
// Jacobian is pentadiagonal (bandwidth 2), so linear algebra is O(dof).
#pragma once

#include <vector>

#include "pydrill/export.hpp"
#include "pydrill/friction.hpp"
#include "pydrill/params.hpp"

namespace pydrill {

// How the bit–rock contact is currently treated. The mode is part of the
// simulator's discrete state; the right-hand side only reads it.
enum class Mode {
  SlipPositive,  // bit turns forward, friction = +f_b(ω_b)
  SlipNegative,  // bit turns backward, friction = −f_b(|ω_b|)
  Stick,         // bit held by the rock: friction = T_e, ω_b frozen (exactly 0 with the
                 // exact law; inside the zero-velocity band with Karnopp's)
  Band,          // Karnopp band |ω_b| < D_v with |T_e| > T_s: friction = ±T_s, the bit creeps
};

// "slip+", "slip-", "stick", "band"; "?" for a value outside the enum.
PYDRILL_API const char* mode_name(Mode m) noexcept;

// One string at one operating point (W_ob, u). Every `y` below points to a state of size()
// doubles in the layout above, `ydot` to size() doubles, `band` to 5·size(); units are SI
// (rad/s, rad, N·m, W, J). It keeps a copy of the Params, so it may outlive the one it was
// made from.
class PYDRILL_API Chain {
 public:
  // Throws std::invalid_argument for invalid Params, a wob (N) not finite and > 0, or a
  // torque (N·m) that is not finite.
  Chain(const Params& params, double wob, double torque);

  int dof() const { return dof_; }
  int size() const { return 2 * dof_ - 1; }
  int bit_index() const { return 2 * dof_ - 2; }
  double torque() const { return torque_; }
  double wob() const { return wob_; }
  const Params& params() const { return params_; }
  const BitFriction& friction() const { return friction_; }
  double static_torque() const { return friction_.static_torque(); }

  // Reaction torque T_e = k θ_{N−2} + c (ω_{N−2} − ω_b) − c_b ω_b: what the
  // rock must hold for the bit to stay still (Eq. 12).
  double reaction_torque(const double* y) const;

  // Friction torque on the bit in the given mode.
  double friction_torque(const double* y, Mode mode) const;

  // dω_0/dt and dω_b/dt alone, in O(1): the components of rhs() that the regime judge
  // needs at every sample to locate the velocity extremes between samples.
  double top_acceleration(const double* y) const;
  double bit_acceleration(const double* y, Mode mode) const;
  // dT_e/dt along the motion in the given mode, in O(1) (T_e is linear in the state).
  double reaction_rate(const double* y, Mode mode) const;

  // ẏ = f(y) in the given mode. Pure: no state is changed.
  void rhs(const double* y, Mode mode, double* ydot) const { rhs(y, mode, ydot, nullptr); }
  // The same, and (if power is not null) the three power densities below in
  // power[0..2] = input, viscous, friction, from the same pass over the chain.
  void rhs(const double* y, Mode mode, double* ydot, double* power) const;

  // Jacobian ∂f/∂y in band storage: band[5*r + (c − r + 2)] = J(r, c) for
  // |c − r| <= 2. Entries outside the matrix are set to zero.
  void jacobian_band(const double* y, Mode mode, double* band) const;

  // Power balance densities: input power u·ω_0, viscous dissipation
  // c_r ω_0² + Σ c_i (ω_i − ω_{i+1})² + c_b ω_b², friction power T_f·ω_b.
  double input_power(const double* y) const { return torque_ * y[0]; }
  double viscous_power(const double* y, Mode mode) const;
  double friction_power(const double* y, Mode mode) const;

  // Kinetic plus elastic energy ½Σ I ω² + ½Σ k θ².
  double energy(const double* y) const;

  // Mode in which a simulation starting from y must begin.
  Mode initial_mode(const double* y, bool karnopp) const;

 private:
  Params params_;
  BitFriction friction_;
  int dof_;
  double wob_, torque_;
  std::vector<double> inv_inertia_;
};

}  // namespace pydrill
