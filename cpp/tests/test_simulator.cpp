#include <catch2/catch.hpp>

#include <cmath>

#include "pydrill/equilibrium.hpp"
#include "pydrill/simulator.hpp"

using namespace pydrill;

TEST_CASE("paper regimes, reduced-scale dof 4, u = 8.3 N m, from rest", "[simulator]") {
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 300.0;
  SECTION("W_ob = 100 N sticks and slips (Fig. 4)") {
    const Result r = simulate(p, 100.0, 8.3, o);
    CHECK(r.summary.regime == "stick-slip");
    CHECK(r.summary.stick_events >= 2);
    CHECK(r.summary.period > 0);
  }
  SECTION("W_ob = 160 N stays stuck (Fig. 7)") {
    const Result r = simulate(p, 160.0, 8.3, o);
    CHECK(r.summary.regime == "stuck");
    CHECK(r.summary.stuck_fraction == 1.0);
  }
  SECTION("W_ob = 40 N drills steadily at the analytic Omega") {
    const Result r = simulate(p, 40.0, 8.3, o);
    CHECK(r.summary.regime == "steady");
    const double omega = equilibrium_velocities(p, 40.0, 8.3).back();
    const double wb = r.states[r.states.size() - 1];
    CHECK(std::fabs(wb - omega) / omega < 1e-6);
  }
}
