// The initial state and the checks simulate makes before integrating; see simulation_setup.hpp.
#include "simulation_setup.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "pydrill/equilibrium.hpp"
#include "shortest.hpp"

namespace pydrill::detail {

std::vector<double> initial_state(const Params& params, double wob, double torque,
                                  const SimulationOptions& opt) {
  const int N = params.dof();
  switch (opt.initial) {
    case Initial::Rest: return std::vector<double>(static_cast<std::size_t>(2 * N - 1), 0.0);
    case Initial::State: return opt.state;
    case Initial::Equilibrium: {
      const auto omegas = equilibrium_velocities(params, wob, std::fabs(torque));
      if (omegas.empty()) {
        std::ostringstream o;
        o << "initial = 'equilibrium' is not possible: no steady rotation exists for wob = "
          << wob << " N, torque = " << torque << " N·m (the torque cannot balance the bit friction); "
          << "start from 'rest' instead";
        throw std::invalid_argument(o.str());
      }
      // The fastest steady state: the one a driller aims for. At u < 0 its mirror image.
      auto y = equilibrium_state(params, wob, omegas.back());
      y[static_cast<std::size_t>(2 * N - 2)] *= 1.0 + opt.perturbation;
      if (torque < 0) {
        for (double& v : y) v = -v;
      }
      return y;
    }
  }
  return {};
}

// Loads a run can integrate: ten orders of magnitude above any drill string's (a real string's
// torque is ~1e4 N·m, its weight on bit ~1e5 N). Far beyond, the bit speeds and accelerations
// overflow double precision and the solver could only say that its step fell to 0 at t = 0.
// Only a run is bounded: the stability curves rightly reach such weights near their asymptotes.
void check_simulated_loads(double wob, double torque) {
  constexpr double kMaxLoad = 1e15;
  if (wob > kMaxLoad) {
    throw std::invalid_argument("wob = " + detail::shortest(wob) +
                                " is not allowed in a simulation: must be <= 1e15 N");
  }
  if (std::abs(torque) > kMaxLoad) {
    throw std::invalid_argument("torque = " + detail::shortest(torque) +
                                " is not allowed in a simulation: need |torque| <= 1e15 N·m");
  }
}

namespace {

// Refuses, before integrating, a run that cannot reach t_end within max_steps: it would grind
// through all of them first (measured: stiffnesses[0] = 1e12 on the paper's dof-4 string, DOP853
// took 2e6 steps to reach t = 0.54 s of 60). Two lower bounds on the steps, both certain:
// - max_step > 0: t_end / max_step.
// - DOP853, ERK and Adams: a step h of an explicit Runge-Kutta method is stable only while
//   h·λ lies in its stability region for every eigenvalue λ of the Jacobian, and the step
//   controllers hold h at that edge. The regions' radii, max |z| over each region (computed
//   from the methods' coefficients): DOP853 6.79, ARKODE's Fehlberg 13-stage 7(8) 5.00.
//   CVODES's Adams corrects with a fixed-point iteration, which converges only while
//   h·β₀·|λ| < 1, β₀ >= 0.274 (Adams–Moulton order 12): radius 1/0.274 = 3.65. So h <= R/|λ|.
//   |λ| of the fastest mode is estimated from below at each inertia above the bit (those move
//   in every friction mode, the stuck bit's too): the frequency sqrt((k_{i−1} + k_i)/I_i) and
//   half the decay rate (c_{i−1} + c_i (+ c_r))/(2 I_i), Rayleigh quotients of M⁻¹K and M⁻¹C
//   that bound a mode's |λ| from below (a damped oscillator's eigenvalues have |λ|² = k/m or,
//   overdamped, a root beyond c/2m). Measured on stiffened paper strings, the runs took 3.7x
//   (DOP853), 6x (ERK) and 12x (Adams) the steps this asks for.
// BDF has no such bound: it steps over fast modes once they have died.
// A SolverError (t_reached = 0), as reaching max_steps is: a sweep keeps the point as failed.
// Only a run that would grind is refused: one whose max_steps times its state size is under
// kGrindWork (milliseconds of steps) fails as fast by itself and tells more (how far it got,
// t_reached); scripts and tests give a small max_steps to make a run fail quickly.
constexpr double kGrindWork = 1e6;

std::string step_count(double n) {  // whole, or in 3 digits when longer than a long holds
  std::ostringstream o;
  if (n < 1e15) {
    o << static_cast<long long>(std::ceil(n));
  } else {
    o.precision(3);
    o << n;
  }
  return o.str();
}

}  // namespace

void check_step_budget(const Params& p, const SimulationOptions& opt, Method method) {
  const double limit = static_cast<double>(opt.max_steps);
  if (limit * (2.0 * p.dof() - 1.0) < kGrindWork) return;
  std::ostringstream o;
  o.precision(3);
  if (opt.max_step > 0 && opt.t_end / opt.max_step > limit) {
    o << "max_steps = " << opt.max_steps << " internal steps cannot reach t_end = " << opt.t_end
      << " s in steps of at most max_step = " << opt.max_step << " s (refused before integrating): "
      << "it needs at least " << step_count(opt.t_end / opt.max_step)
      << "; raise max_steps or shorten t_end";
    throw SolverError(o.str(), 0.0);
  }
  const double radius = method == Method::DOP853 ? 6.8 : method == Method::ERK ? 5.01
                        : method == Method::Adams ? 3.65 : 0.0;
  if (radius == 0.0) return;
  const int N = p.dof();
  double rate = 0.0;
  int at = 0;
  bool decay = false;
  for (int i = 0; i < N - 1; ++i) {
    const double I = p.inertias[i];
    const double K = (i > 0 ? p.stiffnesses[i - 1] : 0.0) + p.stiffnesses[i];
    const double C = (i > 0 ? p.dampings[i - 1] : p.top_damping) + p.dampings[i];
    const double w = std::sqrt(K / I), d = 0.5 * C / I;
    if (std::max(w, d) > rate) {
      rate = std::max(w, d);
      at = i;
      decay = d > w;
    }
  }
  const double needed = opt.t_end * rate / radius;
  if (!(needed > limit)) return;
  o << "max_steps = " << opt.max_steps << " internal steps cannot take method '" << method_name(method)
    << "' to t_end = " << opt.t_end << " s (refused before integrating): the string's fastest mode, at inertias["
    << at << "] (" << (decay ? "decay rate >= " : "frequency >= ") << rate << (decay ? " /s" : " rad/s")
    << "), keeps its steps below " << radius / rate << " s (|step x rate| <= " << radius
    << ", its stability limit), so the run needs at least " << step_count(needed) << " steps"
    << (decay ? " (method 'bdf' steps over a mode that has died)" : "")
    << "; raise max_steps or shorten t_end";
  throw SolverError(o.str(), 0.0);
}

}  // namespace pydrill::detail
