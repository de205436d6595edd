// The fast N_Vector's loop building blocks and raw-array reductions, shared by the files that
// define its operations (nvector_fast*.cpp); see nvector_fast.hpp for what the vector is.
//
// How the loops are written, and why:
//
//  * Every kernel first copies the length and the data pointers out of the
//    vector's content into locals. Otherwise a store to z[i] could (as far as
//    the compiler knows) modify the content struct, forcing a reload of the
//    length/pointers every iteration and blocking vectorisation.
//
//  * Element-wise kernels (z[i] = f(x[i], y[i])) must stay correct when the
//    output is the same array as an input: CVODES calls e.g.
//    N_VLinearSum(a, x, b, y, y) and N_VProd(x, y, x). `restrict` would be a
//    lie there, so these loops use PYDRILL_IVDEP instead: it tells the
//    compiler there are no dependences *between iterations*, which is true
//    for identical arrays (z[i] only depends on x[i], y[i]), so it vectorises
//    without a run-time overlap check. (SUNDIALS vectors are either the same
//    array or disjoint; they never partially overlap.)
//
//  * `restrict` is used only where the output is proven distinct from every
//    input (the fused linear-combination kernel checks this at run time and
//    falls back otherwise). Read-only pointers may alias each other freely.
//
//  * Reductions (sums) use several independent partial sums, see sum_reduce.
//
//  * Operations CVODES only needs with inequality constraints (InvTest,
//    ConstrMask, MinQuotient) are plain ports of NVECTOR_SERIAL's loops: they
//    are not hot, and their branchy semantics are easiest to keep exact that
//    way.
#pragma once

#include "nvector_fast.hpp"

#include <sundials/sundials_math.h>
#if SUNDIALS_VERSION_MAJOR >= 7
#include <sundials/sundials_errors.h>  // SUNErrCode values
#endif

#if defined(__GNUC__) || defined(__clang__)
#define PYDRILL_RESTRICT __restrict__
#elif defined(_MSC_VER)
#define PYDRILL_RESTRICT __restrict
#else
#define PYDRILL_RESTRICT
#endif

#if defined(__clang__)
#define PYDRILL_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define PYDRILL_IVDEP _Pragma("GCC ivdep")
#elif defined(_MSC_VER)
#define PYDRILL_IVDEP __pragma(loop(ivdep))
#else
#define PYDRILL_IVDEP
#endif

