// Optimised serial N_Vector; see nvector_fast.hpp for what and why.
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
#include "nvector_fast.hpp"

#include <sundials/sundials_math.h>
#if SUNDIALS_VERSION_MAJOR >= 7
#include <sundials/sundials_errors.h>  // SUNErrCode values
#endif

#include <cmath>
#include <cstdio>
#include <new>

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

// Compiled twice where the compiler can target AVX2: plain here (x86-64 baseline SSE2), and
// by nvector_fast_avx2.cpp with -mavx2 (4 doubles a vector instead of 2; no FMA, so every
// operation rounds exactly as in the plain build), which defines PYDRILL_NVEC_VARIANT and
// takes only the kernels and their ops table. make_fast_vector attaches the AVX2 table when
// the CPU has AVX2, and clones keep their original's table. As for DOP853's kernels (see
// dop853_kernels.hpp), everything below has internal linkage and calls nothing inline from a
// library header, so no AVX2 code can reach the plain build through the linker.
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
// Linear sum, shared by N_VLinearSum and N_VLinearSumVectorArray.
//
// Reproduces NVECTOR_SERIAL's case analysis exactly (same formula, hence the
// same rounding, in every case). `z_is_y` / `z_is_x` are the identity tests
// NVECTOR_SERIAL makes: on the vectors for N_VLinearSum, on the arrays for
// the vector-array version.
// ---------------------------------------------------------------------------

// y <- a x + y (BLAS axpy); x may be y.
inline void axpy(index_t n, real a, const real* x, real* y) noexcept {
  if (a == kOne) {
    map2(n, x, y, y, [](real xi, real yi) { return yi + xi; });
  } else if (a == -kOne) {
    map2(n, x, y, y, [](real xi, real yi) { return yi - xi; });
  } else {
    map2(n, x, y, y, [a](real xi, real yi) { return yi + a * xi; });
  }
}

void linear_sum(index_t n, real a, const real* x, real b, const real* y, real* z, bool z_is_x,
                bool z_is_y) noexcept {
  if (b == kOne && z_is_y) {  // y <- a x + y
    axpy(n, a, x, z);
    return;
  }
  if (a == kOne && z_is_x) {  // x <- b y + x
    axpy(n, b, y, z);
    return;
  }
  if (a == kOne && b == kOne) {
    map2(n, x, y, z, [](real xi, real yi) { return xi + yi; });
    return;
  }
  if (a == kOne && b == -kOne) {
    map2(n, x, y, z, [](real xi, real yi) { return xi - yi; });
    return;
  }
  if (a == -kOne && b == kOne) {
    map2(n, x, y, z, [](real xi, real yi) { return yi - xi; });
    return;
  }
  if (a == kOne) {  // b y + x (b is "other", possibly 0)
    map2(n, x, y, z, [b](real xi, real yi) { return (b * yi) + xi; });
    return;
  }
  if (b == kOne) {  // a x + y
    map2(n, x, y, z, [a](real xi, real yi) { return (a * xi) + yi; });
    return;
  }
  if (a == -kOne) {  // b y - x
    map2(n, x, y, z, [b](real xi, real yi) { return (b * yi) - xi; });
    return;
  }
  if (b == -kOne) {  // a x - y
    map2(n, x, y, z, [a](real xi, real yi) { return (a * xi) - yi; });
    return;
  }
  if (a == b) {  // a (x + y)
    map2(n, x, y, z, [a](real xi, real yi) { return a * (xi + yi); });
    return;
  }
  if (a == -b) {  // a (x - y)
    map2(n, x, y, z, [a](real xi, real yi) { return a * (xi - yi); });
    return;
  }
  map2(n, x, y, z, [a, b](real xi, real yi) { return (a * xi) + (b * yi); });
}

