#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define PYDRILL_HAVE_MXCSR 1
#endif

#include "integrator.hpp"
#include "pydrill/equilibrium.hpp"
#include "shortest.hpp"
#include "summary.hpp"

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
  if (!std::isfinite(t_end) || !(t_end > 0)) refuse("t_end = " + num(t_end) + " is not allowed: must be a finite time > 0 s");
  // Below kMinRtol a step's error is rounding: CVODES and ARKODE stop with "too much
  // accuracy requested" at 1e-16, DOP853 grinds on. Below kMinAtol the weight 1/atol of a
  // component sitting at 0 swamps the error norm: BDF took 3.7 million steps at 1e-30 and
  // every method failed with NaN step sizes at 1e-300.
  // Above kMaxRtol and kMaxAtol a step's error misjudges the regime (simulator.hpp).
  if (!(rtol >= kMinRtol) || !(rtol <= kMaxRtol)) refuse("rtol = " + num(rtol) + " is not allowed: need " + num(kMinRtol) + " <= rtol <= " + num(kMaxRtol) + " (a double resolves ~2.2e-16; a looser tolerance misjudges the regime)");
  if (!(atol >= kMinAtol) || !(atol <= kMaxAtol)) refuse("atol = " + num(atol) + " is not allowed: need " + num(kMinAtol) + " <= atol <= " + num(kMaxAtol) + " (rad and rad/s; a looser tolerance misjudges the regime)");
  if (!(max_step >= 0) || !std::isfinite(max_step)) refuse("max_step = " + num(max_step) + " is not allowed: must be >= 0 (0 = no limit)");
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
  if (!(max_switch_rate > 0) || std::isnan(max_switch_rate)) refuse("max_switch_rate = " + num(max_switch_rate) + " is not allowed: must be > 0 switches/s");
  if (!std::isfinite(perturbation) || std::fabs(perturbation) >= 1) refuse("perturbation = " + num(perturbation) + " is not allowed: need |perturbation| < 1 (relative to the steady bit velocity)");
  if (t_out.empty()) {
    if (n_out < 2 || n_out > 100'000'000) refuse("n_out = " + std::to_string(n_out) + " is not allowed: need 2 <= n_out <= 1e8");
  } else {
    for (std::size_t i = 0; i < t_out.size(); ++i) {
      const double t = t_out[i];
      if (!std::isfinite(t) || t < 0 || t > t_end) refuse("t_out[" + std::to_string(i) + "] = " + num(t) + " is not allowed: output times must lie in [0, t_end = " + num(t_end) + "]");
      if (i > 0 && !(t > t_out[i - 1])) refuse("t_out[" + std::to_string(i) + "] = " + num(t) + " is not allowed: output times must increase strictly");
    }
  }
  if (initial == Initial::State) {
    const std::size_t n = static_cast<std::size_t>(2 * dof - 1);
    if (state.size() != n) refuse("state has " + std::to_string(state.size()) + " entries: dof = " + std::to_string(dof) + " needs 2*dof-1 = " + std::to_string(n) + " (w_0, theta_0, ..., theta_{N-2}, w_bit)");
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(state[i])) refuse("state[" + std::to_string(i) + "] = " + num(state[i]) + " is not allowed: must be finite");
    }
  }
}

