// libFuzzer harness for pydrill's public C++ API (see README.md beside it): fuzz bytes become
// a string (Params), an operating point and simulation options; every entry point must either
// refuse the input with std::invalid_argument naming it, fail with the documented error, or
// return finite numbers. Anything else (a crash, a sanitizer report, another exception, a NaN
// handed back as a result) stops the fuzzer.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <pydrill/equilibrium.hpp>
#include <pydrill/simulator.hpp>
#include <pydrill/stability.hpp>

namespace {

[[noreturn]] void defect(const std::string& what) {
  std::fprintf(stderr, "DEFECT: %s\n", what.c_str());
  std::abort();
}

void finite(double v, const char* what) {
  if (!std::isfinite(v)) defect(std::string(what) + " is not finite: " + std::to_string(v));
}
void finite(std::complex<double> v, const char* what) {
  finite(v.real(), what);
  finite(v.imag(), what);
}
template <typename T>
void finite(const std::vector<T>& vs, const char* what) {
  for (const T& v : vs) finite(v, what);
}
// For a value that may rightly be beyond the doubles (a product or exponential of valid
// inputs, as boundary_wob's exp(γΩ/v_f)): ±inf is that overflow, NaN a defect.
void not_nan(double v, const char* what) {
  if (std::isnan(v)) defect(std::string(what) + " is NaN");
}
void not_nan(const std::vector<double>& vs, const char* what) {
  for (double v : vs) not_nan(v, what);
}

// A number near `typical` most of the time (so most strings are valid and reach the solvers),
// across up to ±12 decades, sometimes an edge value: 0, negatives, NaN, inf, extremes.
double number(FuzzedDataProvider& in, double typical) {
  const int kind = in.ConsumeIntegralInRange(0, 15);
  if (kind < 11) {
    const double decades = in.ConsumeIntegralInRange(-96, 96) / 8.0;
    return typical * std::pow(10.0, kind < 6 ? decades / 8.0 : decades);
  }
  static const double edge[] = {0.0, -0.0, -1.0, 1.0, std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::max(), 1e-300, 1e300, 1e15, 1e150, 1e-15};
  if (kind < 15) return edge[in.ConsumeIntegralInRange<std::size_t>(0, std::size(edge) - 1)];
  return in.ConsumeFloatingPoint<double>();
}

// Every refusal names what it refuses: "name = value is not allowed: ..." or "... has N entries".
template <typename F>
bool refused(F&& call, const char* where) {
  try {
    call();
    return false;
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    if (m.find(" = ") == std::string::npos && m.find(" entries") == std::string::npos &&
        m.find("crossings are not") == std::string::npos) {
      defect(std::string(where) + ": refusal names nothing: " + m);
    }
    return true;
  }
}

void check_result(const pydrill::Result& r, const pydrill::Params& p, const pydrill::SimulationOptions& o) {
  const std::size_t n = static_cast<std::size_t>(2 * p.dof() - 1);
  const std::size_t rows = o.t_out.empty() ? static_cast<std::size_t>(o.n_out) : o.t_out.size();
  if (r.t.size() != rows || r.states.size() != rows * n || r.energy.size() != rows || r.modes.size() != rows) {
    defect("result sizes: t " + std::to_string(r.t.size()) + ", states " + std::to_string(r.states.size()) +
           ", expected rows " + std::to_string(rows));
  }
  finite(r.t, "t");
  finite(r.states, "states");
  finite(r.top_angle, "top_angle");
  finite(r.work_input, "work_input");
  finite(r.viscous_loss, "viscous_loss");
  finite(r.friction_loss, "friction_loss");
  finite(r.energy, "energy");
  const pydrill::Summary& s = r.summary;
  for (double v : {s.window_start, s.window_end, s.bit_min, s.bit_max, s.bit_mean, s.top_min, s.top_max,
                   s.top_mean, s.stuck_fraction, s.period, s.static_torque}) {
    finite(v, "summary field");
  }
  finite(s.omega_equilibrium, "omega_equilibrium");
  if (std::string(pydrill::regime_name(s.regime)) == "?") defect("regime outside its enum");
}

void stability(const pydrill::Params& p, double wob, double torque, double omega, double delta) {
  using namespace pydrill;
  const int dof = p.dof();
  refused([&] { finite(stribeck_slope(p, wob, omega), "stribeck_slope"); }, "stribeck_slope");
  refused([&] { not_nan(boundary_wob(p, delta, omega), "boundary_wob"); }, "boundary_wob");
  refused([&] { finite(bit_impedance(p, {delta, omega}), "bit_impedance"); }, "bit_impedance");
  refused([&] { not_nan(equilibrium_torque(p, wob, omega), "equilibrium_torque"); }, "equilibrium_torque");
  refused([&] { not_nan(equilibrium_state(p, wob, omega), "equilibrium_state"); }, "equilibrium_state");
  refused([&] {
    for (double w : equilibrium_velocities(p, wob, torque)) {
      finite(w, "equilibrium velocity");
      if (!(w > 0)) defect("equilibrium velocity <= 0");
      const double u = equilibrium_torque(p, wob, w);
      const double scale = std::max(std::fabs(torque), p.mu_static * wob * p.bit_radius);
      if (std::fabs(u - torque) > 1e-6 * scale) {
        defect("equilibrium velocity " + std::to_string(w) + " needs torque " + std::to_string(u) +
               ", asked " + std::to_string(torque));
      }
    }
  }, "equilibrium_velocities");
  refused([&] { not_nan(jacobian(p, delta), "jacobian"); }, "jacobian");
  if (dof <= 8) {
    // The dense solver's one documented error ("did not converge") is allowed; the
    // structured solver falls back on it.
    const auto dense = [&](const char* name, auto solve) {
      refused([&] {
        try {
          finite(solve(), name);
        } catch (const std::invalid_argument&) {
          throw;
        } catch (const std::runtime_error& e) {
          if (std::string(e.what()) != "eigenvalue solver did not converge") throw;
        }
      }, name);
    };
    dense("eigenvalues", [&] { return eigenvalues(p, delta); });
    dense("structured_eigenvalues", [&] { return structured_eigenvalues(p, delta); });
  }
  refused([&] {
    const auto a = characteristic_polynomial(p, delta);
    not_nan(a, "characteristic_polynomial");
    if (a.size() != static_cast<std::size_t>(2 * dof)) defect("characteristic_polynomial size");
    if (a.back() > 0) not_nan(hurwitz_determinants(a), "hurwitz_determinants");
  }, "characteristic_polynomial");
  if (dof == 2) refused([&] { finite(hopf_deltas_dof2(p), "hopf_deltas_dof2"); }, "hopf_deltas_dof2");
  std::vector<Crossing> crossings;
  refused([&] { crossings = critical_deltas(p); }, "critical_deltas");
  for (const Crossing& c : crossings) {
    finite(c.delta, "crossing delta");
    finite(c.frequency, "crossing frequency");
    if (c.type == CrossingType::Hopf && c.frequency > 0) {
      refused([&] { finite(first_lyapunov_coefficient(p, c.delta, c.frequency), "lyapunov"); }, "lyapunov");
    }
  }
  // The crossings' count of unstable eigenvalues is the dense solver's, away from the axis.
  refused([&] {
    const int count = unstable_count(crossings, delta);
    if (dof > 8 || count < 0 || count > 2 * dof - 1) {
      if (count < 0 || count > 2 * dof - 1) defect("unstable_count " + std::to_string(count) + " out of range");
      return;
    }
    for (const Crossing& c : crossings) {
      if (std::fabs(c.delta - delta) <= 1e-6 * std::max(std::fabs(delta), std::fabs(c.delta))) return;
    }
    try {
      int dense = 0;
      const auto ev = eigenvalues(p, delta);
      double largest = 0;
      for (const auto& z : ev) largest = std::max(largest, std::abs(z));
      for (const auto& z : ev) {
        // Too near the axis to say, or below what a dense solver resolves beside the largest.
        if (std::fabs(z.real()) <= 1e-6 * std::abs(z) || std::fabs(z.real()) <= 1e-9 * largest) return;
        dense += z.real() > 0;
      }
      if (dense != count) {
        defect("unstable_count " + std::to_string(count) + " from the crossings, " + std::to_string(dense) +
               " eigenvalues in the right half-plane at delta " + std::to_string(delta));
      }
    } catch (const std::runtime_error&) {
    }
  }, "unstable_count");
  auto check_point = [](const StabilityPoint& s) {
    for (double v : {s.omega, s.wob, s.torque, s.delta, s.spectral_abscissa}) finite(v, "stability point");
    finite(s.eigenvalues, "stability eigenvalues");
    if (s.eigenvalues.empty()) defect("stability point without eigenvalues");
  };
  try {
    refused([&] { check_point(stability_at_velocity(p, wob, omega)); }, "stability_at_velocity");
    refused([&] { for (const auto& s : stability_at_torque(p, wob, torque)) check_point(s); }, "stability_at_torque");
    refused([&] { for (const auto& s : stability_at_torque(p, crossings, wob, torque)) check_point(s); },
            "stability_at_torque(crossings)");
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()) != "eigenvalue solver did not converge") throw;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pydrill;
  FuzzedDataProvider in(data, size);
  Params p = preset("reduced-scale", 4);
  const int dof = in.ConsumeIntegralInRange(2, 7);
  const std::size_t springs = static_cast<std::size_t>(dof - 1);
  const bool mismatched = in.ConsumeIntegralInRange(0, 31) == 0;
  p.inertias.assign(static_cast<std::size_t>(dof), 0.0);
  p.stiffnesses.assign(springs + (mismatched ? 1 : 0), 0.0);
  p.dampings.assign(springs, 0.0);
  for (double& v : p.inertias) v = number(in, 0.03);
  for (double& v : p.stiffnesses) v = number(in, 0.073);
  for (double& v : p.dampings) v = number(in, 1e-4);
  p.top_damping = number(in, 0.18);
  p.bit_damping = number(in, 0.01);
  p.bit_radius = number(in, 0.1);
  p.mu_coulomb = number(in, 0.5);
  p.mu_static = in.ConsumeBool() ? p.mu_coulomb * (1 + std::fabs(number(in, 0.6))) : number(in, 0.8);
  p.stribeck_decay = number(in, 0.9);
  p.stribeck_velocity = number(in, 1.0);
  p.karnopp_band = number(in, 1e-6);
  const double wob = number(in, 100.0), torque = (in.ConsumeBool() ? -1 : 1) * number(in, 8.3);
  const double omega = number(in, 5.0), delta = number(in, 0.01);

