// The fast N_Vector's operations compiled for AVX2 (see nvector_fast_kernels.hpp): the same
// sources, their kernels and ops table only (nvector_fast.cpp's make_fast_vector & co. are left
// out, PYDRILL_NVEC_MAIN being undefined), in namespace avx2. make_fast_vector uses them when the
// CPU has AVX2.
#define PYDRILL_NVEC_VARIANT avx2
// NOLINTBEGIN(bugprone-suspicious-include): compiled a second time
#include "nvector_fast.cpp"
#include "nvector_fast_arrays.cpp"
#include "nvector_fast_constraints.cpp"
#include "nvector_fast_elementwise.cpp"
#include "nvector_fast_reductions.cpp"
// NOLINTEND(bugprone-suspicious-include)
