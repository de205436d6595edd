// What simulate does before it integrates (simulation_setup.cpp): the state it starts from,
// and the refusals that a run would otherwise fail (or grind) to find out.
#pragma once

#include <vector>

#include "pydrill/params.hpp"
#include "pydrill/simulator.hpp"

namespace pydrill::detail {

// The state opt.initial names: rest, the fastest steady state (perturbed, mirrored for a
// negative torque) or opt.state. std::invalid_argument if no steady state exists.
std::vector<double> initial_state(const Params& params, double wob, double torque,
                                  const SimulationOptions& opt);

// std::invalid_argument for loads beyond what a run can integrate (1e15 N, N·m).
void check_simulated_loads(double wob, double torque);

// SolverError (t_reached = 0) for a run that cannot reach t_end within opt.max_steps.
void check_step_budget(const Params& p, const SimulationOptions& opt, Method method);

}  // namespace pydrill::detail