// z = c x, with NVECTOR_SERIAL's special cases (z_is_x: in place).
void scale(index_t n, real c, const real* x, real* z, bool z_is_x) noexcept {
  if (z_is_x) {
    map1(n, z, z, [c](real zi) { return zi * c; });
  } else if (c == kOne) {
    map1(n, x, z, [](real xi) { return xi; });
  } else if (c == -kOne) {
    map1(n, x, z, [](real xi) { return -xi; });
  } else {
    map1(n, x, z, [c](real xi) { return c * xi; });
  }
}

// ---------------------------------------------------------------------------
// Linear combination z = sum_k c[k] X[k], shared by N_VLinearCombination and
// N_VLinearCombinationVectorArray.
//
// NVECTOR_SERIAL makes one pass over z per term (z = c0 x0; z += c1 x1; ...).
// We fuse up to 1 + kMaxTerms terms per pass, evaluating each element in the
// same left-to-right order, so results are identical while z is read and
// written nsum/4 times instead of nsum times.
// ---------------------------------------------------------------------------

enum class Start { Accumulate, ScaleZ, SetFromX0 };  // z[j] | z[j]*s | s*x0[j]
constexpr int kMaxTerms = 4;

// z[j] = start(j) + c[0]*x[0][j] + ... + c[M-1]*x[M-1][j], left to right.
// z must not alias any x[k] or x0 (checked by the caller): hence restrict.
template <Start S, int M>
void lc_block(index_t n, real* PYDRILL_RESTRICT z, real s, const real* PYDRILL_RESTRICT x0,
              const real* c, const real* const* x) noexcept {
  const real c0 = M > 0 ? c[0] : kZero, c1 = M > 1 ? c[1] : kZero;
  const real c2 = M > 2 ? c[2] : kZero, c3 = M > 3 ? c[3] : kZero;
  const real* PYDRILL_RESTRICT p0 = M > 0 ? x[0] : nullptr;
  const real* PYDRILL_RESTRICT p1 = M > 1 ? x[1] : nullptr;
  const real* PYDRILL_RESTRICT p2 = M > 2 ? x[2] : nullptr;
  const real* PYDRILL_RESTRICT p3 = M > 3 ? x[3] : nullptr;
  for (index_t j = 0; j < n; ++j) {
    real acc;
    if constexpr (S == Start::Accumulate) {
      acc = z[j];
    } else if constexpr (S == Start::ScaleZ) {
      acc = z[j] * s;
    } else {
      acc = s * x0[j];
    }
    if constexpr (M > 0) acc += c0 * p0[j];
    if constexpr (M > 1) acc += c1 * p1[j];
    if constexpr (M > 2) acc += c2 * p2[j];
    if constexpr (M > 3) acc += c3 * p3[j];
    z[j] = acc;
  }
}

template <Start S>
void lc_block_dispatch(int m, index_t n, real* z, real s, const real* x0, const real* c,
                       const real* const* x) noexcept {
  switch (m) {
    case 0: lc_block<S, 0>(n, z, s, x0, c, x); break;
    case 1: lc_block<S, 1>(n, z, s, x0, c, x); break;
    case 2: lc_block<S, 2>(n, z, s, x0, c, x); break;
    case 3: lc_block<S, 3>(n, z, s, x0, c, x); break;
    default: lc_block<S, 4>(n, z, s, x0, c, x); break;
  }
}

