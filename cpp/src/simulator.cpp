// simulate: the run loop (class Run, the mode machine that integrates one smooth piece after
// another) and the steps around it. The options' names and validation are in
// simulation_options.cpp, the method "auto" picks in method_choice.cpp, the initial state and
// the checks before integrating in simulation_setup.cpp.
#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "flush_subnormals.hpp"
#include "integrator.hpp"
#include "simulation_setup.hpp"
#include "summary.hpp"

namespace pydrill {

namespace {

using detail::FlushSubnormals;
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

}  // namespace

Result simulate(const Params& params, double wob, double torque, const SimulationOptions& options) {
  params.validate();
  check_operating_point(wob, torque);
  detail::check_simulated_loads(wob, torque);
  options.validate(params.dof());
  const Chain chain(params, wob, torque);
  std::string reason;
  Method method = options.method;
  if (method == Method::Auto) {
    method = choose_method(params, &reason);
  } else {
    reason = "requested";
  }
  const std::vector<double> y0 = detail::initial_state(params, wob, torque, options);
  detail::check_step_budget(params, options, method);
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
