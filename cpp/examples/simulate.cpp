// The paper's Fig. 4 case from C++: a 4-DOF laboratory string at
// W_ob = 100 N and u = 8.3 N·m sticks and slips.
#include <cstdio>

#include <pydrill/simulator.hpp>

int main() {
  const int dof = 4;
  const double wob = 100.0, torque = 8.3;  // N, N·m
  const pydrill::Params params = pydrill::preset("reduced-scale", dof);
  pydrill::SimulationOptions options;
  options.t_end = 300.0;
  options.initial = pydrill::Initial::Rest;
  std::printf("reduced-scale string, dof %d: W_ob %g N, u %g N·m, from rest for %g s\n", dof, wob, torque,
              options.t_end);

  const pydrill::Result r = pydrill::simulate(params, wob, torque, options);
  const pydrill::Summary& s = r.summary;
  std::printf("regime: %s (judged on t = %g ... %g s)\n", pydrill::regime_name(s.regime), s.window_start, s.window_end);
  std::printf("in that window: bit velocity min %.4f  max %.4f  mean %.4f rad/s\n", s.bit_min, s.bit_max,
              s.bit_mean);
  std::printf("in that window: period %.4f s, %ld stick events, stuck %.1f %% of the time\n", s.period,
              s.stick_events, 100.0 * s.stuck_fraction);
  std::printf("whole run: solver %s, %ld steps, %ld switches, %.3f ms\n", pydrill::method_name(r.stats.method),
              r.stats.steps, r.stats.switches, 1e3 * r.stats.wall_time);
  return s.regime == pydrill::Regime::StickSlip ? 0 : 1;
}