// z = sum_{k<nsum} c[k] * xp(k), nsum >= 3 (smaller counts are routed to
// scale / linear_sum by the callers, as NVECTOR_SERIAL does). xp(k) returns
// the data pointer of term k.
//
// NVECTOR_SERIAL's cases: if X[0] is z, then z += ... (c0 == 1) or
// z = c0 z + ...; otherwise z = c0 X[0] + .... We test data pointers rather
// than vector handles: when X[0] is a different vector sharing z's array,
// NVECTOR_SERIAL's general path computes c0*z[j] too, so results agree.
template <class XP>
void linear_combination(index_t n, int nsum, const real* c, XP xp, real* z) noexcept {
  bool later_alias = false;  // some X[k], k >= 1, shares z's array
  for (int k = 1; k < nsum; ++k) later_alias = later_alias || (xp(k) == z);
  const real* x0 = xp(0);

  if (later_alias) {
    // Unusual; replicate NVECTOR_SERIAL's term-by-term passes exactly, since
    // a later term then reads partially updated z.
    if (x0 == z) {
      if (c[0] != kOne) map1(n, z, z, [s = c[0]](real zi) { return zi * s; });
    } else {
      map1(n, x0, z, [s = c[0]](real xi) { return s * xi; });
    }
    for (int k = 1; k < nsum; ++k) {
      map2(n, xp(k), z, z, [ck = c[k]](real xi, real zi) { return zi + ck * xi; });
    }
    return;
  }

  const real* ptrs[kMaxTerms];
  int k = 1;
  int m = 0;
  while (k + m < nsum && m < kMaxTerms) {
    ptrs[m] = xp(k + m);
    ++m;
  }
  if (x0 == z) {
    if (c[0] == kOne) {
      lc_block_dispatch<Start::Accumulate>(m, n, z, c[0], nullptr, c + k, ptrs);
    } else {
      lc_block_dispatch<Start::ScaleZ>(m, n, z, c[0], nullptr, c + k, ptrs);
    }
  } else {
    lc_block_dispatch<Start::SetFromX0>(m, n, z, c[0], x0, c + k, ptrs);
  }
  k += m;
  while (k < nsum) {
    m = 0;
    while (k + m < nsum && m < kMaxTerms) {
      ptrs[m] = xp(k + m);
      ++m;
    }
    lc_block_dispatch<Start::Accumulate>(m, n, z, kOne, nullptr, c + k, ptrs);
    k += m;
  }
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

// ---------------------------------------------------------------------------
// N_Vector operations
// ---------------------------------------------------------------------------

N_Vector_ID op_getvectorid(N_Vector) noexcept { return SUNDIALS_NVEC_CUSTOM; }

sunindextype op_getlength(N_Vector v) noexcept { return len(v); }

void op_destroy(N_Vector v) noexcept;
N_Vector op_cloneempty(N_Vector w) noexcept;

N_Vector op_clone(N_Vector w) noexcept {
  N_Vector v = op_cloneempty(w);
  if (v == nullptr) return nullptr;
  const index_t n = len(w);
  if (n > 0) {
    real* data = new (std::nothrow) real[static_cast<size_t>(n)]();
    if (data == nullptr) {
      op_destroy(v);
      return nullptr;
    }
    content(v)->owned = data;
    content(v)->data = data;
  }
  return v;
}

N_Vector op_cloneempty(N_Vector w) noexcept {
  if (w == nullptr) return nullptr;
  N_Vector v = N_VNewEmpty(w->sunctx);
  if (v == nullptr) return nullptr;
  if (N_VCopyOps(w, v) != 0) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  auto* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = len(w);
  v->content = c;
  return v;
}

void op_destroy(N_Vector v) noexcept {
  if (v == nullptr) return;
  if (v->content != nullptr) {
    Content* c = content(v);
    delete[] c->owned;
    delete c;
    v->content = nullptr;
  }
  N_VFreeEmpty(v);  // frees the ops table and the vector struct
}

void op_space(N_Vector v, sunindextype* lrw, sunindextype* liw) noexcept {
  if (lrw != nullptr) *lrw = len(v);
  if (liw != nullptr) *liw = 1;
}

sunrealtype* op_getarraypointer(N_Vector v) noexcept { return dat(v); }

// Like NVECTOR_SERIAL: ignored for zero-length vectors; never frees anything
// (our own array, if any, is released on destroy).
void op_setarraypointer(sunrealtype* v_data, N_Vector v) noexcept {
  if (len(v) > 0) content(v)->data = v_data;
}

void op_linearsum(real a, N_Vector x, real b, N_Vector y, N_Vector z) noexcept {
  linear_sum(len(x), a, dat(x), b, dat(y), dat(z), z == x, z == y);
}

void op_const(real c, N_Vector z) noexcept {
  const index_t n = len(z);
  real* zd = dat(z);
  for (index_t i = 0; i < n; ++i) zd[i] = c;
}

void op_prod(N_Vector x, N_Vector y, N_Vector z) noexcept {
  map2(len(x), dat(x), dat(y), dat(z), [](real a, real b) { return a * b; });
}

void op_div(N_Vector x, N_Vector y, N_Vector z) noexcept {
  map2(len(x), dat(x), dat(y), dat(z), [](real a, real b) { return a / b; });
}

void op_scale(real c, N_Vector x, N_Vector z) noexcept { scale(len(x), c, dat(x), dat(z), z == x); }

void op_abs(N_Vector x, N_Vector z) noexcept {
  map1(len(x), dat(x), dat(z), [](real a) { return SUNRabs(a); });
}

void op_inv(N_Vector x, N_Vector z) noexcept {
  map1(len(x), dat(x), dat(z), [](real a) { return kOne / a; });
}

void op_addconst(N_Vector x, real b, N_Vector z) noexcept {
  map1(len(x), dat(x), dat(z), [b](real a) { return a + b; });
}

real op_dotprod(N_Vector x, N_Vector y) noexcept { return dot(len(x), dat(x), dat(y)); }

real op_maxnorm(N_Vector x) noexcept {
  const real* xd = dat(x);
  return extremum_reduce(
      0, len(x), kZero, [xd](index_t i) { return SUNRabs(xd[i]); },
      [](real a, real b) { return a > b; });
}

real op_wsqrsumlocal(N_Vector x, N_Vector w) noexcept { return wsqrsum(len(x), dat(x), dat(w)); }

real op_wsqrsummasklocal(N_Vector x, N_Vector w, N_Vector id) noexcept {
  return wsqrsum_mask(len(x), dat(x), dat(w), dat(id));
}

real op_wrmsnorm(N_Vector x, N_Vector w) noexcept {
  return wrms_from_sum(op_wsqrsumlocal(x, w), len(x));
}

real op_wrmsnormmask(N_Vector x, N_Vector w, N_Vector id) noexcept {
  return wrms_from_sum(op_wsqrsummasklocal(x, w, id), len(x));
}

// As NVECTOR_SERIAL: starts from x[0] (so requires length >= 1).
real op_min(N_Vector x) noexcept {
  const real* xd = dat(x);
  return extremum_reduce(
      1, len(x), xd[0], [xd](index_t i) { return xd[i]; }, [](real a, real b) { return a < b; });
}

real op_wl2norm(N_Vector x, N_Vector w) noexcept {
  return SUNRsqrt(wsqrsum(len(x), dat(x), dat(w)));
}

real op_l1norm(N_Vector x) noexcept {
  const real* xd = dat(x);
  return sum_reduce(len(x), [xd](index_t i) { return SUNRabs(xd[i]); });
}

void op_compare(real c, N_Vector x, N_Vector z) noexcept {
  map1(len(x), dat(x), dat(z), [c](real a) { return SUNRabs(a) >= c ? kOne : kZero; });
}

// z[i] = 1/x[i] where x[i] != 0 (other z[i] untouched); false if any x[i] == 0.
sunbooleantype op_invtest(N_Vector x, N_Vector z) noexcept {
  const index_t n = len(x);
  const real* xd = dat(x);
  real* zd = dat(z);
  sunbooleantype no_zero_found = SUNTRUE;
  for (index_t i = 0; i < n; ++i) {
    if (xd[i] == kZero) {
      no_zero_found = SUNFALSE;
    } else {
      zd[i] = kOne / xd[i];
    }
  }
  return no_zero_found;
}

// m[i] = 1 where x[i] violates constraint c[i] (|c| = 2: strict sign, |c| = 1:
// non-strict sign, 0: none), else 0; false if any constraint is violated.
// Statement order as in NVECTOR_SERIAL (m[i] is cleared before c[i], x[i]
// are read), which matters only if m aliases c or x.
sunbooleantype op_constrmask(N_Vector c, N_Vector x, N_Vector m) noexcept {
  const index_t n = len(x);
  const real* cd = dat(c);
  const real* xd = dat(x);
  real* md = dat(m);
  real temp = kZero;
  for (index_t i = 0; i < n; ++i) {
    md[i] = kZero;
    if (cd[i] == kZero) continue;
    const bool violated = (SUNRabs(cd[i]) > kOnePt5 && xd[i] * cd[i] <= kZero) ||
                          (SUNRabs(cd[i]) > kHalf && xd[i] * cd[i] < kZero);
    if (violated) temp = md[i] = kOne;
  }
  return (temp == kOne) ? SUNFALSE : SUNTRUE;
}

// min over i with denom[i] != 0 of num[i]/denom[i]; SUN_BIG_REAL if none.
real op_minquotient(N_Vector num, N_Vector denom) noexcept {
  const index_t n = len(num);
  const real* nd = dat(num);
  const real* dd = dat(denom);
  bool not_even_once = true;
  real min = SUN_BIG_REAL;
  for (index_t i = 0; i < n; ++i) {
    if (dd[i] == kZero) continue;
    const real q = nd[i] / dd[i];
    if (not_even_once) {
      min = q;
      not_even_once = false;
    } else {
      min = SUNMIN(min, q);
    }
  }
  return min;
}

// ---- fused operations ------------------------------------------------------

err_t op_linearcombination(int nvec, real* c, N_Vector* X, N_Vector z) noexcept {
  if (nvec < 1) return kBadArg;
  if (nvec == 1) {
    op_scale(c[0], X[0], z);
    return kSuccess;
  }
  if (nvec == 2) {
    op_linearsum(c[0], X[0], c[1], X[1], z);
    return kSuccess;
  }
  linear_combination(len(z), nvec, c, [X](int k) -> const real* { return dat(X[k]); }, dat(z));
  return kSuccess;
}

// Z[i] = a[i] x + Y[i]. One pass per output (x stays in cache); the loops
// are element-wise, so Z[i] may be Y[i] (or even x).
err_t op_scaleaddmulti(int nvec, real* a, N_Vector x, N_Vector* Y, N_Vector* Z) noexcept {
  if (nvec < 1) return kBadArg;
  if (nvec == 1) {
    op_linearsum(a[0], x, kOne, Y[0], Z[0]);
    return kSuccess;
  }
  const index_t n = len(x);
  const real* xd = dat(x);
  if (Y == Z) {
    for (int i = 0; i < nvec; ++i) {
      map2(n, xd, dat(Y[i]), dat(Y[i]), [ai = a[i]](real xj, real yj) { return yj + ai * xj; });
    }
    return kSuccess;
  }
  for (int i = 0; i < nvec; ++i) {
    map2(n, xd, dat(Y[i]), dat(Z[i]), [ai = a[i]](real xj, real yj) { return ai * xj + yj; });
  }
  return kSuccess;
}

err_t op_dotprodmulti(int nvec, N_Vector x, N_Vector* Y, real* dotprods) noexcept {
  if (nvec < 1) return kBadArg;
  const index_t n = len(x);
  const real* xd = dat(x);
  for (int i = 0; i < nvec; ++i) dotprods[i] = dot(n, xd, dat(Y[i]));
  return kSuccess;
}

// ---- vector array operations -----------------------------------------------

err_t op_linearsumvectorarray(int nvec, real a, N_Vector* X, real b, N_Vector* Y,
                              N_Vector* Z) noexcept {
  if (nvec < 1) return kBadArg;
  if (nvec == 1) {
    op_linearsum(a, X[0], b, Y[0], Z[0]);
    return kSuccess;
  }
  // NVECTOR_SERIAL tests the arrays (Z == Y, Z == X), not the vectors.
  const index_t n = len(Z[0]);
  for (int i = 0; i < nvec; ++i) {
    linear_sum(n, a, dat(X[i]), b, dat(Y[i]), dat(Z[i]), Z == X, Z == Y);
  }
  return kSuccess;
}

err_t op_scalevectorarray(int nvec, real* c, N_Vector* X, N_Vector* Z) noexcept {
  if (nvec < 1) return kBadArg;
  if (nvec == 1) {
    op_scale(c[0], X[0], Z[0]);
    return kSuccess;
  }
  // No c == +-1 special cases here in NVECTOR_SERIAL (same values anyway).
  const index_t n = len(Z[0]);
  for (int i = 0; i < nvec; ++i) {
    if (X == Z) {
      map1(n, dat(X[i]), dat(X[i]), [ci = c[i]](real xj) { return xj * ci; });
    } else {
      map1(n, dat(X[i]), dat(Z[i]), [ci = c[i]](real xj) { return ci * xj; });
    }
  }
  return kSuccess;
}

err_t op_constvectorarray(int nvec, real c, N_Vector* Z) noexcept {
  if (nvec < 1) return kBadArg;
  for (int i = 0; i < nvec; ++i) op_const(c, Z[i]);
  return kSuccess;
}

err_t op_wrmsnormvectorarray(int nvec, N_Vector* X, N_Vector* W, real* nrm) noexcept {
  if (nvec < 1) return kBadArg;
  const index_t n = len(X[0]);
  for (int i = 0; i < nvec; ++i) nrm[i] = wrms_from_sum(wsqrsum(n, dat(X[i]), dat(W[i])), n);
  return kSuccess;
}

err_t op_wrmsnormmaskvectorarray(int nvec, N_Vector* X, N_Vector* W, N_Vector id,
                                 real* nrm) noexcept {
  if (nvec < 1) return kBadArg;
  const index_t n = len(X[0]);
  const real* idd = dat(id);
  for (int i = 0; i < nvec; ++i) {
    nrm[i] = wrms_from_sum(wsqrsum_mask(n, dat(X[i]), dat(W[i]), idd), n);
  }
  return kSuccess;
}

// Z[j][i] = a[j] X[i] + Y[j][i] (j < nsum sums, i < nvec vectors).
err_t op_scaleaddmultivectorarray(int nvec, int nsum, real* a, N_Vector* X, N_Vector** Y,
                                  N_Vector** Z) noexcept {
  if (nvec < 1 || nsum < 1) return kBadArg;
  if (nvec == 1 && nsum == 1) {
    op_linearsum(a[0], X[0], kOne, Y[0][0], Z[0][0]);
    return kSuccess;
  }
  if (nvec > 1 && nsum == 1) return op_linearsumvectorarray(nvec, a[0], X, kOne, Y[0], Z[0]);
  // NVECTOR_SERIAL's nvec == 1 path goes through N_VScaleAddMulti with
  // freshly gathered (hence distinct) Y and Z arrays, i.e. never in place.
  const bool in_place = nvec > 1 && Y == Z;
  const index_t n = len(X[0]);
  for (int i = 0; i < nvec; ++i) {
    const real* xd = dat(X[i]);
    for (int j = 0; j < nsum; ++j) {
      if (in_place) {
        map2(n, xd, dat(Y[j][i]), dat(Y[j][i]),
             [aj = a[j]](real xk, real yk) { return yk + aj * xk; });
      } else {
        map2(n, xd, dat(Y[j][i]), dat(Z[j][i]),
             [aj = a[j]](real xk, real yk) { return aj * xk + yk; });
      }
    }
  }
  return kSuccess;
}

// Z[j] = sum_i c[i] X[i][j] (i < nsum terms, j < nvec vectors).
err_t op_linearcombinationvectorarray(int nvec, int nsum, real* c, N_Vector** X,
                                      N_Vector* Z) noexcept {
  if (nvec < 1 || nsum < 1) return kBadArg;
  if (nvec == 1) {
    if (nsum == 1) {
      op_scale(c[0], X[0][0], Z[0]);
    } else if (nsum == 2) {
      op_linearsum(c[0], X[0][0], c[1], X[1][0], Z[0]);
    } else {
      linear_combination(len(Z[0]), nsum, c, [X](int k) -> const real* { return dat(X[k][0]); },
                         dat(Z[0]));
    }
    return kSuccess;
  }
  const index_t n = len(Z[0]);
  if (nsum == 1) {  // NVECTOR_SERIAL: N_VScaleVectorArray with c[0] for all
    for (int j = 0; j < nvec; ++j) {
      if (X[0] == Z) {
        map1(n, dat(Z[j]), dat(Z[j]), [s = c[0]](real zk) { return zk * s; });
      } else {
        map1(n, dat(X[0][j]), dat(Z[j]), [s = c[0]](real xk) { return s * xk; });
      }
    }
    return kSuccess;
  }
  if (nsum == 2) return op_linearsumvectorarray(nvec, c[0], X[0], c[1], X[1], Z);
  for (int j = 0; j < nvec; ++j) {
    linear_combination(n, nsum, c, [X, j](int k) -> const real* { return dat(X[k][j]); },
                       dat(Z[j]));
  }
  return kSuccess;
}

// ---- XBraid buffer operations and printing (cheap to provide) ---------------

err_t op_bufsize(N_Vector x, sunindextype* size) noexcept {
  *size = len(x) * static_cast<sunindextype>(sizeof(real));
  return kSuccess;
}

err_t op_bufpack(N_Vector x, void* buf) noexcept {
  if (buf == nullptr) return kBadArg;
  map1(len(x), dat(x), static_cast<real*>(buf), [](real a) { return a; });
  return kSuccess;
}

err_t op_bufunpack(N_Vector x, void* buf) noexcept {
  if (buf == nullptr) return kBadArg;
  map1(len(x), static_cast<const real*>(buf), dat(x), [](real a) { return a; });
  return kSuccess;
}

void op_printfile(N_Vector x, FILE* out) noexcept {
  const index_t n = len(x);
  const real* xd = dat(x);
  for (index_t i = 0; i < n; ++i) {
    std::fprintf(out, "%.17Lg\n", static_cast<long double>(xd[i]));
  }
}

void op_print(N_Vector x) noexcept { op_printfile(x, stdout); }

void attach_ops(N_Vector_Ops ops) noexcept {
  // constructors, destructors, utility
  ops->nvgetvectorid = op_getvectorid;
  ops->nvclone = op_clone;
  ops->nvcloneempty = op_cloneempty;
  ops->nvdestroy = op_destroy;
  ops->nvspace = op_space;
  ops->nvgetarraypointer = op_getarraypointer;
  ops->nvsetarraypointer = op_setarraypointer;
  ops->nvgetlength = op_getlength;
  ops->nvgetlocallength = op_getlength;
  // nvgetcommunicator stays NULL: N_VGetCommunicator then reports "none".

  // standard operations
  ops->nvlinearsum = op_linearsum;
  ops->nvconst = op_const;
  ops->nvprod = op_prod;
  ops->nvdiv = op_div;
  ops->nvscale = op_scale;
  ops->nvabs = op_abs;
  ops->nvinv = op_inv;
  ops->nvaddconst = op_addconst;
  ops->nvdotprod = op_dotprod;
  ops->nvmaxnorm = op_maxnorm;
  ops->nvwrmsnorm = op_wrmsnorm;
  ops->nvwrmsnormmask = op_wrmsnormmask;
  ops->nvmin = op_min;
  ops->nvwl2norm = op_wl2norm;
  ops->nvl1norm = op_l1norm;
  ops->nvcompare = op_compare;
  ops->nvinvtest = op_invtest;
  ops->nvconstrmask = op_constrmask;
  ops->nvminquotient = op_minquotient;

  // fused operations (CVODES prefers them when present)
  ops->nvlinearcombination = op_linearcombination;
  ops->nvscaleaddmulti = op_scaleaddmulti;
  ops->nvdotprodmulti = op_dotprodmulti;

  // vector array operations
  ops->nvlinearsumvectorarray = op_linearsumvectorarray;
  ops->nvscalevectorarray = op_scalevectorarray;
  ops->nvconstvectorarray = op_constvectorarray;
  ops->nvwrmsnormvectorarray = op_wrmsnormvectorarray;
  ops->nvwrmsnormmaskvectorarray = op_wrmsnormmaskvectorarray;
  ops->nvscaleaddmultivectorarray = op_scaleaddmultivectorarray;
  ops->nvlinearcombinationvectorarray = op_linearcombinationvectorarray;

  // local reductions: serial, so identical to the global ones
  ops->nvdotprodlocal = op_dotprod;
  ops->nvmaxnormlocal = op_maxnorm;
  ops->nvminlocal = op_min;
  ops->nvl1normlocal = op_l1norm;
  ops->nvinvtestlocal = op_invtest;
  ops->nvconstrmasklocal = op_constrmask;
  ops->nvminquotientlocal = op_minquotient;
  ops->nvwsqrsumlocal = op_wsqrsumlocal;
  ops->nvwsqrsummasklocal = op_wsqrsummasklocal;
  ops->nvdotprodmultilocal = op_dotprodmulti;

  // XBraid interface, debugging
  ops->nvbufsize = op_bufsize;
  ops->nvbufpack = op_bufpack;
  ops->nvbufunpack = op_bufunpack;
  ops->nvprint = op_print;
  ops->nvprintfile = op_printfile;
}

}  // namespace

