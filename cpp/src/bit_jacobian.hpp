// The bit's row of the chain's Jacobian, in O(1): the only row that depends on the state and
// the friction mode (the springs are linear). Chain::jacobian_band writes it into the band,
// and BDF's Newton matrix (chain_solver.cpp) refreshes it at every solve.
#pragma once

#include "pydrill/model.hpp"

namespace pydrill::detail {

// row[0..2] = J(b, b−2), J(b, b−1), J(b, b) with b = chain.bit_index(): the derivatives of
// dω_b/dt by ω_{N−2}, θ_{N−2} and ω_b at the state y in the given mode (zero where the rock
// holds the bit).
void bit_jacobian_row(const Chain& chain, const double* y, Mode mode, double* row);

}  // namespace pydrill::detail