StiffnessEstimate estimate_stiffness(const Params& p) {
  p.validate();
  const int N = p.dof();
  StiffnessEstimate e;
  // Gershgorin bounds on M⁻¹K (squared frequencies) and M⁻¹C (decay rates).
  double w2max = 0.0;
  for (int i = 0; i < N; ++i) {
    double ksum = 0.0, csum = (i == 0 ? p.top_damping : 0.0) + (i == N - 1 ? p.bit_damping : 0.0);
    if (i > 0) { ksum += p.stiffnesses[i - 1]; csum += p.dampings[i - 1]; }
    if (i < N - 1) { ksum += p.stiffnesses[i]; csum += p.dampings[i]; }
    w2max = std::max(w2max, 2.0 * ksum / p.inertias[i]);
    e.fastest_decay = std::max(e.fastest_decay, 2.0 * csum / p.inertias[i]);
  }
  e.fastest_frequency = std::sqrt(w2max);
  // Fundamental: the string clamped at a still bit, lumped as one spring
  // (series compliance) and the inertia above it (Rayleigh quotient).
  double compliance = 0.0, inertia = 0.0;
  for (int i = 0; i < N - 1; ++i) { compliance += 1.0 / p.stiffnesses[i]; inertia += p.inertias[i]; }
  e.fundamental = std::sqrt(1.0 / (compliance * inertia));
  return e;
}

double stiffness_ratio(const Params& p) {
  const StiffnessEstimate e = estimate_stiffness(p);
  return e.fastest_decay / e.fundamental;
}

Method choose_method(const Params& p, std::string* reason) {
  // Stiff means fast modes that decay: BDF steps over them once they have died.
  // Otherwise every method must resolve the fast modes, and the cheapest steps
  // win: DOP853, which restarts at full order after each friction switch and
  // spends almost nothing besides the right-hand side. Measured by
  // benchmarks/bench_methods.py on soft, real, stiff and refined strings:
  // DOP853 is the fastest up to a decay/fundamental ratio of ~1e4 even with
  // overdamped fast modes (3x BDF at 1.8e3); BDF wins only beyond.
  const StiffnessEstimate e = estimate_stiffness(p);
  const double zeta = e.fastest_decay / (2.0 * e.fastest_frequency);
  const double ratio = e.fastest_decay / e.fundamental;
  constexpr double zeta_stiff = 0.5, ratio_stiff = 1e4;
  Method m = Method::DOP853;
  const char* why = "non-stiff: explicit Runge-Kutta DOP853";
  if (zeta > zeta_stiff && ratio > ratio_stiff) {
    m = Method::BDF;
    why = "stiff (fast modes die quickly): BDF with the banded chain solver";
  }
  if (reason) {
    std::ostringstream o;
    o.precision(3);
    o << why << " (fastest decay " << e.fastest_decay << "/s = " << ratio
      << "x the fundamental " << e.fundamental << " rad/s; damping ratio of the fastest modes "
      << zeta << ")";
    *reason = o.str();
  }
  return m;
}

namespace {

using detail::Integrator;
using detail::kQuads;
using detail::kRoots;

// The mode machine: integrates one smooth piece after another, decides at each
// root which mode comes next, keeps the outputs, the switch log and the trace
// the regime is judged on.
class Run {
 public:
  Run(const Chain& chain, const SimulationOptions& opt, const std::vector<double>& y0, Method method)
      : chain_(chain), opt_(opt), n_(chain.size()) {
    data_.chain = &chain_;
    data_.karnopp = opt.friction == FrictionLaw::Karnopp;
    data_.ts = chain.static_torque();
    data_.dv = chain.params().karnopp_band;
    data_.rtol = opt.rtol;
    data_.atol = opt.atol;
    data_.mode = chain.initial_mode(y0.data(), data_.karnopp);
    if (method == Method::DOP853) {
      integrator_ = detail::make_dop853(data_, y0, opt);
    } else if (method == Method::ERK) {
      integrator_ = detail::make_erk(data_, y0, opt);
    } else {
      integrator_ = detail::make_cvodes(method, data_, y0, opt);
    }
    res_.stats.method = method;
  }

  Result run();

 private:
  void record_output(double t, const double* y, const double* q);
  void handle_root(double t);
  void restart(double t);
  bool falls_back_inside(const double* y, double te) const;
  void fail(const SolverError& e);