// This variant's operations, and whether a vector has them (their ID function tells).
void attach(N_Vector_Ops ops) noexcept { attach_ops(ops); }
bool owns(N_Vector v) noexcept { return v->ops->nvgetvectorid == op_getvectorid; }

}  // namespace PYDRILL_NVEC_VARIANT

#ifdef PYDRILL_NVEC_MAIN
#ifdef PYDRILL_NVEC_AVX2
namespace avx2 {
void attach(N_Vector_Ops ops) noexcept;
bool owns(N_Vector v) noexcept;
}  // namespace avx2
#endif

namespace {
using namespace generic;

bool has_avx2() {
#ifdef PYDRILL_NVEC_AVX2
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
#else
  return false;
#endif
}
}  // namespace

N_Vector make_fast_vector(sunindextype length, SUNContext ctx) {
  if (length < 0) return nullptr;
  N_Vector v = N_VNewEmpty(ctx);
  if (v == nullptr) return nullptr;
#ifdef PYDRILL_NVEC_AVX2
  if (has_avx2()) {
    avx2::attach(v->ops);
  } else {
    attach_ops(v->ops);
  }
#else
  attach_ops(v->ops);
#endif
  auto* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = length;
  v->content = c;
  if (length > 0) {
    real* data = new (std::nothrow) real[static_cast<size_t>(length)]();  // () zero-initialises
    if (data == nullptr) {
      op_destroy(v);
      return nullptr;
    }
    c->owned = data;
    c->data = data;
  }
  return v;
}

sunrealtype* fast_vector_data(N_Vector v) { return dat(v); }

bool fast_vector_exact_reductions() { return kLanes == 1; }

bool is_fast_vector(N_Vector v) {
  if (v == nullptr || v->ops == nullptr || v->content == nullptr) return false;
#ifdef PYDRILL_NVEC_AVX2
  if (avx2::owns(v)) return true;
#endif
  return generic::owns(v);
}

bool fast_vector_uses_avx2() { return has_avx2(); }
#endif  // PYDRILL_NVEC_MAIN

}  // namespace pydrill::detail
