// The fast N_Vector's operations CVODES needs only with inequality constraints (InvTest,
// ConstrMask, MinQuotient): plain ports of NVECTOR_SERIAL's loops, as they are not hot and their
// branchy semantics are easiest to keep exact that way.

#include "nvector_fast_ops.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

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

}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
