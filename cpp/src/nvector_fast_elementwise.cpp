// The fast N_Vector's element-wise operations (z[i] = f(x[i], y[i]): linear sum, scaling,
// products, ...), exactly NVECTOR_SERIAL's arithmetic; see nvector_fast_kernels.hpp for how
// the loops are written.

#include "nvector_fast_linear.hpp"
#include "nvector_fast_ops.hpp"

namespace pydrill::detail {
namespace PYDRILL_NVEC_VARIANT {

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

void op_compare(real c, N_Vector x, N_Vector z) noexcept {
  map1(len(x), dat(x), dat(z), [c](real a) { return SUNRabs(a) >= c ? kOne : kZero; });
}

}  // namespace PYDRILL_NVEC_VARIANT
}  // namespace pydrill::detail
