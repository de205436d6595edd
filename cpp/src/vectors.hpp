// The N_Vector the simulator integrates with. Our own serial vector, compiled
// with optimisation, replaces NVECTOR_SERIAL: Debian builds SUNDIALS without
// optimisation, and vector operations are most of CVODES's O(n) work.
#pragma once

#include "nvector_fast.hpp"

namespace pydrill::detail {
inline N_Vector make_vector(int n, SUNContext ctx) { return make_fast_vector(n, ctx); }
}  // namespace pydrill::detail