  SimulationOptions o;
  o.t_end = number(in, 2.0);
  o.n_out = in.ConsumeIntegralInRange(0, 40);
  if (in.ConsumeIntegralInRange(0, 7) == 0) {
    const int k = in.ConsumeIntegralInRange(0, 6);
    for (int i = 0; i < k; ++i) o.t_out.push_back(number(in, o.t_end / 2));
  }
  o.method = static_cast<Method>(in.ConsumeIntegralInRange(0, 5));
  o.friction = static_cast<FrictionLaw>(in.ConsumeIntegralInRange(0, 1));
  o.initial = static_cast<Initial>(in.ConsumeIntegralInRange(0, 2));
  std::vector<double> state(static_cast<std::size_t>(2 * dof - 1), 0.0);
  for (double& v : state) v = number(in, 1.0);
  if (o.initial == Initial::State) o.state = state;  // refused with any other initial
  o.perturbation = in.ConsumeBool() ? 1e-3 : number(in, 0.01);
  o.rtol = in.ConsumeBool() ? 1e-6 : number(in, 1e-6);
  o.atol = in.ConsumeBool() ? 1e-8 : number(in, 1e-8);
  o.max_step = in.ConsumeBool() ? 0.0 : number(in, 0.01);
  o.max_order = in.ConsumeIntegralInRange(0, 7) == 0 ? in.ConsumeIntegralInRange(-1, 13) : 0;
  o.max_steps = in.ConsumeIntegralInRange<long>(1, 3000);
  o.window_fraction = in.ConsumeBool() ? 0.5 : number(in, 0.5);
  o.max_switch_rate = in.ConsumeBool() ? 1e4 : number(in, 1e4);
  const int interrupt_after = in.ConsumeIntegralInRange(-1, 3);
  if (interrupt_after >= 0) {  // a callback that stops the run, or throws its own exception
    auto calls = std::make_shared<int>(0);
    o.interrupt = [calls, interrupt_after] {
      if (++*calls > interrupt_after) {
        if (interrupt_after == 3) throw std::domain_error("user");
        return true;
      }
      return false;
    };
  }

