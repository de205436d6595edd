// ARKODE explicit Runge–Kutta backend (Fehlberg 7(8)). A one-step method restarts
// after a friction switch at full order, where a multistep method climbs back
// from order 1 — with switches every few seconds that is most of the work.
// ARKODE has no quadratures, so the energy ledger and the top angle ride
// along as four extra states (harmless for an explicit method).
#include <arkode/arkode_erkstep.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "integrator.hpp"

// SUNDIALS 7.1 moved ARKODE's step-module functions to a shared ARKode* API
// and deprecated the ERKStep* names; pick whichever this SUNDIALS prefers.
#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 1)
#define PYDRILL_ARK(name) ARKode##name
#else
#define PYDRILL_ARK(name) ERKStep##name
#endif
#include "sundials_compat.hpp"
#include "vectors.hpp"

namespace pydrill::detail {

#if SUNDIALS_VERSION_MAJOR < 7
void capture_arkode_messages(void* arkode_mem, SUNContext, std::string* sink) {
  ERKStepSetErrHandlerFn(arkode_mem, store_message, sink);
}
#endif

namespace {

int rhs_fn(sunrealtype, N_Vector y, N_Vector ydot, void* ud) {
  const auto* d = static_cast<RunData*>(ud);
  const double* Y = N_VGetArrayPointer(y);
  double* F = N_VGetArrayPointer(ydot);
  rhs_with_quadratures(*d, Y, F);
  return 0;
}

struct ArkodeDeleter {
  void operator()(void* mem) const { PYDRILL_ARK(Free)(&mem); }
};

std::string flag_text(int flag) {
  char* name = PYDRILL_ARK(GetReturnFlagName)(flag);
  std::string s = name ? name : std::to_string(flag);
  free(name);
  return s;
}

class Erk final : public Integrator {
 public:
  Erk(RunData& data, const std::vector<double>& y0, const SimulationOptions& opt)
      : data_(data), opt_(opt), n_(data.chain->size()) {
    y_.reset(make_vector(n_ + kQuads, ctx_));
    tmp_.reset(make_vector(n_ + kQuads, ctx_));
    std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y_.get()));  // quadratures start at 0

    mem_.reset(ERKStepCreate(rhs_fn, 0.0, y_.get(), ctx_));
    if (!mem_) throw std::runtime_error("ERKStepCreate failed");
    void* m = mem_.get();
    capture_arkode_messages(m, ctx_, &message_);
    check(PYDRILL_ARK(SetUserData)(m, &data_), "ERKStepSetUserData");
    // Fehlberg 7(8), 13 stages: measured against Verner 6(5) on the paper's
    // stick-slip case, 4x fewer steps and 3000x smaller energy-balance error.
    check(ERKStepSetTableNum(m, ARKODE_FEHLBERG_13_7_8), "ERKStepSetTableNum");
    check(PYDRILL_ARK(SStolerances)(m, opt.rtol, opt.atol), "ERKStepSStolerances");
    check(PYDRILL_ARK(SetMaxNumSteps)(m, 1'000'000), "ERKStepSetMaxNumSteps");
    check(PYDRILL_ARK(SetMaxErrTestFails)(m, 20), "ERKStepSetMaxErrTestFails");
    if (opt.max_step > 0) check(PYDRILL_ARK(SetMaxStep)(m, opt.max_step), "ERKStepSetMaxStep");
    check(PYDRILL_ARK(SetStopTime)(m, opt.t_end), "ERKStepSetStopTime");
    check(PYDRILL_ARK(RootInit)(m, kRoots, root_callback), "ERKStepRootInit");
    check(PYDRILL_ARK(SetNoInactiveRootWarn)(m), "ERKStepSetNoInactiveRootWarn");
    set_directions();
    work_.assign(static_cast<std::size_t>(n_), 0.0);
    watch_.reset(data_, 0.0, state());
  }

