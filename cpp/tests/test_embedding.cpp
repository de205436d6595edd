// What a program that embeds pydrill meets through the public headers alone, beyond simulate:
// the checks it may run itself before a sweep (SimulationOptions::validate) agree with the
// ones simulate runs on the strings they are meant for.
#include <catch2/catch.hpp>

#include <climits>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pydrill/params.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

namespace {

// A string of `dof` inertias built by hand (the preset refuses dof < 2 itself).
Params string_of(int dof) {
  Params p = preset("reduced-scale", 4);
  const std::size_t n = dof > 0 ? static_cast<std::size_t>(dof) : 0;
  p.inertias.assign(n, 0.025);
  p.stiffnesses.assign(n > 0 ? n - 1 : 0, 0.073);
  p.dampings.assign(n > 0 ? n - 1 : 0, 1e-4);
  return p;
}

bool refused(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument&) {
    return true;
  }
  return false;
}

}  // namespace

// options.validate(dof) is public and takes the dof on trust: it passed dof 0 and -5, so a
// program that checked its options first learnt nothing until simulate refused the string.
// The independent judge of which dof a string may have is Params::validate.
TEST_CASE("SimulationOptions::validate refuses exactly the dof a string may not have", "[embedding]") {
  const SimulationOptions options;  // every default valid
  for (int dof : {-5, 0, 1, 2, 3, 7}) {
    INFO("dof = " << dof);
    const Params p = string_of(dof);
    const bool string_refused = refused([&] { p.validate(); });
    CHECK(refused([&] { options.validate(dof); }) == string_refused);
  }
  CHECK_THROWS_WITH(options.validate(0), Catch::StartsWith("dof = 0 is not allowed") && Catch::Contains("dof >= 2"));
}

// Initial::State's size 2·dof − 1 was computed in int: at dof = INT_MAX it overflowed
// (undefined behaviour; in practice the message asked for 18446744073709551613 entries).
// The count it must name is 2·INT_MAX − 1 = 4294967293, computed here in 64 bits.
TEST_CASE("an Initial::State names the size it needs at any int dof", "[embedding]") {
  SimulationOptions options;
  options.initial = Initial::State;
  options.state = {0.0, 0.0, 0.0};  // dof 2's size
  REQUIRE_NOTHROW(options.validate(2));
  const long long needed = 2LL * INT_MAX - 1;
  CHECK_THROWS_WITH(options.validate(INT_MAX),
                    Catch::Contains("needs 2*dof-1 = " + std::to_string(needed)));
}
