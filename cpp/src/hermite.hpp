// The turning point of a cubic Hermite interpolant: where a smooth quantity known by its
// values and rates at both ends of an interval peaks or dips inside it. The regime judge
// finds velocity extremes between samples with it; the rootfinders, a switching function
// that crossed zero and came back within one step.
#pragma once

#include <algorithm>
#include <cmath>

namespace pydrill::detail {

// On [0, 1], p(x) = v0 h00 + m0 h10 + v1 h01 + m1 h11 (m0, m1: the rates times the interval's
// length). When the rates have opposite signs p' changes sign once inside: true, with that x
// and p(x). Otherwise false.
inline bool hermite_turn(double v0, double v1, double m0, double m1, double& x, double& p) {
  if (!(m0 * m1 < 0.0)) return false;
  // p'(x) = A x² + B x + m0, with p'(0) = m0 and p'(1) = m1.
  const double d = v1 - v0;
  const double A = 3.0 * (m0 + m1) - 6.0 * d, B = 6.0 * d - 4.0 * m0 - 2.0 * m1;
  if (std::fabs(A) < 1e-14 * (std::fabs(B) + std::fabs(m0))) {
    x = -m0 / B;
  } else {
    // The stable pair of roots; the one inside (0, 1) is where p' changes sign.
    const double r = std::sqrt(std::max(B * B - 4.0 * A * m0, 0.0));
    const double q = -0.5 * (B + std::copysign(r, B));
    const double x1 = q / A, x2 = q != 0.0 ? m0 / q : x1;
    x = (x1 > 0.0 && x1 < 1.0) ? x1 : x2;
  }
  if (!(x > 0.0 && x < 1.0)) return false;
  const double x2 = x * x, x3 = x2 * x;
  p = v0 * (2 * x3 - 3 * x2 + 1) + m0 * (x3 - 2 * x2 + x) + v1 * (-2 * x3 + 3 * x2) +
      m1 * (x3 - x2);
  return true;
}

}  // namespace pydrill::detail
