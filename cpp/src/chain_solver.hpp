// A SUNDIALS linear solver specialised for the drillstring chain.
//
// CVODES's BDF Newton iteration needs solves with M = I − γJ. In twist coordinates J is
// pentadiagonal, and each twist row is θ̇_i = ω_i − ω_{i+1}: the twists eliminate exactly
// (θ_i = b_θi + γ(ω_i − ω_{i+1})), which leaves a tridiagonal system in the dof velocities,
// strictly diagonally dominant above the bit (every row is 1 plus γ times a dissipative
// spring stencil). It is factored top down without pivoting, so the factors of every row
// above the bit depend on γ alone — the springs are linear — and the bit's row, the only one
// the state and the friction mode change, is refreshed in O(1) at every solve. The solver is
// "matrix-embedded": it asks CVODES for γ and the predicted state itself and forms J from the
// model, so no SUNMatrix is involved.
#pragma once

#include <sundials/sundials_linearsolver.h>

#include <vector>

#include "pydrill/model.hpp"

namespace pydrill::detail {

// M = I − γJ for one chain, reduced to the velocities and factored.
class ChainNewtonMatrix {
 public:
  // Factors the rows above the bit for this γ (O(dof); they depend on nothing else). False
  // if a pivot is too small to trust.
  bool factor(const Chain& chain, double gamma);
  // The bit's row for the state y in the given mode (O(1)), after factor(). False if its
  // pivot is too small to trust.
  bool set_bit_row(const Chain& chain, const double* y, Mode mode);
  // x = M⁻¹ b (size chain.size(); x may alias b), after factor() and set_bit_row().
  void solve(const double* b, double* x) const;
  double gamma() const { return gamma_; }

 private:
  // Per velocity row i: the multiplier of row i−1 in the elimination, 1/pivot, the entry of
  // ω_{i+1}, and γ·J(2i, 2i∓1), which carry the twists' right-hand sides into the row.
  struct Row {
    double mult = 0, inv_pivot = 0, upper = 0, from_twist_above = 0, from_twist_below = 0;
  };
  std::vector<Row> rows_;
  double gamma_ = 0.0;
};

struct ChainSolverData {
  void* cvode_mem = nullptr;
  const Chain* chain = nullptr;
  const Mode* mode = nullptr;   // the simulator's current mode (read only)
  ChainNewtonMatrix matrix;
  long factorizations = 0;      // factor() calls: one per new γ
  long solves = 0;
  bool valid = false;           // factored for matrix.gamma()
};

SUNLinearSolver make_chain_solver(SUNContext ctx, ChainSolverData* data);

}  // namespace pydrill::detail
