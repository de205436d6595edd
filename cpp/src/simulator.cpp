#include "pydrill/simulator.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "chain_solver.hpp"
#include "pydrill/equilibrium.hpp"
#include "summary.hpp"
#include "sundials_compat.hpp"
#include "vectors.hpp"

namespace pydrill {

const char* method_name(Method m) {
  switch (m) {
    case Method::Auto: return "auto";
    case Method::BDF: return "bdf";
    case Method::Adams: return "adams";
  }
  return "?";
}

const char* switch_kind_name(SwitchKind k) {
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
  throw std::invalid_argument("method = '" + s + "' is not allowed: choose 'auto', 'bdf' or 'adams'");
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
  auto num = [](double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
  };
  if (!std::isfinite(t_end) || !(t_end > 0)) refuse("t_end = " + num(t_end) + " is not allowed: must be a finite time > 0 s");
  if (!(rtol > 0) || !(rtol < 1) || !std::isfinite(rtol)) refuse("rtol = " + num(rtol) + " is not allowed: need 0 < rtol < 1");
  if (!(atol > 0) || !std::isfinite(atol)) refuse("atol = " + num(atol) + " is not allowed: must be a finite number > 0");
  if (!(max_step >= 0) || !std::isfinite(max_step)) refuse("max_step = " + num(max_step) + " is not allowed: must be >= 0 (0 = no limit)");
  if (max_steps < 1) refuse("max_steps = " + std::to_string(max_steps) + " is not allowed: must be >= 1");
  if (max_order < 0 || max_order > 12) refuse("max_order = " + std::to_string(max_order) + " is not allowed: need 0 (method default) or 1..12 (Adams), 1..5 (BDF)");
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
  // Fast modes that only ring must be resolved by any method, and then Adams'
  // cheap fixed-point steps win. Thresholds measured by
  // benchmarks/bench_methods.py (Adams vs BDF on soft, real and refined strings).
  const StiffnessEstimate e = estimate_stiffness(p);
  const double zeta = e.fastest_decay / (2.0 * e.fastest_frequency);
  const double ratio = e.fastest_decay / e.fundamental;
  constexpr double zeta_min = 0.5, ratio_min = 100.0;
  const bool stiff = zeta > zeta_min && ratio > ratio_min;
  if (reason) {
    std::ostringstream o;
    o.precision(3);
    o << "fastest decay " << e.fastest_decay << "/s = " << ratio << "x the fundamental "
      << e.fundamental << " rad/s, damping ratio of the fastest modes " << zeta << ": "
      << (stiff ? "stiff, BDF with the banded chain solver" : "non-stiff, Adams");
    *reason = o.str();
  }
  return stiff ? Method::BDF : Method::Adams;
}

namespace {

constexpr int kQuads = 4;  // φ_0, ∫u ω_0, ∫viscous, ∫friction

struct RunData {
  const Chain* chain;
  Mode mode;
  bool karnopp;
  bool band_held;  // Karnopp band with |T_e| <= T_s: the bit cannot move
  double held_omega;  // ω_b while band_held (constant there)
  double ts, dv;
};

int rhs_fn(sunrealtype, N_Vector y, N_Vector ydot, void* ud) {
  const auto* d = static_cast<RunData*>(ud);
  d->chain->rhs(N_VGetArrayPointer(y), d->mode, N_VGetArrayPointer(ydot));
  return 0;
}

int quad_fn(sunrealtype, N_Vector y, N_Vector q, void* ud) {
  const auto* d = static_cast<RunData*>(ud);
  const double* Y = N_VGetArrayPointer(y);
  double* Q = N_VGetArrayPointer(q);
  Q[0] = Y[0];
  Q[1] = d->chain->input_power(Y);
  Q[2] = d->chain->viscous_power(Y, d->mode);
  Q[3] = d->chain->friction_power(Y, d->mode);
  return 0;
}

// Root functions per mode; each is non-zero right after its mode is entered.
// Unused slots hold a constant so they never fire.
constexpr int kRoots = 4;

int root_fn(sunrealtype, N_Vector y, sunrealtype* g, void* ud) {
  const auto* d = static_cast<RunData*>(ud);
  const double* Y = N_VGetArrayPointer(y);
  const double wb = Y[d->chain->bit_index()];
  g[0] = g[1] = g[2] = g[3] = 1.0;
  switch (d->mode) {
    case Mode::SlipPositive: g[0] = d->karnopp ? wb - d->dv : wb; break;
    case Mode::SlipNegative: g[0] = d->karnopp ? wb + d->dv : wb; break;
    case Mode::Stick: {
      const double te = d->chain->reaction_torque(Y);
      g[0] = te - d->ts;
      g[1] = te + d->ts;
      break;
    }
    case Mode::Band: {
      // Inside the band the friction clips T_e at ±T_s, a kink in the
      // right-hand side. While |T_e| <= T_s the bit is held and only T_e can
      // end that; once beyond, the bit creeps and may leave the band. Keeping
      // the two apart stops high-order steps from straddling the kink (their
      // interpolant would carry ω_b across the band edge too early).
      const double te = d->chain->reaction_torque(Y);
      if (d->band_held) {
        g[0] = te - d->ts;
        g[1] = te + d->ts;
      } else {
        g[0] = wb - d->dv;
        g[1] = wb + d->dv;
        g[2] = te - d->ts;
        g[3] = te + d->ts;
      }
      break;
    }
  }
  return 0;
}

void root_directions(Mode m, int dir[kRoots]) {
  dir[0] = dir[1] = dir[2] = dir[3] = 0;
  switch (m) {
    case Mode::SlipPositive: dir[0] = -1; break;
    case Mode::SlipNegative: dir[0] = +1; break;
    case Mode::Stick:
    case Mode::Band: dir[0] = +1; dir[1] = -1; break;
  }
}

struct CvodeDeleter {
  void operator()(void* mem) const { CVodeFree(&mem); }
};
struct VectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct SolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
struct NonlinDeleter {
  void operator()(SUNNonlinearSolver s) const { SUNNonlinSolFree(s); }
};
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;

std::string flag_text(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string s = name ? name : std::to_string(flag);
  free(name);
  return s;
}

class Run {
 public:
  Run(const Chain& chain, const SimulationOptions& opt, std::vector<double> y0, Method method)
      : chain_(chain), opt_(opt), method_(method), n_(chain.size()) {
    data_.chain = &chain_;
    data_.karnopp = opt.friction == FrictionLaw::Karnopp;
    data_.ts = chain.static_torque();
    data_.dv = chain.params().karnopp_band;
    data_.mode = chain.initial_mode(y0.data(), data_.karnopp);
    data_.band_held = std::fabs(chain.reaction_torque(y0.data())) <= data_.ts;
    data_.held_omega = y0[static_cast<std::size_t>(chain.bit_index())];

    y_.reset(detail::make_vector(n_, ctx_));
    tmp_.reset(detail::make_vector(n_, ctx_));
    q_.reset(detail::make_vector(kQuads, ctx_));
    qtmp_.reset(detail::make_vector(kQuads, ctx_));
    std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y_.get()));
    N_VConst(0.0, q_.get());

