// The fast N_Vector's linear sums, scalings and fused linear combinations on raw arrays, each
// reproducing NVECTOR_SERIAL's case analysis; shared by the element-wise operations
// (nvector_fast_elementwise.cpp) and the fused and vector-array ones (nvector_fast_arrays.cpp).
#pragma once

#include "nvector_fast_kernels.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {
namespace {

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

// inline, as scale below: not every file that includes this header calls them, and an unused
// function with internal linkage would be warned about.
inline void linear_sum(index_t n, real a, const real* x, real b, const real* y, real* z,
                       bool z_is_x, bool z_is_y) noexcept {
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
inline void scale(index_t n, real c, const real* x, real* z, bool z_is_x) noexcept {
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

}  // namespace
}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