  const Chain& chain_;
  const SimulationOptions& opt_;
  int n_;
  detail::RunData data_;
  std::unique_ptr<Integrator> integrator_;
  Result res_;
  detail::Trace trace_;
  std::vector<detail::ModeChange> modes_;
};

void Run::record_output(double t, const double* y, const double* q) {
  res_.t.push_back(t);
  res_.states.insert(res_.states.end(), y, y + n_);
  res_.top_angle.push_back(q[0]);
  res_.work_input.push_back(q[1]);
  res_.viscous_loss.push_back(q[2]);
  res_.friction_loss.push_back(q[3]);
  res_.energy.push_back(chain_.energy(y));
  res_.modes.push_back(static_cast<int>(data_.mode));
}

void Run::handle_root(double t) {
  double* y = integrator_->state();
  const int b = chain_.bit_index();
  const double ts = data_.ts;
  int found[kRoots] = {0, 0, 0, 0};
  integrator_->roots_found(found);
  double g[kRoots];
  detail::root_functions(data_, y, g);
  double residual = g[0];
  for (int i = 0; i < kRoots; ++i) {
    if (found[i]) {
      residual = g[i];
      break;
    }
  }

  const Mode before = data_.mode;
  Mode after = before;
  SwitchKind kind = SwitchKind::Stick;
  if (!data_.karnopp) {
    if (before == Mode::Stick) {
      // T_e reached ±T_s: the rock lets go in the direction of T_e.
      after = found[0] ? Mode::SlipPositive : Mode::SlipNegative;
      kind = SwitchKind::Slip;
    } else {
      // ω_b crossed zero. The integrator stops just past the root: put the
      // bit exactly at rest, then let the reaction torque decide.
      y[b] = 0.0;
      const double te = chain_.reaction_torque(y);
      if (std::fabs(te) <= ts || falls_back_inside(y, te)) {
        after = Mode::Stick;
        kind = SwitchKind::Stick;
      } else if ((te > 0) != (before == Mode::SlipPositive)) {
        after = te > 0 ? Mode::SlipPositive : Mode::SlipNegative;
        kind = SwitchKind::Reversal;
      } else {
        // A graze: the torque pushes the bit on in its own direction.
        after = before;
        kind = SwitchKind::Slip;
      }
    }
  } else {
    // Karnopp: |ω_b| < D_v is the band. Held there (mode Stick: friction = T_e,
    // ω_b frozen) while |T_e| <= T_s, creeping (mode Band: friction = ±T_s)
    // beyond. Each sub-mode has a smooth right-hand side, so no step straddles
    // the kink of the clipped friction.
    const double te = chain_.reaction_torque(y);
    if (before == Mode::Stick) {
      data_.mode = Mode::Band;  // T_e reached ±T_s: the bit starts to creep
      restart(t);
      return;
    }
    if (before == Mode::Band && !found[0] && !found[1]) {
      data_.mode = Mode::Stick;  // T_e fell back inside ±T_s: held again
      restart(t);
      return;
    }
    if (before == Mode::Band) {
      after = found[0] ? Mode::SlipPositive : Mode::SlipNegative;
      kind = SwitchKind::BandLeave;
    } else {
      after = std::fabs(te) <= ts ? Mode::Stick : Mode::Band;
      kind = SwitchKind::BandEnter;
    }
  }
  data_.mode = after;
  const int direction = after == Mode::SlipPositive ? 1 : after == Mode::SlipNegative ? -1 : 0;
  res_.switches.push_back({t, kind, direction, chain_.reaction_torque(y), residual});
  modes_.push_back({t, after});

  // Zeno guard: a burst of switches in a vanishing time is chattering.
  constexpr std::size_t burst = 50;
  const auto& sw = res_.switches;
  if (sw.size() > burst) {
    const double dt = t - sw[sw.size() - 1 - burst].t;
    if (dt < static_cast<double>(burst) / opt_.max_switch_rate) {
      std::ostringstream o;
      o << "chattering: " << burst << " friction switches within " << dt << " s near t = " << t
        << " s (limit max_switch_rate = " << opt_.max_switch_rate << " /s)";
      throw SolverError(o.str(), t);
    }
  }
  restart(t);
}

bool Run::falls_back_inside(const double* y, double te) const {
  // The bit came to rest with |T_e| on the static limit, within the noise of
  // locating the switch that started this slip (a graze of T_s). If T_e is
  // heading back inside ±T_s the rock holds the bit; slipping on would start
  // it the wrong way.
  const double ts = data_.ts;
  if (std::fabs(te) - ts > 1e-9 * ts) return false;
  std::vector<double> ydot(static_cast<std::size_t>(n_));
  chain_.rhs(y, Mode::Stick, ydot.data());
  const double rate = chain_.reaction_torque(ydot.data());  // T_e is linear in y
  return te > 0 ? rate < 0 : rate > 0;
}

void Run::restart(double t) {
  // History from the old mode is invalid: the integrator starts afresh here.
  integrator_->collect(res_.stats);
  integrator_->restart(t);
  ++res_.stats.reinits;
}

// Subnormal numbers flushed to zero while a simulation runs (this thread only,
// restored after). A string started from rest winds up from its top: ahead of
// the torsional wave the states are exponentially small, and arithmetic on
// subnormals costs ~100x: measured, 200 pipes from rest ran 2x slower per step
// than from equilibrium. Nothing below 2e-308 matters at any tolerance.
// The caller's own code — options.interrupt, which a program that embeds pydrill may use to
// run its event loop, and Python's signal handlers — runs with the caller's setting: see
// ask().
class FlushSubnormals {
 public:
#ifdef PYDRILL_HAVE_MXCSR
  FlushSubnormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040); }  // FTZ | DAZ
  ~FlushSubnormals() { _mm_setcsr(saved_); }
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;
#endif

  // interrupt() under the caller's floating-point setting, ours again after it (or after an
  // exception from it). It ran with subnormals flushed: a callback's arithmetic on numbers
  // below 2e-308 silently gave 0 there.
  bool ask(const std::function<bool()>& interrupt) const {
#ifdef PYDRILL_HAVE_MXCSR
    struct Caller {
      unsigned ours;
      explicit Caller(unsigned theirs) : ours(_mm_getcsr()) { _mm_setcsr(theirs); }
      ~Caller() { _mm_setcsr(ours); }
    } caller(saved_);
#endif
    return interrupt();
  }

