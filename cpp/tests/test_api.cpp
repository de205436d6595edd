// The library as a program that embeds it meets it: typed results, names that match
// Python's, calls from several threads at once.
#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define PYDRILL_TEST_MXCSR 1
#endif

#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"
#include "pydrill/version.hpp"

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

TEST_CASE("the headers and the library say which pydrill they are", "[api]") {
  // A program that builds against more than one pydrill had nothing to test: the C++ API
  // changes between minor versions before 1.0.
  CHECK(std::string(version()) == PYDRILL_VERSION_STRING);
  CHECK(std::string(PYDRILL_VERSION_STRING) == PYDRILL_PROJECT_VERSION);  // CMake's project()
  CHECK(std::string(PYDRILL_VERSION_STRING) == std::to_string(PYDRILL_VERSION_MAJOR) + "." +
                                                   std::to_string(PYDRILL_VERSION_MINOR) + "." +
                                                   std::to_string(PYDRILL_VERSION_PATCH));
}

namespace {

struct Case {
  int dof;
  double wob, torque;
  Method method;
};

// Everything a run computes that another run of the same case must reproduce bit for bit.
struct Outcome {
  std::vector<double> states, energy;
  std::vector<int> modes;
  Regime regime;
  double period;
  long steps;
  std::vector<Crossing> crossings;
  std::vector<StabilityPoint> points;
};

Outcome compute(const Case& c) {
  const Params p = preset("reduced-scale", c.dof);
  SimulationOptions o;
  o.t_end = 100.0;
  o.n_out = 501;
  o.method = c.method;
  const Result r = simulate(p, c.wob, c.torque, o);
  return {r.states, r.energy, r.modes, r.summary.regime, r.summary.period, r.stats.steps,
          critical_deltas(p), stability_at_torque(p, c.wob, c.torque)};
}

void check_same(const Outcome& a, const Outcome& b) {
  CHECK(a.states == b.states);
  CHECK(a.energy == b.energy);
  CHECK(a.modes == b.modes);
  CHECK(a.regime == b.regime);
  CHECK(a.period == b.period);
  CHECK(a.steps == b.steps);
  REQUIRE(a.crossings.size() == b.crossings.size());
  for (std::size_t k = 0; k < a.crossings.size(); ++k) CHECK(a.crossings[k].delta == b.crossings[k].delta);
  REQUIRE(a.points.size() == b.points.size());
  for (std::size_t k = 0; k < a.points.size(); ++k) CHECK(a.points[k].eigenvalues == b.points[k].eigenvalues);
}

}  // namespace

TEST_CASE("two threads simulate and analyse at once, each as if alone", "[api][threads]") {
  // simulate() and the stability functions keep no state between calls: a program may run
  // them in as many threads as it likes (Python's sweeps run them in Dask's worker threads).
  // Each integrator, with a string long enough to need the structured eigenvalues (dof >= 24).
  const std::vector<Case> cases = {{4, 100.0, 8.3, Method::DOP853}, {4, 100.0, 8.3, Method::BDF},
                                   {30, 100.0, 8.3, Method::ERK},   {30, 40.0, 8.3, Method::Adams},
                                   {4, 40.0, 8.3, Method::Auto},    {30, 160.0, 8.3, Method::DOP853}};
  std::vector<Outcome> alone;
  for (const Case& c : cases) alone.push_back(compute(c));
  // Two threads, each through every case, in opposite orders, so that different integrators
  // and the stability analysis overlap.
  std::vector<Outcome> forward(cases.size()), backward(cases.size());
  std::thread a([&] {
    for (std::size_t k = 0; k < cases.size(); ++k) forward[k] = compute(cases[k]);
  });
  std::thread b([&] {
    for (std::size_t k = cases.size(); k-- > 0;) backward[k] = compute(cases[k]);
  });
  a.join();
  b.join();
  for (std::size_t k = 0; k < cases.size(); ++k) {
    INFO("case " << k << ", method " << method_name(cases[k].method));
    check_same(alone[k], forward[k]);
    check_same(alone[k], backward[k]);
  }
}

#ifdef PYDRILL_TEST_MXCSR
TEST_CASE("options.interrupt runs with the caller's floating-point setting", "[api]") {
  // A run flushes subnormal numbers to zero in its thread (they cost ~100x); the callback,
  // the caller's own code, ran so too: a value below 2e-308 computed there became 0.
  const unsigned flags = 0x8040;  // FTZ | DAZ
  const unsigned before = _mm_getcsr();
  REQUIRE((before & flags) == 0);
  SimulationOptions o;
  o.t_end = 20000.0;  // 300 pipes: long enough to be asked (every 0.1 s)
  o.n_out = 11;
  unsigned seen = flags;
  volatile double tiny = 1e-300;
  double product = 0.0;
  o.interrupt = [&] {
    seen = _mm_getcsr() & flags;
    product = tiny * 1e-10;  // 1e-310, subnormal
    return true;
  };
  CHECK_THROWS_AS(simulate(preset("reduced-scale", 303), 100.0, 8.3, o), Interrupted);
  CHECK(seen == 0);
  CHECK_THROWS_AS(simulate(preset("reduced-scale", 303), 100.0, 8.3, o), Cancelled);
  CHECK(product > 0.0);
  // Restored after the run, interrupted or not (the control bits: the low six are sticky
  // exception flags, which the subnormal product above raises).
  CHECK((_mm_getcsr() & ~0x3Fu) == (before & ~0x3Fu));
}
#endif

TEST_CASE("the closed-form and Hurwitz calls name what they were given", "[api]") {
  // Both refused without naming the bad input: "the closed form of Eq. (51) is for dof = 2"
  // (which dof came?) and "hurwitz_determinants needs a polynomial of degree >= 1" (how many
  // coefficients came?), where every other refusal names the parameter and its value.
  CHECK_THROWS_WITH(hopf_deltas_dof2(preset("reduced-scale", 4)),
                    Catch::StartsWith("dof = 4 is not allowed: the closed form of Eq. (51) is for dof = 2"));
  CHECK_THROWS_WITH(hurwitz_determinants({}), Catch::StartsWith("ascending has 0 coefficients"));
  CHECK_THROWS_WITH(hurwitz_determinants({2.0}),
                    Catch::StartsWith("ascending has 1 coefficient: hurwitz_determinants needs a polynomial of degree >= 1"));
  // What they accept is unchanged: the paper's 2-DOF string has one Hopf point below its fold,
  // and λ + 1 is Hurwitz with no determinant to give.
  CHECK(hopf_deltas_dof2(preset("real-string", 2)).size() == 1);
  CHECK(hurwitz_determinants({1.0, 1.0}).empty());
}