    mem_.reset(CVodeCreate(method == Method::BDF ? CV_BDF : CV_ADAMS, ctx_));
    if (!mem_) throw std::runtime_error("CVodeCreate failed");
    void* m = mem_.get();
    detail::capture_messages(m, ctx_, &message_);
    check(CVodeInit(m, rhs_fn, 0.0, y_.get()), "CVodeInit");
    check(CVodeSetUserData(m, &data_), "CVodeSetUserData");
    check(CVodeSStolerances(m, opt.rtol, opt.atol), "CVodeSStolerances");
    check(CVodeSetMaxNumSteps(m, 1'000'000), "CVodeSetMaxNumSteps");
    check(CVodeSetMaxErrTestFails(m, 20), "CVodeSetMaxErrTestFails");
    check(CVodeSetMaxConvFails(m, 50), "CVodeSetMaxConvFails");
    if (opt.max_step > 0) check(CVodeSetMaxStep(m, opt.max_step), "CVodeSetMaxStep");
    if (opt.max_order > 0) check(CVodeSetMaxOrd(m, opt.max_order), "CVodeSetMaxOrd");
    check(CVodeSetStopTime(m, opt.t_end), "CVodeSetStopTime");
    check(CVodeRootInit(m, kRoots, root_fn), "CVodeRootInit");
    check(CVodeSetNoInactiveRootWarn(m), "CVodeSetNoInactiveRootWarn");
    set_directions();
    check(CVodeQuadInit(m, quad_fn, q_.get()), "CVodeQuadInit");
    check(CVodeQuadSStolerances(m, opt.rtol, opt.atol), "CVodeQuadSStolerances");
    check(CVodeSetQuadErrCon(m, SUNTRUE), "CVodeSetQuadErrCon");
    if (method == Method::BDF) {
      lsdata_.cvode_mem = m;
      lsdata_.chain = &chain_;
      lsdata_.mode = &data_.mode;
      ls_.reset(detail::make_chain_solver(ctx_, &lsdata_));
      check(CVodeSetLinearSolver(m, ls_.get(), nullptr), "CVodeSetLinearSolver");
    } else {
      nls_.reset(SUNNonlinSol_FixedPoint(y_.get(), 0, ctx_));
      check(CVodeSetNonlinearSolver(m, nls_.get()), "CVodeSetNonlinearSolver");
    }
  }