// Compiled twice where the compiler can target AVX2: plain (x86-64 baseline SSE2), and by
// nvector_fast_avx2.cpp with -mavx2 (4 doubles a vector instead of 2; no FMA, so every
// operation rounds exactly as in the plain build), which defines PYDRILL_NVEC_VARIANT and
// takes only the kernels and their ops table. make_fast_vector attaches the AVX2 table when
// the CPU has AVX2, and clones keep their original's table. As for DOP853's kernels (see
// dop853_kernels.hpp), no AVX2 code may reach the plain build through the linker: everything
// in this header and nvector_fast_linear.hpp has internal linkage (an anonymous namespace),
// the operations (nvector_fast_ops.hpp) are named in their variant's namespace, and none of
// it calls anything inline from a library header.
#ifndef PYDRILL_NVEC_VARIANT
#define PYDRILL_NVEC_VARIANT generic
#define PYDRILL_NVEC_MAIN 1
#endif

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {
namespace {

using real = sunrealtype;
using index_t = sunindextype;

// Fused / vector-array operations return an error code: plain int in 6.x,
// SUNErrCode (a typedef of int) in 7.x.
#if SUNDIALS_VERSION_MAJOR >= 7
using err_t = SUNErrCode;
constexpr err_t kSuccess = SUN_SUCCESS;
constexpr err_t kBadArg = SUN_ERR_ARG_OUTOFRANGE;
#else
using err_t = int;
constexpr err_t kSuccess = 0;
constexpr err_t kBadArg = -1;  // what NVECTOR_SERIAL 6.x returns for nvec < 1
#endif

constexpr real kZero = static_cast<real>(0.0);
constexpr real kHalf = static_cast<real>(0.5);
constexpr real kOne = static_cast<real>(1.0);
constexpr real kOnePt5 = static_cast<real>(1.5);

struct Content {
  index_t length = 0;
  real* data = nullptr;   // the array the operations use
  real* owned = nullptr;  // storage we allocated (freed on destroy). `data`
                          // differs from it after N_VSetArrayPointer, which
                          // CVODES' DQ Jacobian uses to point an empty clone
                          // at a matrix column; keeping both means such user
                          // arrays are never freed by us and our own array
                          // is never leaked.
};

inline Content* content(N_Vector v) noexcept { return static_cast<Content*>(v->content); }
inline index_t len(N_Vector v) noexcept { return content(v)->length; }
inline real* dat(N_Vector v) noexcept { return content(v)->data; }

// ---------------------------------------------------------------------------
// Loop building blocks
// ---------------------------------------------------------------------------

// z[i] = f(x[i]); z may be x.
template <class F>
inline void map1(index_t n, const real* x, real* z, F f) noexcept {
  PYDRILL_IVDEP
  for (index_t i = 0; i < n; ++i) z[i] = f(x[i]);
}

// z[i] = f(x[i], y[i]); z may be x and/or y.
template <class F>
inline void map2(index_t n, const real* x, const real* y, real* z, F f) noexcept {
  PYDRILL_IVDEP
  for (index_t i = 0; i < n; ++i) z[i] = f(x[i], y[i]);
}

// Number of independent partial results in the reductions. With a single
// accumulator every add waits for the previous one (FP-add latency, ~4
// cycles), and without -ffast-math the compiler may not reassociate the sum
// itself, so `s += t(i)` runs neither in parallel nor in SIMD. With 8
// explicit partial sums the adds are independent and g++'s SLP vectoriser
// packs them into SIMD registers (4x2 doubles with SSE2). Cost: the
// summation order differs from NVECTOR_SERIAL's, so sums agree to rounding
// rather than bit for bit (for n < kLanes the order, hence the result, is
// identical). Define PYDRILL_NVEC_EXACT_REDUCTIONS to sum sequentially, in
// NVECTOR_SERIAL's order, when bit-for-bit agreement matters more.
#ifdef PYDRILL_NVEC_EXACT_REDUCTIONS
constexpr int kLanes = 1;
#else
constexpr int kLanes = 8;
#endif
static_assert((kLanes & (kLanes - 1)) == 0, "kLanes must be a power of two");

// sum_{i<n} t(i)
template <class T>
inline real sum_reduce(index_t n, T t) noexcept {
  real s[kLanes] = {};
  index_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (int l = 0; l < kLanes; ++l) s[l] += t(i + l);
  }
  for (; i < n; ++i) s[0] += t(i);
  // Pairwise combination (with kLanes == 1: just s[0], the sequential sum).
  for (int width = kLanes / 2; width > 0; width /= 2) {
    for (int l = 0; l < width; ++l) s[l] += s[l + width];
  }
  return s[0];
}

// Running extremum over t(first..n-1) starting from `init`, where
// better(a, b) says a should replace b. Partial extrema are exact, so unlike
// sums the result equals the sequential one (NaNs are skipped the same way:
// a comparison with NaN is false, so a NaN never replaces a number).
template <class T, class Better>
inline real extremum_reduce(index_t first, index_t n, real init, T t, Better better) noexcept {
  real m[kLanes];
  for (int l = 0; l < kLanes; ++l) m[l] = init;
  index_t i = first;
  for (; i + kLanes <= n; i += kLanes) {
    for (int l = 0; l < kLanes; ++l) {
      const real v = t(i + l);
      m[l] = better(v, m[l]) ? v : m[l];
    }
  }
  for (; i < n; ++i) {
    const real v = t(i);
    m[0] = better(v, m[0]) ? v : m[0];
  }
  real r = m[0];
  for (int l = 1; l < kLanes; ++l) r = better(m[l], r) ? m[l] : r;
  return r;
}

// ---------------------------------------------------------------------------
// Reductions on raw arrays
// ---------------------------------------------------------------------------

inline real dot(index_t n, const real* PYDRILL_RESTRICT x, const real* PYDRILL_RESTRICT y) noexcept {
  return sum_reduce(n, [=](index_t i) { return x[i] * y[i]; });
}

inline real wsqrsum(index_t n, const real* PYDRILL_RESTRICT x, const real* PYDRILL_RESTRICT w) noexcept {
  return sum_reduce(n, [=](index_t i) {
    const real p = x[i] * w[i];
    return p * p;
  });
}

// Masked entries contribute exactly 0 (a select, not a multiply by the mask,
// so an inf/NaN in a masked-out entry is ignored, as in NVECTOR_SERIAL).
// g++ turns the select into a branch per element rather than a blend; that
// is acceptable because the masked norms are IDA's (CVODES does not use
// them).
inline real wsqrsum_mask(index_t n, const real* PYDRILL_RESTRICT x, const real* PYDRILL_RESTRICT w,
                         const real* PYDRILL_RESTRICT id) noexcept {
  return sum_reduce(n, [=](index_t i) {
    const real p = id[i] > kZero ? x[i] * w[i] : kZero;
    return p * p;
  });
}

// NVECTOR_SERIAL: sqrt(sum / N), with SUNRsqrt's "<= 0 gives 0".
inline real wrms_from_sum(real sum, index_t n) noexcept { return SUNRsqrt(sum / n); }

}  // namespace
}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
