// What every integrator backend shares: the discrete state of the friction
// (mode) and the root functions that end each smooth piece of the motion.
#pragma once

#include <sundials/sundials_nvector.h>

#include "pydrill/model.hpp"

namespace pydrill::detail {

constexpr int kQuads = 4;  // φ_0, ∫u ω_0 dt, ∫viscous dissipation dt, ∫friction dissipation dt
constexpr int kRoots = 4;  // slots; unused ones hold a constant so they never fire

// Read by the right-hand side and the root functions, changed only at
// switches: the right-hand side stays pure.
struct RunData {
  const Chain* chain = nullptr;
  Mode mode = Mode::Stick;
  bool karnopp = false;
  double ts = 0.0, dv = 0.0;
};

// Right-hand side with the quadrature integrands riding along as four extra
// states (the explicit integrators have no separate quadratures).
inline void rhs_with_quadratures(const RunData& d, const double* y, double* f) {
  double* q = f + d.chain->size();
  q[0] = y[0];
  d.chain->rhs(y, d.mode, f, q + 1);
}

// Quadrature integrands (power balance and the top angle).
inline void quadrature_rhs(const RunData& d, const double* y, double* q) {
  q[0] = y[0];
  q[1] = d.chain->input_power(y);
  q[2] = d.chain->viscous_power(y, d.mode);
  q[3] = d.chain->friction_power(y, d.mode);
}

// Root functions of the current mode; each is non-zero right after its mode
// is entered, so CVODES/ARKODE never start on a blind zero.
void root_functions(const RunData& d, const double* y, double* g);
void root_directions(const RunData& d, int dir[kRoots]);

// dg/dt along the motion, from f = dy/dt: every root function is affine in y (ω_b ∓ D_v,
// T_e ∓ T_s, with T_e linear in the state), so its rate is its linear part applied to f.
void root_rates(const RunData& d, const double* f, double* gdot);

// SUNDIALS callback shape (user data = RunData).
int root_callback(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data);

}  // namespace pydrill::detail