  if (std::getenv("PYDRILL_FUZZ_PRINT")) {  // a crash's input, readably
    auto list = [](const char* name, const std::vector<double>& v) {
      std::printf("%s = {", name);
      for (double x : v) std::printf("%.17g, ", x);
      std::printf("}\n");
    };
    list("inertias", p.inertias);
    list("stiffnesses", p.stiffnesses);
    list("dampings", p.dampings);
    std::printf("top_damping %.17g bit_damping %.17g bit_radius %.17g mu_c %.17g mu_s %.17g decay %.17g "
                "v_f %.17g band %.17g\nwob %.17g torque %.17g omega %.17g delta %.17g\n",
                p.top_damping, p.bit_damping, p.bit_radius, p.mu_coulomb, p.mu_static, p.stribeck_decay,
                p.stribeck_velocity, p.karnopp_band, wob, torque, omega, delta);
    std::printf("t_end %.17g n_out %d t_out %zu method %d friction %d initial %d rtol %g atol %g "
                "max_step %g max_order %d max_steps %ld window %g switch_rate %g perturbation %g interrupt %d\n",
                o.t_end, o.n_out, o.t_out.size(), static_cast<int>(o.method), static_cast<int>(o.friction),
                static_cast<int>(o.initial), o.rtol, o.atol, o.max_step, o.max_order, o.max_steps,
                o.window_fraction, o.max_switch_rate, o.perturbation, interrupt_after);
    list("t_out", o.t_out);
    list("state", o.state);
    std::fflush(stdout);
  }
  const bool bad_params = refused([&] { p.validate(); }, "validate");
  try {
    const bool bad = refused([&] { check_result(simulate(p, wob, torque, o), p, o); }, "simulate");
    if (bad_params && !bad) defect("simulate accepted Params that validate refused");
  } catch (const SolverError& e) {
    finite(e.t_reached(), "t_reached");
  } catch (const Interrupted&) {
  } catch (const std::domain_error&) {  // the callback's own exception passes through
  }
  if (!bad_params) {
    // inf only where the ratio is beyond the doubles (long double: 1e4932).
    long double flex = 0, mass = 0, decay = 0;
    for (int i = 0; i + 1 < p.dof(); ++i) flex += 1.0L / p.stiffnesses[i], mass += p.inertias[i];
    const double r = stiffness_ratio(p), d = estimate_stiffness(p).fastest_decay;
    decay = d;
    if (!std::isfinite(r) && decay * std::sqrt(flex * mass) < 1e308L) defect("stiffness_ratio not finite");
    stability(p, wob, torque, omega, delta);
  }
  return 0;
}
