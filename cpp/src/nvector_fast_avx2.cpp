// The fast N_Vector's operations compiled for AVX2 (see nvector_fast.cpp): the same source,
// its kernels and ops table only, in namespace avx2. make_fast_vector uses them when the CPU
// has AVX2.
#define PYDRILL_NVEC_VARIANT avx2
#include "nvector_fast.cpp"  // NOLINT(bugprone-suspicious-include): compiled a second time
