#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "pydrill/friction.hpp"
#include "pydrill/params.hpp"
#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

using pydrill::Params;
using pydrill::preset;

namespace {
std::string refusal(const Params& p) {
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("pipes_to_dof refuses a string without pipes", "[params]") {
  // pipes_to_dof(-5) returned -2 without complaint.
  CHECK(pydrill::pipes_to_dof(1) == 4);
  CHECK(pydrill::pipes_to_dof(99997) == 100000);
  CHECK_THROWS_AS(pydrill::pipes_to_dof(-5), std::invalid_argument);
  CHECK_THROWS_WITH(pydrill::pipes_to_dof(-5), Catch::StartsWith("pipes = -5 is not allowed: need 1 <= pipes"));
  CHECK_THROWS_AS(pydrill::pipes_to_dof(0), std::invalid_argument);
  CHECK_THROWS_AS(pydrill::pipes_to_dof(2147483647), std::invalid_argument);
}

TEST_CASE("reduced-scale preset builds the chain of Eq. (14) for any dof", "[params]") {
  for (int dof : {2, 3, 4, 13, 503}) {
    const Params p = preset("reduced-scale", dof);
    REQUIRE(p.dof() == dof);
    REQUIRE(p.stiffnesses.size() == static_cast<std::size_t>(dof - 1));
    CHECK(p.inertias.front() == 0.518);
    CHECK(p.inertias.back() == 0.0318);
    if (dof >= 3) CHECK(p.inertias[dof - 2] == 0.0318);  // J_l = J_b
    if (dof >= 4) CHECK(p.inertias[1] == 0.025);        // pipes
  }
  const Params r = preset("real-string", 2);
  CHECK(r.inertias[1] == 471.9698);
  CHECK(r.stiffnesses[0] == 861.5336);
  CHECK_THROWS_AS(preset("real-string", 4), std::invalid_argument);
  // What a C++ caller can do (the Python-only tally is named as such).
  CHECK_THROWS_WITH(preset("real-string", 4),
                    Catch::Contains("element by element (Params::inertias, stiffnesses, dampings"));
  CHECK_THROWS_AS(preset("nonsense", 4), std::invalid_argument);
  CHECK_THROWS_AS(preset("reduced-scale", 1), std::invalid_argument);
}

TEST_CASE("bad parameters are refused with their name, value and range", "[params]") {
  const Params good = preset("reduced-scale", 4);
  REQUIRE(refusal(good).empty());

  Params p = good;
  p.inertias[2] = -1.0;
  CHECK(refusal(p).find("inertias[2] = -1") != std::string::npos);
  CHECK(refusal(p).find("> 0") != std::string::npos);

  p = good;
  p.dampings[0] = -1e-3;
  CHECK(refusal(p).find("dampings[0]") != std::string::npos);

  p = good;
  p.stiffnesses[1] = std::numeric_limits<double>::quiet_NaN();
  CHECK(refusal(p).find("stiffnesses[1]") != std::string::npos);

  p = good;
  p.mu_static = 0.4;  // below μ_c = 0.5
  CHECK(refusal(p).find("mu_static") != std::string::npos);

  p = good;
  p.stiffnesses.pop_back();
  CHECK(refusal(p).find("stiffnesses has 2 entries") != std::string::npos);

  p = good;
  p.bit_radius = std::numeric_limits<double>::infinity();
  CHECK(refusal(p).find("bit_radius") != std::string::npos);

  CHECK_THROWS_WITH(pydrill::check_operating_point(0.0, 8.3), Catch::Contains("wob = 0"));
  CHECK_THROWS_WITH(pydrill::check_operating_point(100.0, std::nan("")), Catch::Contains("torque"));
}

TEST_CASE("every public function that reads a string checks it first", "[params]") {
  // A string whose vectors disagree with its dof: read blindly, it runs off the end of
  // stiffnesses (a crash) or returns numbers made of stale memory.
  Params p = preset("reduced-scale", 4);
  p.stiffnesses.clear();
  const auto names_it = Catch::Contains("stiffnesses has 0 entries");
  CHECK_THROWS_WITH(pydrill::bit_impedance(p, {0.0, 1.0}), names_it);
  CHECK_THROWS_WITH(pydrill::estimate_stiffness(p), names_it);
  CHECK_THROWS_WITH(pydrill::stiffness_ratio(p), names_it);
  CHECK_THROWS_WITH(pydrill::choose_method(p), names_it);
  CHECK_THROWS_WITH(pydrill::boundary_wob(p, 1.0, 1.0), names_it);
  CHECK_THROWS_WITH(pydrill::stribeck_slope(p, 100.0, 1.0), names_it);
  CHECK_THROWS_WITH(pydrill::critical_deltas(p), names_it);

  // A default-constructed Params has no string at all; its friction law has v_f = 1 but
  // μ = 0, which a friction object would turn into zero torque without a word.
  const Params empty;
  CHECK_THROWS_WITH(pydrill::bit_impedance(empty, {0.0, 1.0}), Catch::Contains("dof = 0"));
  CHECK_THROWS_WITH(pydrill::BitFriction(empty, 100.0), Catch::Contains("dof = 0"));
  Params q = preset("reduced-scale", 4);
  q.stribeck_velocity = 0.0;
  CHECK_THROWS_WITH(pydrill::BitFriction(q, 100.0), Catch::Contains("stribeck_velocity = 0"));
  CHECK_THROWS_WITH(pydrill::boundary_wob(q, 1.0, 1.0), Catch::Contains("stribeck_velocity = 0"));
  CHECK_THROWS_WITH(pydrill::BitFriction(preset("reduced-scale", 4), -1.0), Catch::Contains("wob = -1"));
  // The checked constructor still gives the law of DESIGN.md §2.
  const pydrill::BitFriction f(preset("reduced-scale", 4), 100.0);
  CHECK(f.static_torque() == Approx(0.8 * 100.0 * 0.1));
  CHECK(f.magnitude(1.0) == Approx(100.0 * 0.1 * (0.5 + 0.3 * std::exp(-0.9))));
}

TEST_CASE("rates a double cannot square are refused, naming the parameter and the inertia",
          "[params]") {
  // Measured before: top_damping = 1e300 ground through max_steps at t = 1e-13 s, an inertia of
  // 1e-300 failed at t = 0 with "h = nan", stiffnesses 1e300 with "step size fell" at t = 0.
  const Params base = preset("reduced-scale", 4);
  Params p = base;
  p.top_damping = 1e300;
  CHECK(refusal(p) ==
        "top_damping = 1e+300 is not allowed with inertias[0] = 0.518: the decay rate at inertia "
        "0, (top_damping + dampings[0]) / inertias[0] = 1.93e+300 /s, must be <= 1e15 /s (no step "
        "of a double-precision solver resolves a faster decay; a real string's are below 1e7 /s: "
        "check the units)");
  p = base;
  p.inertias[0] = 1e-300;  // the absurd one of the two is named first
  CHECK_THAT(refusal(p), Catch::StartsWith("inertias[0] = 1e-300 is not allowed with top_damping = 0.18: "
                                           "the decay rate at inertia 0"));
  p = base;
  p.stiffnesses[1] = 1e300;
  CHECK_THAT(refusal(p), Catch::StartsWith("stiffnesses[1] = 1e+300 is not allowed with inertias[1] = 0.025: "
                                           "the frequency at inertia 1, sqrt((stiffnesses[0] + "
                                           "stiffnesses[1]) / inertias[1]) = 6.32e+150 rad/s"));
  p = base;
  p.bit_damping = 1e300;
  CHECK_THAT(refusal(p), Catch::StartsWith("bit_damping = 1e+300 is not allowed with inertias[3] = 0.0318"));
  p = base;
  p.dampings[2] = 1e300;  // acts on inertias 2 and 3: the first one found is named
  CHECK_THAT(refusal(p), Catch::StartsWith("dampings[2] = 1e+300 is not allowed with inertias[2] = 0.0318"));
  // At the limit and below it, accepted: 1e15 /s for a decay, 1e150 rad/s for a frequency.
  p = base;
  p.top_damping = 0.999e15 * p.inertias[0];
  CHECK_NOTHROW(p.validate());
  p.top_damping = 1.001e15 * p.inertias[0];
  CHECK_THROWS_AS(p.validate(), std::invalid_argument);
  p = base;
  p.stiffnesses[0] = 0.998e300 * p.inertias[1];  // frequency 0.999e150 rad/s at inertia 1
  CHECK_NOTHROW(p.validate());
  p.stiffnesses[0] = 1.002e300 * p.inertias[1];
  CHECK_THROWS_AS(p.validate(), std::invalid_argument);
  // Slow rates are not refused: the string barely moves, and a run ends at once.
  p = base;
  p.inertias[0] = 1e300;
  p.stiffnesses[2] = 1e-300;
  CHECK_NOTHROW(p.validate());
  // Nor is anything of the paper's strings, nor of a real one element by element.
  CHECK_NOTHROW(preset("real-string", 2).validate());
  CHECK_NOTHROW(preset("reduced-scale", 100000).validate());
}
