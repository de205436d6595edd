// The paper's Fig. 4 case from C++: a 4-DOF laboratory string at
// W_ob = 100 N and u = 8.3 N·m sticks and slips.
#include <cstdio>

#include <pydrill/simulator.hpp>

int main() {
  const pydrill::Params params = pydrill::preset("reduced-scale", 4);
  pydrill::SimulationOptions options;
  options.t_end = 300.0;
  options.initial = pydrill::Initial::Rest;

  const pydrill::Result r = pydrill::simulate(params, /*wob=*/100.0, /*torque=*/8.3, options);
  const pydrill::Summary& s = r.summary;
  std::printf("regime: %s\n", s.regime.c_str());
  std::printf("bit velocity: min %.4f  max %.4f  mean %.4f rad/s\n", s.bit_min, s.bit_max, s.bit_mean);
  std::printf("stick-slip period: %.4f s, %ld stick events, stuck %.1f %% of the time\n", s.period,
              s.stick_events, 100.0 * s.stuck_fraction);
  std::printf("solver: %s, %ld steps, %ld switches, %.3f ms\n", r.stats.method.c_str(), r.stats.steps,
              r.stats.switches, 1e3 * r.stats.wall_time);
  return s.regime == "stick-slip" ? 0 : 1;
}
