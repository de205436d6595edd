// Guards from a second mutation audit of the core's stability side (session 37): each test
// fails on a small change to the code that decides steady states, eigenvalues and crossings
// (a loosened tolerance, a wrong sort, a transposed solve) that no other test noticed, and
// checks against something independent of that code: a documented rule, a dense eigensolver,
// or a value computed another way.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include "pydrill/params.hpp"
#include "pydrill/stability.hpp"

using namespace pydrill;

TEST_CASE("stab guard: crossings of a string whose fold differs by 1e-6 are not this string's",
          "[mutation]") {
  // The documented test (stability.cpp, the same as Python's math.isclose): the fold of the
  // crossings handed in must be c_r + c_b to a relative 1e-9. A top damping 1e-6 larger moves
  // the fold by ~1e-6 of it: those crossings belong to another string (Python checks first,
  // so only the C++ API reaches this), while a change at the rounding level (1e-12) passes.
  const Params p = preset("reduced-scale", 4);
  Params near = p, other = p;
  near.top_damping *= 1.0 + 1e-12;
  other.top_damping *= 1.0 + 1e-6;
  CHECK_NOTHROW(stability_at_torque(p, critical_deltas(near), 100.0, 8.3));
  CHECK_THROWS_WITH(stability_at_torque(p, critical_deltas(other), 100.0, 8.3),
                    Catch::StartsWith("crossings are not this string's (a fold at delta = "));
}
