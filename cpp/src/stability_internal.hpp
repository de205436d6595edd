// What stability's files share (stability.cpp, stability_jacobian.cpp, hopf_crossings.cpp):
// the bit impedance's continued fraction, the Stribeck factor, the check of a slope δ and the
// reduced Jacobian's entries. Private: the public API is pydrill/stability.hpp.
#pragma once

#include <complex>

#include "pydrill/params.hpp"

namespace pydrill {

// Shorthand for stability's own files: the public headers spell std::complex<double>.
using complex = std::complex<double>;

namespace detail {

// The Stribeck slope (−d/dω of the bit's friction torque) at ω = 0 per newton of weight on
// bit: stribeck_slope = wob · stribeck_factor · exp(−decay ω / v_s).
double stribeck_factor(const Params& p);

// Z_b = N/D with N and D rescaled at every element so that long strings
// neither overflow nor underflow; their ratio is all that matters.
struct Fraction {
  complex num, den;
};

Fraction bit_fraction(const Params& p, complex lambda);

// Z_b(λ) for a string already validated (the public bit_impedance checks first).
complex impedance(const Params& p, complex lambda);
// Z_b'(λ), exact along the continued fraction (hopf_crossings.cpp), for a validated string.
complex impedance_slope(const Params& p, complex lambda);

// δ enters every linearisation as a number; a NaN or infinite one would come back as a
// "did not converge", a NaN spectrum or a stable count, none of which names it.
void check_delta(double delta);

// The reduced Jacobian's entries, at(row, column) = value for each that is not zero: at most
// two neighbours either side of the diagonal (interleaved coordinates).
template <typename At>
void jacobian_entries(const Params& p, double delta, At&& at) {
  const int N = p.dof();
  for (int i = 0; i < N; ++i) {
    const int r = 2 * i;
    const double inv = 1.0 / p.inertias[i];
    double diag = (i == 0 ? -p.top_damping : 0.0) + (i == N - 1 ? -p.bit_damping + delta : 0.0);
    if (i > 0) {
      at(r, r - 2) = p.dampings[i - 1] * inv;
      at(r, r - 1) = p.stiffnesses[i - 1] * inv;
      diag -= p.dampings[i - 1];
    }
    if (i < N - 1) {
      at(r, r + 1) = -p.stiffnesses[i] * inv;
      at(r, r + 2) = p.dampings[i] * inv;
      diag -= p.dampings[i];
      at(r + 1, r) = 1.0;
      at(r + 1, r + 2) = -1.0;
    }
    at(r, r) = diag * inv;
  }
}

}  // namespace detail
}  // namespace pydrill
