// The fast N_Vector's fused operations (linear combination, scale-add-multi, multiple dot
// products) and vector-array operations, each reproducing NVECTOR_SERIAL's special cases; the
// linear combinations fuse several terms a pass (see nvector_fast_linear.hpp).

#include "nvector_fast_linear.hpp"
#include "nvector_fast_ops.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

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

}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
