#include "chain_solver.hpp"
#include "sundials_compat.hpp"

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>

#include <algorithm>
#include <cmath>

namespace pydrill::detail {

bool factor_band(std::vector<double>& a, int n, double gamma) {
  // M = I − γJ, formed in place.
  for (int r = 0; r < n; ++r) {
    double* row = &a[5 * static_cast<std::size_t>(r)];
    for (int d = 0; d < 5; ++d) row[d] *= -gamma;
    row[2] += 1.0;
  }
  // Gaussian elimination without pivoting: for this mechanical chain M is
  // I plus γ times a matrix whose symmetric part (in energy coordinates) is
  // dissipative, which keeps pivots away from zero; a tiny pivot is reported
  // as a recoverable failure so CVODES retries with a smaller step. The
  // diagonal keeps 1/pivot: the solves, run several times per factorisation,
  // then multiply where they would divide (a division's latency sat on the
  // back substitution's critical path, a third of a long string's run time).
  for (int k = 0; k < n; ++k) {
    const double piv = a[5 * k + 2];
    double scale = 0.0;
    for (int d = 0; d < 5; ++d) scale = std::max(scale, std::fabs(a[5 * k + d]));
    if (!(std::fabs(piv) > 1e-14 * scale) || !std::isfinite(piv)) return false;
    const double inv = 1.0 / piv;
    const int last = std::min(k + 2, n - 1);
    for (int r = k + 1; r <= last; ++r) {
      double& lrk = a[5 * r + (k - r + 2)];
      if (lrk == 0.0) continue;
      lrk *= inv;
      for (int c = k + 1; c <= last; ++c) a[5 * r + (c - r + 2)] -= lrk * a[5 * k + (c - k + 2)];
    }
    a[5 * k + 2] = inv;
  }
  return true;
}

void solve_band(const std::vector<double>& lu, int n, const double* b, double* x) {
  const double* a = lu.data();
  if (x != b) std::copy(b, b + n, x);
  // Row r holds (l_{r,r-2}, l_{r,r-1}, 1/u_rr, u_{r,r+1}, u_{r,r+2}).
  if (n > 1) x[1] -= a[5 + 1] * x[0];
  for (int r = 2; r < n; ++r) {  // forward: L z = b (unit diagonal)
    const double* row = a + 5 * r;
    x[r] -= row[0] * x[r - 2] + row[1] * x[r - 1];
  }
  x[n - 1] *= a[5 * (n - 1) + 2];
  if (n > 1) x[n - 2] = (x[n - 2] - a[5 * (n - 2) + 3] * x[n - 1]) * a[5 * (n - 2) + 2];
  for (int r = n - 3; r >= 0; --r) {  // backward: U x = z
    const double* row = a + 5 * r;
    x[r] = (x[r] - row[3] * x[r + 1] - row[4] * x[r + 2]) * row[2];
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
  const int n = chain.size();
  const double* yp = N_VGetArrayPointer(ypred);
  const double slope = chain.friction().slip_slope(yp[chain.bit_index()]);
  const bool fresh = d->valid && d->gamma == gamma && d->factored_mode == *d->mode &&
                     std::fabs(slope - d->slope) <= 1e-3 * std::fabs(d->slope) + 1e-300;
  if (!fresh) {
    d->lu.resize(5 * static_cast<std::size_t>(n));
    chain.jacobian_band(yp, *d->mode, d->lu.data());
    ++d->factorizations;
    if (!factor_band(d->lu, n, gamma)) {
      d->valid = false;
      return kLinSolFailRecoverable;
    }
    d->valid = true;
    d->gamma = gamma;
    d->slope = slope;
    d->factored_mode = *d->mode;
  }
  ++d->solves;
  solve_band(d->lu, n, N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  return kLinSolSuccess;
}

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
  S->ops->free = solver_free;
  S->content = data;
  return S;
}

}  // namespace pydrill::detail
