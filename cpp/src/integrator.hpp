// One interface over the integrators the simulator can use:
//   CVODES BDF   — stiff strings; Newton with the O(dof) chain solver;
//   CVODES Adams — non-stiff, fixed-point iteration;
//   ARKODE ERK   — non-stiff, explicit Fehlberg 7(8) Runge–Kutta (one-step: no
//                  order ramp-up after each friction switch);
//   DOP853       — non-stiff, Dormand–Prince 8(5,3), our own code (the fastest
//                  where the fast modes ring; see integrator_dop853.cpp).
// All take single steps, locate roots of the current mode's switching
// functions, interpolate inside the last step and restart from a given state.
#pragma once

#include <memory>
#include <string>

#include "events.hpp"
#include "pydrill/simulator.hpp"

namespace pydrill::detail {

class Integrator {
 public:
  enum class Status { Step, Root, Stop };
  virtual ~Integrator() = default;
  // One internal step towards t_end (never past it). Throws SolverError.
  virtual Status step(double t_end, double& t) = 0;
  // Current state (size 2·dof − 1) and quadratures (size kQuads) at the time
  // of the last return; writable before restart().
  virtual double* state() = 0;
  virtual double* quadratures() = 0;
  // State and quadratures at t inside the last step.
  virtual void interpolate(double t, double* y, double* q) = 0;
  // Which root functions fired (+1 rising, −1 falling, 0 not) at the last Root.
  virtual void roots_found(int found[kRoots]) = 0;
  // Restart at t from state()/quadratures(), with the current mode's roots.
  virtual void restart(double t) = 0;
  // Counters since the last restart are added to stats and reset.
  virtual void collect(SolverStats& stats) = 0;
  virtual long steps_since_restart() = 0;
};

std::unique_ptr<Integrator> make_cvodes(Method method, RunData& data, const std::vector<double>& y0,
                                        const SimulationOptions& opt);
std::unique_ptr<Integrator> make_dop853(RunData& data, const std::vector<double>& y0,
                                        const SimulationOptions& opt);
std::unique_ptr<Integrator> make_erk(RunData& data, const std::vector<double>& y0,
                                     const SimulationOptions& opt);

}  // namespace pydrill::detail