  Status step(double t_end, double& t) override {
    const int flag = PYDRILL_ARK(Evolve)(mem_.get(), t_end, y_.get(), &t, ARK_ONE_STEP);
    if (flag < 0) {
      std::ostringstream o;
      if (std::isfinite(t)) {
        o << "ARKODE failed at t = " << t << " s (" << flag_text(flag) << "): " << message_;
      } else {
        // ARKODE hands back t = NaN when its step size became NaN (an overflowing state or
        // error estimate); its own message then quotes the NaNs. Report the last time
        // reached instead.
        t = t_reached_;
        o << "ARKODE failed at t = " << t << " s (" << flag_text(flag)
          << "): its step size became NaN (the state or its error estimate overflowed)";
      }
      throw SolverError(o.str(), t);
    }
    t_reached_ = t;
    if (flag == ARK_ROOT_RETURN) return Status::Root;
    // ARKODE sees roots at sign changes between step ends; one that crossed and came back
    // inside the step is looked for here, on ARKODE's own interpolant.
    auto at = [this](double tt, double* y) {
      PYDRILL_ARK(GetDky)(mem_.get(), tt, 0, tmp_.get());
      std::copy_n(N_VGetArrayPointer(tmp_.get()), n_, y);
    };
    double troot;
    if (watch_.check(data_, t, state(), at, work_.data(), troot, hidden_found_)) {
      PYDRILL_ARK(GetDky)(mem_.get(), troot, 0, y_.get());  // state and quadratures there
      t = t_reached_ = troot;
      hidden_ = true;
      return Status::Root;
    }
    if (flag == ARK_TSTOP_RETURN) return Status::Stop;
    return Status::Step;
  }

  double* state() override { return N_VGetArrayPointer(y_.get()); }
  double* quadratures() override { return N_VGetArrayPointer(y_.get()) + n_; }

  void interpolate(double t, double* y, double* q) override {
    PYDRILL_ARK(GetDky)(mem_.get(), t, 0, tmp_.get());
    const double* v = N_VGetArrayPointer(tmp_.get());
    std::copy_n(v, n_, y);
    std::copy_n(v + n_, kQuads, q);
  }

  void roots_found(int found[kRoots]) override {
    if (hidden_) {
      std::copy_n(hidden_found_, kRoots, found);
    } else {
      PYDRILL_ARK(GetRootInfo)(mem_.get(), found);
    }
  }

  void restart(double t) override {
    void* m = mem_.get();
    // Start the new piece with the last accepted step: a one-step method
    // needs no ramp-up, and the error test shrinks it if the switch demands.
    sunrealtype h = 0.0;
    PYDRILL_ARK(GetLastStep)(m, &h);
    check(ERKStepReInit(m, rhs_fn, t, y_.get()), "ERKStepReInit");
    if (h > 0) check(PYDRILL_ARK(SetInitStep)(m, h), "ERKStepSetInitStep");
    check(PYDRILL_ARK(SetStopTime)(m, opt_.t_end), "ERKStepSetStopTime");
    set_directions();
    base_ = counters();
    hidden_ = false;
    t_reached_ = t;
    watch_.reset(data_, t, state());
  }

  void collect(SolverStats& s) override {
    const Counters c = counters();
    s.method = Method::ERK;
    s.steps += c.steps - base_.steps;
    s.rhs_evals += c.rhs - base_.rhs;
    s.err_test_fails += c.etf - base_.etf;
    s.root_evals += c.ge - base_.ge + watch_.evals() - watch_reported_;
    watch_reported_ = watch_.evals();
    base_ = c;
  }

  long steps_since_restart() override { return counters().steps - base_.steps; }

 private:
  struct Counters {
    long steps = 0, rhs = 0, etf = 0, ge = 0;
  };
  Counters counters() {
    void* m = mem_.get();
    Counters c;
    PYDRILL_ARK(GetNumSteps)(m, &c.steps);
    ERKStepGetNumRhsEvals(m, &c.rhs);
    PYDRILL_ARK(GetNumErrTestFails)(m, &c.etf);
    PYDRILL_ARK(GetNumGEvals)(m, &c.ge);
    return c;
  }
  void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + flag_text(flag) + " " + message_);
  }
  void set_directions() {
    int dir[kRoots];
    root_directions(data_, dir);
    check(PYDRILL_ARK(SetRootDirection)(mem_.get(), dir), "ERKStepSetRootDirection");
  }

  RunData& data_;
  const SimulationOptions& opt_;
  int n_;
  StepWatch watch_;
  std::vector<double> work_;
  bool hidden_ = false;
  double t_reached_ = 0.0;  // the last time reached: what a failure reports if ARKODE says NaN
  int hidden_found_[kRoots] = {};
  long watch_reported_ = 0;
  Context ctx_;
  VectorPtr y_, tmp_;
  std::unique_ptr<void, ArkodeDeleter> mem_;
  std::string message_;
  Counters base_;
};

}  // namespace

std::unique_ptr<Integrator> make_erk(RunData& data, const std::vector<double>& y0,
                                     const SimulationOptions& opt) {
  return std::make_unique<Erk>(data, y0, opt);
}

}  // namespace pydrill::detail
