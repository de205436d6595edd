// The fast N_Vector's reductions (dot product, norms, minimum): partial sums as
// nvector_fast_kernels.hpp's sum_reduce explains, so they agree with NVECTOR_SERIAL to rounding.

#include "nvector_fast_ops.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

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

}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
