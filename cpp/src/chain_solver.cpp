#include "chain_solver.hpp"
#include "sundials_compat.hpp"

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>

#include <algorithm>
#include <cmath>

#include "bit_jacobian.hpp"

namespace pydrill::detail {

namespace {

// A pivot smaller than this fraction of its row's largest entry is not trusted: the step is
// retried with a smaller γ (CVODES does that on a recoverable failure).
bool trusted(double pivot, double scale) { return std::isfinite(pivot) && std::fabs(pivot) > 1e-14 * scale; }

}  // namespace

bool ChainNewtonMatrix::factor(const Chain& chain, double gamma) {
  // Velocity row i of M x = b, with θ_{i−1} and θ_i eliminated by their rows
  // θ_j = b_θj + γ(ω_j − ω_{j+1}):
  //   a_i ω_{i−1} + d_i ω_i + u_i ω_{i+1} = b_ωi + γJ(2i, 2i−1) b_θ(i−1) + γJ(2i, 2i+1) b_θi
  // with, above the bit (J from Chain::jacobian_band),
  //   a_i = −γ(c_{i−1} + γk_{i−1})/I_i,  u_i = −γ(c_i + γk_i)/I_i,
  //   d_i = 1 + γ(c_r[i = 0] + c_{i−1} + c_i)/I_i + γ²(k_{i−1} + k_i)/I_i = 1 − a_i − u_i (+ γc_r/I_0).
  const Params& p = chain.params();
  const int N = chain.dof();
  rows_.resize(static_cast<std::size_t>(N));
  gamma_ = gamma;
  const double* k = p.stiffnesses.data();
  const double* c = p.dampings.data();
  double inv_prev = 0.0, upper_prev = 0.0;
  for (int i = 0; i < N - 1; ++i) {
    Row& row = rows_[static_cast<std::size_t>(i)];
    const double inv_inertia = 1.0 / p.inertias[static_cast<std::size_t>(i)];
    const double a = i > 0 ? -gamma * (c[i - 1] + gamma * k[i - 1]) * inv_inertia : 0.0;
    const double u = -gamma * (c[i] + gamma * k[i]) * inv_inertia;
    const double d = 1.0 - a - u + (i == 0 ? gamma * p.top_damping * inv_inertia : 0.0);
    row.from_twist_above = i > 0 ? gamma * k[i - 1] * inv_inertia : 0.0;
    row.from_twist_below = -gamma * k[i] * inv_inertia;
    row.upper = u;
    row.mult = a * inv_prev;
    const double pivot = d - row.mult * upper_prev;
    if (!trusted(pivot, std::max({std::fabs(a), std::fabs(d), std::fabs(u)}))) return false;
    row.inv_pivot = 1.0 / pivot;
    inv_prev = row.inv_pivot;
    upper_prev = u;
  }
  return true;
}

bool ChainNewtonMatrix::set_bit_row(const Chain& chain, const double* y, Mode mode) {
  // The bit's row (R0, R1, R2) = J(b, b−2 … b), θ_{N−2} eliminated as above.
  double R[3];
  bit_jacobian_row(chain, y, mode, R);
  const double g = gamma_;
  const double a = -g * R[0] - g * g * R[1];
  const double d = 1.0 - g * R[2] + g * g * R[1];
  const std::size_t last = rows_.size() - 1;
  const Row& above = rows_[last - 1];
  Row& row = rows_[last];
  row.from_twist_above = g * R[1];
  row.from_twist_below = 0.0;
  row.upper = 0.0;
  row.mult = a * above.inv_pivot;
  const double pivot = d - row.mult * above.upper;
  if (!trusted(pivot, std::max(std::fabs(a), std::fabs(d)))) return false;
  row.inv_pivot = 1.0 / pivot;
  return true;
}

void ChainNewtonMatrix::solve(const double* b, double* x) const {
  const int N = static_cast<int>(rows_.size());
  const Row* R = rows_.data();
  // Forward: z_i = rhs_i − mult_i z_{i−1}, kept in x's velocity slots (each b_ω is read
  // before its slot is written; the twist slots still hold b_θ).
  double z = b[0] + R[0].from_twist_below * b[1];
  x[0] = z;
  for (int i = 1; i < N - 1; ++i) {
    const int r = 2 * i;
    z = b[r] + R[i].from_twist_above * b[r - 1] + R[i].from_twist_below * b[r + 1] - R[i].mult * z;
    x[r] = z;
  }
  const int bit = 2 * N - 2;
  x[bit] = b[bit] + R[N - 1].from_twist_above * b[bit - 1] - R[N - 1].mult * z;
  // Backward: ω_i = (z_i − u_i ω_{i+1}) / pivot_i, then θ_i = b_θi + γ(ω_i − ω_{i+1}).
  double w_next = x[bit] * R[N - 1].inv_pivot;
  x[bit] = w_next;
  for (int i = N - 2; i >= 0; --i) {
    const double w = (x[2 * i] - R[i].upper * w_next) * R[i].inv_pivot;
    x[2 * i + 1] = b[2 * i + 1] + gamma_ * (w - w_next);
    x[2 * i] = w;
    w_next = w;
  }
}

namespace {

ChainSolverData* content(SUNLinearSolver S) { return static_cast<ChainSolverData*>(S->content); }

SUNLinearSolver_Type solver_type(SUNLinearSolver) { return SUNLINEARSOLVER_MATRIX_EMBEDDED; }

int solver_solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, sunrealtype) {
  ChainSolverData* d = content(S);
  sunrealtype tcur, gamma, rl1;
  N_Vector ypred, y, fn, zn1;
  void* user_data;
  if (CVodeGetNonlinearSystemData(d->cvode_mem, &tcur, &ypred, &y, &fn, &gamma, &rl1, &zn1,
                                  &user_data) != CV_SUCCESS) {
    return kLinSolFailUnrecoverable;
  }
  const Chain& chain = *d->chain;
  if (!d->valid || d->matrix.gamma() != gamma) {
    ++d->factorizations;
    d->valid = d->matrix.factor(chain, gamma);
    if (!d->valid) return kLinSolFailRecoverable;
  }
  // The bit's row at the predicted state, in the current mode: exact, at O(1).
  if (!d->matrix.set_bit_row(chain, N_VGetArrayPointer(ypred), *d->mode)) return kLinSolFailRecoverable;
  ++d->solves;
  d->matrix.solve(N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  return kLinSolSuccess;
}

// CVODES treats a matrix-embedded solver as an iterative one: without this operation it
// computes, before every solve, the mean of the error weights for a tolerance a direct solve
// never reads (a fill and a norm over the state). The weights are not needed either.
int solver_set_scaling(SUNLinearSolver, N_Vector, N_Vector) { return kLinSolSuccess; }

int solver_free(SUNLinearSolver S) {
  if (S == nullptr) return kLinSolSuccess;
  S->content = nullptr;  // the data belongs to the simulator
  SUNLinSolFreeEmpty(S);
  return kLinSolSuccess;
}

}  // namespace

SUNLinearSolver make_chain_solver(SUNContext ctx, ChainSolverData* data) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == nullptr) return nullptr;
  S->ops->gettype = solver_type;
  S->ops->solve = solver_solve;
  S->ops->setscalingvectors = solver_set_scaling;
  S->ops->free = solver_free;
  S->content = data;
  return S;
}

}  // namespace pydrill::detail
