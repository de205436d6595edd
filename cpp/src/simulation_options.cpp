// The simulation options' names (method, regime, friction law, initial state, switch kind),
// their parsers, and SimulationOptions::validate: what simulate refuses before it starts.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "pydrill/simulator.hpp"
#include "shortest.hpp"

namespace pydrill {

const char* method_name(Method m) noexcept {
  switch (m) {
    case Method::Auto: return "auto";
    case Method::BDF: return "bdf";
    case Method::Adams: return "adams";
    case Method::ERK: return "erk";
    case Method::DOP853: return "dop853";
  }
  return "?";
}

const char* regime_name(Regime r) noexcept {
  switch (r) {
    case Regime::Steady: return "steady";
    case Regime::StickSlip: return "stick-slip";
    case Regime::Stuck: return "stuck";
    case Regime::Oscillation: return "oscillation";
  }
  return "?";
}

Regime parse_regime(const std::string& s) {
  if (s == "steady") return Regime::Steady;
  if (s == "stick-slip") return Regime::StickSlip;
  if (s == "stuck") return Regime::Stuck;
  if (s == "oscillation") return Regime::Oscillation;
  throw std::invalid_argument("regime = '" + s +
                              "' is not allowed: choose 'steady', 'stick-slip', 'stuck' or 'oscillation'");
}

const char* switch_kind_name(SwitchKind k) noexcept {
  switch (k) {
    case SwitchKind::Stick: return "stick";
    case SwitchKind::Slip: return "slip";
    case SwitchKind::Reversal: return "reversal";
    case SwitchKind::BandEnter: return "band-enter";
    case SwitchKind::BandLeave: return "band-leave";
  }
  return "?";
}

Method parse_method(const std::string& s) {
  if (s == "auto") return Method::Auto;
  if (s == "bdf") return Method::BDF;
  if (s == "adams") return Method::Adams;
  if (s == "erk") return Method::ERK;
  if (s == "dop853") return Method::DOP853;
  throw std::invalid_argument("method = '" + s +
                              "' is not allowed: choose 'auto', 'bdf', 'adams', 'erk' or 'dop853'");
}

FrictionLaw parse_friction(const std::string& s) {
  if (s == "exact") return FrictionLaw::Exact;
  if (s == "karnopp") return FrictionLaw::Karnopp;
  throw std::invalid_argument("friction = '" + s + "' is not allowed: choose 'exact' or 'karnopp'");
}

Initial parse_initial(const std::string& s) {
  if (s == "rest") return Initial::Rest;
  if (s == "equilibrium") return Initial::Equilibrium;
  if (s == "state") return Initial::State;
  throw std::invalid_argument("initial = '" + s +
                              "' is not allowed: choose 'rest', 'equilibrium' or a state vector");
}

void SimulationOptions::validate(int dof) const {
  auto refuse = [](const std::string& what) { throw std::invalid_argument(what); };
  const auto num = detail::shortest;
  // validate is public: a program may check its options before it builds its strings. The
  // dof is the string's (Params::dof()), and a string has at least 2; a dof of 0 passed, and
  // Initial::State's 2·dof − 1 (int) came out as 18446744073709551615, or overflowed (undefined)
  // from INT_MAX / 2 + 1 on. Counted in std::size_t below, it cannot.
  if (dof < 2) refuse("dof = " + std::to_string(dof) + " is not allowed: options are checked for a string of dof >= 2 inertias (Params::dof())");
  if (!std::isfinite(t_end) || !(t_end > 0)) refuse("t_end = " + num(t_end) + " is not allowed: must be a finite time > 0 s");
  if (t_end > kMaxTEnd) refuse("t_end = " + num(t_end) + " is not allowed: need 0 < t_end <= " + num(kMaxTEnd) + " s (317 years; beyond, a run's times overflow)");
  // Below kMinRtol a step's error is rounding: CVODES and ARKODE stop with "too much
  // accuracy requested" at 1e-16, DOP853 grinds on. Below kMinAtol the weight 1/atol of a
  // component sitting at 0 swamps the error norm: BDF took 3.7 million steps at 1e-30 and
  // every method failed with NaN step sizes at 1e-300.
  // Above kMaxRtol and kMaxAtol a step's error misjudges the regime (simulator.hpp).
  if (!(rtol >= kMinRtol) || !(rtol <= kMaxRtol)) refuse("rtol = " + num(rtol) + " is not allowed: need " + num(kMinRtol) + " <= rtol <= " + num(kMaxRtol) + " (a double resolves ~2.2e-16; a looser tolerance misjudges the regime)");
  if (!(atol >= kMinAtol) || !(atol <= kMaxAtol)) refuse("atol = " + num(atol) + " is not allowed: need " + num(kMinAtol) + " <= atol <= " + num(kMaxAtol) + " (rad and rad/s; a looser tolerance misjudges the regime)");
  if (!(max_step >= 0) || !std::isfinite(max_step)) refuse("max_step = " + num(max_step) + " is not allowed: must be >= 0 (0 = no limit)");
  // A run flushes subnormals (below): a max_step of 1e-320 s reached the integrators as 0, and
  // they failed with "h = nan" (CVODES) or "its step size became NaN (the state or its error
  // estimate overflowed)" (ARKODE), naming neither max_step nor the cause.
  if (max_step > 0 && max_step < std::numeric_limits<double>::min()) {
    refuse("max_step = " + num(max_step) + " is not allowed: 0 (no limit) or at least 2.23e-308 s (the smallest normal float, which the core computes with)");
  }
  // An enum holds any value of its type: a cast (static_cast<Method>(42)) ran as if it
  // were a method and reported "?".
  if (std::string(method_name(method)) == "?") refuse("method = " + std::to_string(static_cast<int>(method)) + " is not a pydrill::Method");
  if (friction != FrictionLaw::Exact && friction != FrictionLaw::Karnopp) refuse("friction = " + std::to_string(static_cast<int>(friction)) + " is not a pydrill::FrictionLaw");
  if (initial != Initial::Rest && initial != Initial::Equilibrium && initial != Initial::State) refuse("initial = " + std::to_string(static_cast<int>(initial)) + " is not a pydrill::Initial");
  if (max_steps < 1) refuse("max_steps = " + std::to_string(max_steps) + " is not allowed: must be >= 1");
  // CVODES caps BDF at order 5 and Adams at 12; the explicit methods have a fixed order, so
  // a max_order there would be silently ignored. "auto" may pick either family: it takes
  // no order.
  if (max_order != 0) {
    const int cap = method == Method::BDF ? 5 : method == Method::Adams ? 12 : 0;
    if (cap == 0) {
      refuse("max_order = " + std::to_string(max_order) + " is not allowed with method '" + method_name(method) +
             "': only 'bdf' (1..5) and 'adams' (1..12) take an order; use 0 (the method's default)");
    }
    if (max_order < 1 || max_order > cap) {
      refuse("max_order = " + std::to_string(max_order) + " is not allowed with method '" + method_name(method) +
             "': need 0 (the method's default) or 1.." + std::to_string(cap));
    }
  }
  if (!(window_fraction > 0) || !(window_fraction <= 1)) refuse("window_fraction = " + num(window_fraction) + " is not allowed: need 0 < window_fraction <= 1");
  // The window opens at t_end·(1 − window_fraction), as the run computes it: below ~1.1e-16
  // that is t_end itself, and an empty window was judged anyway ("steady", its mean bit
  // velocity 0 beside a min and max of 18.3 rad/s).
  if (std::isfinite(t_end) && t_end > 0 && !(t_end * (1.0 - window_fraction) < t_end)) {
    refuse("window_fraction = " + num(window_fraction) + " is not allowed with t_end = " + num(t_end) +
           " s: the judged window, the run's last t_end * window_fraction, rounds to nothing; need window_fraction >= 1.2e-16 (a window of a few of the string's slowest periods judges best)");
  }
  if (!(max_switch_rate > 0) || std::isnan(max_switch_rate)) refuse("max_switch_rate = " + num(max_switch_rate) + " is not allowed: must be > 0 switches/s");
  if (!std::isfinite(perturbation) || std::fabs(perturbation) >= 1) refuse("perturbation = " + num(perturbation) + " is not allowed: need |perturbation| < 1 (relative to the steady bit velocity)");
  // A run flushes subnormal numbers to 0 (flush_subnormals.hpp): output times below the
  // smallest normal double are 0 to it. t_end = 5e-324 s was judged "steady" from rest, and
  // t_out = {0, 1e-320, 1} came back as times {0, 0, 1}.
  constexpr double tiny = std::numeric_limits<double>::min();
  if (t_out.empty()) {
    if (n_out < 2 || n_out > 100'000'000) refuse("n_out = " + std::to_string(n_out) + " is not allowed: need 2 <= n_out <= 1e8");
    const double spacing = t_end / (n_out - 1);
    if (spacing < tiny) {
      refuse("t_end = " + num(t_end) + " is not allowed with n_out = " + std::to_string(n_out) + ": its output times would be " + num(spacing) +
             " s apart, below the smallest normal float (2.23e-308) the core computes with; need t_end >= (n_out - 1) * 2.2e-308 s");
    }
  } else {
    if (t_end < tiny) refuse("t_end = " + num(t_end) + " is not allowed: below the smallest normal float (2.23e-308 s), which the core computes with");
    for (std::size_t i = 0; i < t_out.size(); ++i) {
      const double t = t_out[i];
      if (!std::isfinite(t) || t < 0 || t > t_end) refuse("t_out[" + std::to_string(i) + "] = " + num(t) + " is not allowed: output times must lie in [0, t_end = " + num(t_end) + "]");
      if (t > 0 && t < tiny) refuse("t_out[" + std::to_string(i) + "] = " + num(t) + " is not allowed: an output time is 0 or at least 2.23e-308 s (the smallest normal float, which the core computes with)");
      if (i > 0 && !(t > t_out[i - 1])) refuse("t_out[" + std::to_string(i) + "] = " + num(t) + " is not allowed: output times must increase strictly");
    }
  }
  if (initial == Initial::State) {
    const std::size_t n = 2 * static_cast<std::size_t>(dof) - 1;
    if (state.size() != n) refuse("state has " + std::to_string(state.size()) + " entries: dof = " + std::to_string(dof) + " needs 2*dof-1 = " + std::to_string(n) + " (w_0, theta_0, ..., theta_{N-2}, w_bit)");
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(state[i])) refuse("state[" + std::to_string(i) + "] = " + num(state[i]) + " is not allowed: must be finite");
    }
  } else if (!state.empty()) {
    // A state given without Initial::State was silently ignored, as a max_order would be
    // (above): the run started from rest, or from the steady state, not from it.
    refuse("state has " + std::to_string(state.size()) + (state.size() == 1 ? " entry" : " entries") + " but initial = '" +
           (initial == Initial::Rest ? "rest" : "equilibrium") +
           "' does not use it: set initial = Initial::State to start from it, or leave state empty");
  }
}

}  // namespace pydrill