  Result run();

 private:
  void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + flag_text(flag) + " " + message_);
  }
  void set_directions() {
    int dir[kRoots];
    root_directions(data_.mode, dir);
    check(CVodeSetRootDirection(mem_.get(), dir), "CVodeSetRootDirection");
  }
  void accumulate_stats();
  void record_output(double t, const double* y, const double* q);
  void handle_root(double t);
  void restart(double t);

  const Chain& chain_;
  const SimulationOptions& opt_;
  Method method_;
  int n_;
  detail::Context ctx_;
  RunData data_{};
  detail::ChainSolverData lsdata_;
  VectorPtr y_, tmp_, q_, qtmp_;
  std::unique_ptr<void, CvodeDeleter> mem_;
  std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, SolverDeleter> ls_;
  std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinDeleter> nls_;
  std::string message_;
  Result res_;
  detail::Trace trace_;
  std::vector<detail::ModeChange> modes_;
};

void Run::accumulate_stats() {
  void* m = mem_.get();
  long v = 0;
  SolverStats& s = res_.stats;
  CVodeGetNumSteps(m, &v); s.steps += v;
  CVodeGetNumRhsEvals(m, &v); s.rhs_evals += v;
  CVodeGetNumErrTestFails(m, &v); s.err_test_fails += v;
  CVodeGetNumNonlinSolvIters(m, &v); s.nonlin_iters += v;
  CVodeGetNumNonlinSolvConvFails(m, &v); s.nonlin_conv_fails += v;
  CVodeGetNumGEvals(m, &v); s.root_evals += v;
  if (method_ == Method::BDF) {
    CVodeGetNumLinSolvSetups(m, &v); s.lin_setups += v;
  }
}

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
  double* y = N_VGetArrayPointer(y_.get());
  const int b = chain_.bit_index();
  const double ts = data_.ts;
  int found[kRoots] = {0, 0, 0, 0};
  CVodeGetRootInfo(mem_.get(), found);
  double g[kRoots];
  root_fn(t, y_.get(), g, &data_);
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
      // ω_b crossed zero. CVODES stops just past the root: put the bit
      // exactly at rest, then let the reaction torque decide.
      y[b] = 0.0;
      const double te = chain_.reaction_torque(y);
      if (std::fabs(te) <= ts) {
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
    if (before == Mode::Band) {
      if (data_.band_held || (!found[0] && !found[1])) {
        // T_e crossed ±T_s inside the band: same mode, the other smooth piece.
        // While held, ω_b is constant; the interpolant of a step that
        // straddles the kink is not, so restore the exact value.
        if (data_.band_held) y[b] = data_.held_omega;
        data_.band_held = !data_.band_held;
        data_.held_omega = y[b];
        restart(t);
        return;
      }
      after = found[0] ? Mode::SlipPositive : Mode::SlipNegative;
      kind = SwitchKind::BandLeave;
    } else {
      after = Mode::Band;
      kind = SwitchKind::BandEnter;
      data_.band_held = std::fabs(chain_.reaction_torque(y)) <= ts;
      data_.held_omega = y[b];
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

void Run::restart(double t) {
  // Restart the integrator from the switch: history from the old mode is invalid.
  accumulate_stats();
  sunrealtype tq;
  CVodeGetQuad(mem_.get(), &tq, q_.get());
  void* m = mem_.get();
  check(CVodeReInit(m, t, y_.get()), "CVodeReInit");
  check(CVodeQuadReInit(m, q_.get()), "CVodeQuadReInit");
  check(CVodeSetStopTime(m, opt_.t_end), "CVodeSetStopTime");
  set_directions();
  lsdata_.valid = false;
  ++res_.stats.reinits;
}

Result Run::run() {
  const auto wall0 = std::chrono::steady_clock::now();
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
  };

  std::size_t k = 0;
  const double* y = N_VGetArrayPointer(y_.get());
  const double* q = N_VGetArrayPointer(q_.get());
  while (k < tout.size() && tout[k] <= 0.0) record_output(0.0, y, q), ++k;
  if (wstart <= 0.0) {
    sample(0.0, y);
    w.bit0 = bit_angle(y, 0.0);
  }
  bool window_open = wstart <= 0.0;

  double t = 0.0;
  while (t < t_end) {
    const double tprev = t;
    const int flag = CVode(mem_.get(), t_end, y_.get(), &t, CV_ONE_STEP);
    if (flag < 0) {
      accumulate_stats();
      std::ostringstream o;
      o << "CVODES failed at t = " << t << " s (" << flag_text(flag) << "): " << message_;
      throw SolverError(o.str(), t);
    }
    // Dense output: interpolate requested times inside the step just taken.
    double* yt = N_VGetArrayPointer(tmp_.get());
    const double* qt = N_VGetArrayPointer(qtmp_.get());
    auto interpolate = [&](double ti) {
      CVodeGetDky(mem_.get(), ti, 0, tmp_.get());
      CVodeGetQuadDky(mem_.get(), ti, 0, qtmp_.get());
    };
    if (!window_open && t >= wstart && tprev <= wstart) {
      interpolate(wstart);
      w.top0 = qt[0];
      w.bit0 = bit_angle(yt, qt[0]);
      sample(wstart, yt);
      window_open = true;
    }
    while (k < tout.size() && tout[k] <= t) {
      if (tout[k] == t) {
        CVodeGetQuad(mem_.get(), &t, q_.get());
        record_output(t, y, q);
      } else {
        interpolate(tout[k]);
        record_output(tout[k], yt, qt);
        sample(tout[k], yt);
      }
      ++k;
    }
    if (flag == CV_ROOT_RETURN) handle_root(t);
    sample(t, y);
    long steps = 0;
    CVodeGetNumSteps(mem_.get(), &steps);
    if (res_.stats.steps + steps > opt_.max_steps) {
      accumulate_stats();
      std::ostringstream o;
      o << "max_steps = " << opt_.max_steps << " internal steps reached at t = " << t
        << " s; raise max_steps or shorten t_end";
      throw SolverError(o.str(), t);
    }
    if (flag == CV_TSTOP_RETURN) break;
  }
  accumulate_stats();
  CVodeGetQuad(mem_.get(), &t, q_.get());
  w.top1 = q[0];
  w.bit1 = bit_angle(y, q[0]);
  res_.stats.jac_evals = lsdata_.factorizations;
  res_.stats.lin_solves = lsdata_.solves;
  res_.stats.switches = static_cast<long>(res_.switches.size());
  res_.summary = detail::summarize(chain_, trace_, modes_, w, data_.karnopp);
  res_.stats.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return std::move(res_);
}

std::vector<double> initial_state(const Params& params, double wob, double torque,
                                  const SimulationOptions& opt) {
  const int N = params.dof();
  switch (opt.initial) {
    case Initial::Rest: return std::vector<double>(static_cast<std::size_t>(2 * N - 1), 0.0);
    case Initial::State: return opt.state;
    case Initial::Equilibrium: {
      const auto omegas = equilibrium_velocities(params, wob, torque);
      if (omegas.empty()) {
        std::ostringstream o;
        o << "initial = 'equilibrium' is not possible: no steady rotation Ω > 0 exists for wob = "
          << wob << " N, torque = " << torque << " N·m (the torque cannot balance the bit friction); "
          << "start from 'rest' instead";
        throw std::invalid_argument(o.str());
      }
      // The fastest steady state: the one a driller aims for.
      auto y = equilibrium_state(params, wob, omegas.back());
      y[static_cast<std::size_t>(2 * N - 2)] *= 1.0 + opt.perturbation;
      return y;
    }
  }
  return {};
}

}  // namespace

Result simulate(const Params& params, double wob, double torque, const SimulationOptions& options) {
  params.validate();
  check_operating_point(wob, torque);
  options.validate(params.dof());
  const Chain chain(params, wob, torque);
  std::string reason;
  Method method = options.method;
  if (method == Method::Auto) {
    method = choose_method(params, &reason);
  } else {
    reason = "requested";
  }
  const auto wall0 = std::chrono::steady_clock::now();
  Run run(chain, options, initial_state(params, wob, torque, options), method);
  Result r = run.run();
  r.stats.method = method_name(method);
  r.stats.method_reason = reason;
  r.stats.stiffness_ratio = stiffness_ratio(params);
  r.stats.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace pydrill

