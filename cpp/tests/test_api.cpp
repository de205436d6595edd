// The library as a program that embeds it meets it: typed results, names that match
// Python's, calls from several threads at once.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

using namespace pydrill;

TEST_CASE("regimes, methods and crossing types are enums named as Python names them", "[api]") {
  // They were strings ("stick-slip", "bdf", "hopf"): a typo in a comparison compiled and was
  // silently false. The names stay those of Python, the command line and an atlas.
  for (Regime r : {Regime::Steady, Regime::StickSlip, Regime::Stuck, Regime::Oscillation}) {
    CHECK(parse_regime(regime_name(r)) == r);
  }
  CHECK(std::string(regime_name(Regime::StickSlip)) == "stick-slip");
  CHECK(std::string(regime_name(Regime::Oscillation)) == "oscillation");
  CHECK(std::string(regime_name(static_cast<Regime>(9))) == "?");
  CHECK_THROWS_WITH(parse_regime("stick_slip"), Catch::StartsWith("regime = 'stick_slip' is not allowed"));

  for (CrossingType t : {CrossingType::Hopf, CrossingType::Fold}) {
    CHECK(parse_crossing_type(crossing_type_name(t)) == t);
  }
  CHECK(std::string(crossing_type_name(CrossingType::Hopf)) == "hopf");
  CHECK(std::string(crossing_type_name(static_cast<CrossingType>(5))) == "?");
  CHECK_THROWS_AS(parse_crossing_type("Hopf"), std::invalid_argument);

  for (Method m : {Method::Auto, Method::BDF, Method::Adams, Method::ERK, Method::DOP853}) {
    CHECK(parse_method(method_name(m)) == m);
  }
}

TEST_CASE("a result says what ran and what it found as enums", "[api]") {
  SimulationOptions o;
  o.t_end = 300.0;
  const Result r = simulate(preset("reduced-scale", 4), 100.0, 8.3, o);
  CHECK(r.summary.regime == Regime::StickSlip);
  CHECK(r.stats.method == Method::DOP853);  // what Method::Auto picks for this string
  const std::vector<Crossing> c = critical_deltas(preset("reduced-scale", 4));
  REQUIRE(!c.empty());
  CHECK(c.front().type == CrossingType::Hopf);  // the first Hopf point, δ = 0.0108
  const auto fold = std::find_if(c.begin(), c.end(), [](const Crossing& x) { return x.type == CrossingType::Fold; });
  REQUIRE(fold != c.end());
  CHECK(fold->delta == Approx(0.18 + 0.01));  // at c_r + c_b
}
