// The DOP853 step arithmetic compiled for AVX2+FMA (see dop853_kernels.hpp);
// integrator_dop853.cpp uses it when the CPU has both.
#define PYDRILL_DOP853_VARIANT avx2
#include "dop853_kernels.hpp"

namespace pydrill::detail::dop853 {
const Kernels& kernels_avx2() {
  static const Kernels k{avx2::trial_step, avx2::prepare_dense, avx2::evaluate_dense};
  return k;
}
}  // namespace pydrill::detail::dop853
