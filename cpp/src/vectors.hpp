// The N_Vector the simulator integrates with.
#pragma once

#include <nvector/nvector_serial.h>

namespace pydrill::detail {
inline N_Vector make_vector(int n, SUNContext ctx) { return N_VNew_Serial(n, ctx); }
}  // namespace pydrill::detail
