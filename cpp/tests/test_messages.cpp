// What the library's messages tell a C++ caller to change names a C++ field, not another
// language's: the short-window note's advice named "(window)", the sweep spec's key, where
// SimulationOptions takes window_fraction.
#include <catch2/catch.hpp>

#include <string>

#include "pydrill/params.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

namespace {
bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

TEST_CASE("the short-window note names SimulationOptions::window_fraction", "[summary][messages]") {
  // docs/guide/simulate.md's 13-inertia string from equilibrium at t_end = 100 s: its slowest
  // period (about 72 s) is longer than the 50 s judged by default.
  const Params p = preset("reduced-scale", 13);
  SimulationOptions o;
  o.t_end = 100.0;
  o.n_out = 501;
  o.initial = Initial::Equilibrium;
  const Result r = simulate(p, 40.0, 8.3, o);
  REQUIRE(r.summary.caveat == "short-window");
  CHECK(ends_with(r.summary.note,
                  "simulate longer, or judge a larger fraction of the run (window_fraction)"));
  // The advice works as named: the whole 100 s holds the 72 s period, and the note goes.
  o.window_fraction = 1.0;
  CHECK(simulate(p, 40.0, 8.3, o).summary.caveat != "short-window");
}
