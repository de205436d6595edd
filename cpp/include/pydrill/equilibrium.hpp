// Steady drilling (DESIGN.md §3): every element turns at the same Ω > 0,
// the twists carry the bit's torque h(Ω) = c_b Ω + T_fb(Ω), and the surface
// torque balances it: u = c_r Ω + h(Ω).
#pragma once

#include <vector>

#include "pydrill/export.hpp"
#include "pydrill/params.hpp"

namespace pydrill {

// Each function throws std::invalid_argument for invalid Params, a weight on bit (N) not
// finite and > 0, a torque (N·m) that is not finite, or an Ω not finite and > 0.

// Surface torque u (N·m) needed to turn at Ω > 0 with the given weight on bit.
PYDRILL_API double equilibrium_torque(const Params& params, double wob, double omega);

// Every Ω > 0 (rad/s) with u = c_r Ω + c_b Ω + T_fb(Ω), in increasing order. The
// right side is convex in Ω, so there are 0, 1 or 2 solutions; each is found
// by bracketed bisection to machine precision.
PYDRILL_API std::vector<double> equilibrium_velocities(const Params& params, double wob,
                                                   double torque);

// Twist-coordinate steady state (size 2·dof − 1, layout of model.hpp) for velocity Ω.
PYDRILL_API std::vector<double> equilibrium_state(const Params& params, double wob, double omega);

}  // namespace pydrill
