// A SUNDIALS linear solver specialised for the drillstring chain.
//
// CVODES's BDF Newton iteration needs solves with M = I − γJ. In twist
// coordinates J is pentadiagonal, so M is factored by banded Gaussian
// elimination in O(dof) — in code this project compiles with optimisation
// (Debian's SUNDIALS band solver is built without it). The solver is
// "matrix-embedded": it asks CVODES for γ and the predicted state itself and
// forms J from the model, so no SUNMatrix is involved.
#pragma once

#include <sundials/sundials_linearsolver.h>

#include <vector>

#include "pydrill/model.hpp"

namespace pydrill::detail {

struct ChainSolverData {
  void* cvode_mem = nullptr;
  const Chain* chain = nullptr;
  const Mode* mode = nullptr;   // the simulator's current mode (read only)
  std::vector<double> lu;       // 5 entries per row: L below, U on/above the diagonal
  long factorizations = 0;
  long solves = 0;
  // The factorisation is reused while γ, the mode and the friction slope are
  // unchanged: a modified Newton iteration tolerates a slightly stale matrix.
  bool valid = false;
  double gamma = 0.0, slope = 0.0;
  Mode factored_mode = Mode::Stick;
};

SUNLinearSolver make_chain_solver(SUNContext ctx, ChainSolverData* data);

// Factor M = I − γJ (J in band storage, see Chain::jacobian_band) in place, without
// pivoting: L below the diagonal, U above it, and 1/u_rr on it (for solve_band).
// Returns false if a pivot is too small to trust.
bool factor_band(std::vector<double>& band, int n, double gamma);
// Solve with the factors from factor_band; x may alias b.
void solve_band(const std::vector<double>& lu, int n, const double* b, double* x);

}  // namespace pydrill::detail