#ifdef PYDRILL_HAVE_MXCSR
 private:
  unsigned saved_;
#endif
};

Result Run::run() {
  const FlushSubnormals flush;
  const double t_end = opt_.t_end;
  std::vector<double> tout = opt_.t_out;
  if (tout.empty()) {
    tout.resize(static_cast<std::size_t>(opt_.n_out));
    for (int i = 0; i < opt_.n_out; ++i) tout[i] = t_end * i / (opt_.n_out - 1);
    tout.back() = t_end;
  }
  const double wstart = t_end * (1.0 - opt_.window_fraction);
  res_.dof = chain_.dof();
  res_.wob = chain_.wob();
  res_.torque = chain_.torque();
  res_.t.reserve(tout.size());
  res_.states.reserve(tout.size() * static_cast<std::size_t>(n_));
  modes_.push_back({0.0, data_.mode});

  const int b = chain_.bit_index();
  auto bit_angle = [&](const double* y, double top) {
    double s = top;  // φ_b = φ_0 − Σ θ_i
    for (int i = 0; i < chain_.dof() - 1; ++i) s -= y[2 * i + 1];
    return s;
  };
  detail::WindowAngles w{wstart, t_end, 0, 0, 0, 0};
  auto sample = [&](double t, const double* y) {
    if (t < wstart) return;
    trace_.t.push_back(t);
    trace_.bit.push_back(y[b]);
    trace_.top.push_back(y[0]);
    trace_.dbit.push_back(chain_.bit_acceleration(y, data_.mode));
    trace_.dtop.push_back(chain_.top_acceleration(y));
  };

  std::size_t k = 0;
  const double* y = integrator_->state();
  const double* q = integrator_->quadratures();
  while (k < tout.size() && tout[k] <= 0.0) record_output(0.0, y, q), ++k;
  bool window_open = wstart <= 0.0;
  if (window_open) {
    sample(0.0, y);
    w.bit0 = bit_angle(y, 0.0);
  }

  std::vector<double> yt(static_cast<std::size_t>(n_)), qt(kQuads);
  double t = 0.0;
  // The clock is read every 64 steps (a step is a microsecond or more), the caller asked
  // every 0.1 s: a Ctrl-C stops a long run at once, at no measurable cost.
  using clock = std::chrono::steady_clock;
  auto next_poll = clock::now() + std::chrono::milliseconds(100);
  long polls = 0;
  try {
    while (t < t_end) {
      if (opt_.interrupt && (++polls & 63) == 0 && clock::now() >= next_poll) {
        if (flush.ask(opt_.interrupt)) throw Interrupted(t);
        next_poll = clock::now() + std::chrono::milliseconds(100);
      }
      const double tprev = t;
      const Integrator::Status status = integrator_->step(t_end, t);
      y = integrator_->state();
      q = integrator_->quadratures();
      // Dense output: requested times inside the step just taken.
      if (!window_open && t >= wstart && tprev <= wstart) {
        integrator_->interpolate(wstart, yt.data(), qt.data());
        w.top0 = qt[0];
        w.bit0 = bit_angle(yt.data(), qt[0]);
        sample(wstart, yt.data());
        window_open = true;
      }
      while (k < tout.size() && tout[k] <= t) {
        if (tout[k] == t) {
          record_output(t, y, q);
        } else {
          integrator_->interpolate(tout[k], yt.data(), qt.data());
          record_output(tout[k], yt.data(), qt.data());
          sample(tout[k], yt.data());
        }
        ++k;
      }
      if (status == Integrator::Status::Root) handle_root(t);
      sample(t, y);
      if (res_.stats.steps + integrator_->steps_since_restart() > opt_.max_steps) {
        std::ostringstream o;
        o << "max_steps = " << opt_.max_steps << " internal steps reached at t = " << t
          << " s; raise max_steps or shorten t_end";
        throw SolverError(o.str(), t);
      }
      if (status == Integrator::Status::Stop) break;
    }
  } catch (const SolverError&) {
    integrator_->collect(res_.stats);
    throw;
  }
  integrator_->collect(res_.stats);
  w.top1 = q[0];
  w.bit1 = bit_angle(y, q[0]);
  res_.stats.switches = static_cast<long>(res_.switches.size());
  std::function<bool()> interrupt;
  if (opt_.interrupt) interrupt = [&] { return flush.ask(opt_.interrupt); };
  try {  // the judgement may need the string's crossings: stoppable too, as the run was
    res_.summary = detail::summarize(chain_, trace_, modes_, w, data_.karnopp,
                                     detail::steady_swing_for_tolerance(opt_.rtol), interrupt);
  } catch (const StabilityInterrupted&) {
    throw Interrupted(opt_.t_end);
  }
  return std::move(res_);
}

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

}  // namespace

Result simulate(const Params& params, double wob, double torque, const SimulationOptions& options) {
  params.validate();
  check_operating_point(wob, torque);
  check_simulated_loads(wob, torque);
  options.validate(params.dof());
  const Chain chain(params, wob, torque);
  std::string reason;
  Method method = options.method;
  if (method == Method::Auto) {
    method = choose_method(params, &reason);
  } else {
    reason = "requested";
  }
  const std::vector<double> y0 = initial_state(params, wob, torque, options);
  check_step_budget(params, options, method);
  const auto wall0 = std::chrono::steady_clock::now();
  Run run(chain, options, y0, method);
  Result r = run.run();
  r.stats.method = method;
  r.stats.method_reason = reason;
  r.stats.stiffness_ratio = stiffness_ratio(params);
  r.stats.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace pydrill

