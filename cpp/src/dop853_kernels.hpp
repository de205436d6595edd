// The arithmetic of a DOP853 step, on raw arrays: the trial step (stages,
// solution, error sums), the dense-output coefficients and their evaluation.
//
// Compiled twice: plain (x86-64 baseline SSE2) in integrator_dop853.cpp and
// with AVX2+FMA in integrator_dop853_avx2.cpp; the integrator picks one at run
// time. Everything here has internal linkage and calls nothing inline from a
// library header, so no AVX2 code can leak into the plain build through the
// linker's choice among duplicate inline functions.
#pragma once

#include <cstddef>
#include <utility>

#include "dop853_coefficients.hpp"

#ifndef PYDRILL_DOP853_VARIANT
#error "define PYDRILL_DOP853_VARIANT before including dop853_kernels.hpp"
#endif

namespace pydrill::detail::dop853 {

// f = rhs(ctx, t, y): the integrator's right-hand side.
using RhsFn = void (*)(void* ctx, double t, const double* y, double* f);

struct Kernels {
  // Stages 1–11 from (t, y) with row 0 = f(t, y) in k, the 8th-order solution
  // in ynew, f(t + h, ynew) in row 12, and the squared error sums.
  void (*trial_step)(const double* y, double* k, int m, double t, double h, double* tmp,
                     double* ynew, double rtol, double atol, RhsFn rhs, void* ctx, double* s5,
                     double* s3);
  // Stages 13–15 from (told, yold) and the 7 rows of the interpolant in dense.
  void (*prepare_dense)(const double* yold, const double* ynew, double* k, int m, double told,
                        double h, double* tmp, double* dense, RhsFn rhs, void* ctx);
  // y(told + x h) from the interpolant.
  void (*evaluate_dense)(const double* yold, const double* dense, int m, double x, double* out);
};

const Kernels& kernels_generic();
const Kernels& kernels_avx2();  // only where the compiler can target AVX2+FMA

namespace PYDRILL_DOP853_VARIANT {
namespace {

// The weights of one linear combination of stages, known at compile time: a
// zero weight costs nothing, and each output element is summed in a register
// from all stages at once (one pass over memory instead of one per stage).
template <int S>
struct StageWeights {  // row S of the Butcher matrix
  template <std::size_t J>
  static void add(double& acc, double k) {
    if constexpr (A[S][J] != 0.0) acc += A[S][J] * k;
  }
};

// out = base + h Σ_{j<N} w_j K_j.
template <typename W, std::size_t... J>
void weighted_sum(const double* base, const double* k, int m, double h, double* __restrict__ out,
                  std::index_sequence<J...>) {
  const double* const rows[] = {k + J * static_cast<std::size_t>(m)...};
  for (int i = 0; i < m; ++i) {
    double acc = 0.0;
    (W::template add<J>(acc, rows[J][i]), ...);
    out[i] = base[i] + h * acc;
  }
}

template <int S>
void stage(const double* base, double* k, int m, double t0, double h, double* tmp, RhsFn rhs,
           void* ctx) {
  weighted_sum<StageWeights<S>>(base, k, m, h, tmp, std::make_index_sequence<S>{});
  rhs(ctx, t0 + C[S] * h, tmp, k + static_cast<std::size_t>(S) * m);
}

template <std::size_t... S>
void stages(const double* base, double* k, int m, double t0, double h, double* tmp, RhsFn rhs,
            void* ctx, std::index_sequence<S...>) {
  (stage<static_cast<int>(S) + 1>(base, k, m, t0, h, tmp, rhs, ctx), ...);
}

inline double magnitude(double v) { return v < 0 ? -v : v; }

// The solution ŷ = y + h Σ b_j K_j and, in the same pass over the stages,
// Σ_i (e5_i/sc_i)², Σ_i (e3_i/sc_i)² with sc_i = atol + rtol·max(|y_i|, |ŷ_i|).
// The error weights of f(t + h, ŷ) are zero, so it is not needed yet.
static_assert(E5[kStages] == 0.0 && E3[kStages] == 0.0);
template <std::size_t... J>
void solution_and_error(const double* k, int m, const double* y, double h, double* ynew,
                        double rtol, double atol, double* s5, double* s3,
                        std::index_sequence<J...>) {
  const double* const rows[] = {k + J * static_cast<std::size_t>(m)...};
  double a5 = 0.0, a3 = 0.0;
  for (int i = 0; i < m; ++i) {
    double acc = 0.0, e5 = 0.0, e3 = 0.0;
    (
        [&] {
          const double kj = rows[J][i];
          if constexpr (B[J] != 0.0) acc += B[J] * kj;
          if constexpr (E5[J] != 0.0) e5 += E5[J] * kj;
          if constexpr (E3[J] != 0.0) e3 += E3[J] * kj;
        }(),
        ...);
    ynew[i] = y[i] + h * acc;
    const double a = magnitude(y[i]), b = magnitude(ynew[i]);
    const double scale = atol + (a > b ? a : b) * rtol;
    a5 += (e5 / scale) * (e5 / scale);
    a3 += (e3 / scale) * (e3 / scale);
  }
  *s5 = a5;
  *s3 = a3;
}

void trial_step(const double* y, double* k, int m, double t, double h, double* tmp, double* ynew,
                double rtol, double atol, RhsFn rhs, void* ctx, double* s5, double* s3) {
  stages(y, k, m, t, h, tmp, rhs, ctx, std::make_index_sequence<kStages - 1>{});
  solution_and_error(k, m, y, h, ynew, rtol, atol, s5, s3, std::make_index_sequence<kStages>{});
  rhs(ctx, t + h, ynew, k + static_cast<std::size_t>(kStages) * m);
}

// The 7 rows of the interpolant, all in one pass over the 16 stages.
template <std::size_t... J>
void dense_rows(const double* yold, const double* ynew, const double* f_old, const double* f_new,
                const double* k, int m, double h, double* F, std::index_sequence<J...>) {
  const double* const rows[] = {k + J * static_cast<std::size_t>(m)...};
  const auto at = [&](int r) { return F + static_cast<std::size_t>(r) * m; };
  double* __restrict__ o0 = at(0);
  double* __restrict__ o1 = at(1);
  double* __restrict__ o2 = at(2);
  double* __restrict__ o3 = at(3);
  double* __restrict__ o4 = at(4);
  double* __restrict__ o5 = at(5);
  double* __restrict__ o6 = at(6);
  for (int i = 0; i < m; ++i) {
    const double dy = ynew[i] - yold[i];
    o0[i] = dy;
    o1[i] = h * f_old[i] - dy;
    o2[i] = 2 * dy - h * (f_new[i] + f_old[i]);
  }
  for (int i = 0; i < m; ++i) {
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;
    (
        [&] {
          const double kj = rows[J][i];
          if constexpr (D[0][J] != 0.0) d0 += D[0][J] * kj;
          if constexpr (D[1][J] != 0.0) d1 += D[1][J] * kj;
          if constexpr (D[2][J] != 0.0) d2 += D[2][J] * kj;
          if constexpr (D[3][J] != 0.0) d3 += D[3][J] * kj;
        }(),
        ...);
    o3[i] = h * d0;
    o4[i] = h * d1;
    o5[i] = h * d2;
    o6[i] = h * d3;
  }
}

void prepare_dense(const double* yold, const double* ynew, double* k, int m, double told,
                   double h, double* tmp, double* dense, RhsFn rhs, void* ctx) {
  stage<13>(yold, k, m, told, h, tmp, rhs, ctx);
  stage<14>(yold, k, m, told, h, tmp, rhs, ctx);
  stage<15>(yold, k, m, told, h, tmp, rhs, ctx);
  const double* f_old = k;
  const double* f_new = k + static_cast<std::size_t>(kStages) * m;
  dense_rows(yold, ynew, f_old, f_new, k, m, h, dense,
             std::make_index_sequence<kStagesExtended>{});
}

void evaluate_dense(const double* yold, const double* dense, int m, double x, double* out) {
  static_assert(kInterpolatorPower == 7);
  const double u = 1.0 - x;
  const double* F[7];
  for (int r = 0; r < 7; ++r) F[r] = dense + static_cast<std::size_t>(r) * m;
  // scipy's Dop853DenseOutput nesting, alternate factors x and 1 − x, in one pass.
  for (int j = 0; j < m; ++j) {
    out[j] = yold[j] + x * (F[0][j] + u * (F[1][j] + x * (F[2][j] + u * (F[3][j] +
             x * (F[4][j] + u * (F[5][j] + x * F[6][j]))))));
  }
}

}  // namespace
}  // namespace PYDRILL_DOP853_VARIANT
}  // namespace pydrill::detail::dop853
