// CVODES backends: BDF with the chain solver, and Adams with fixed-point
// iteration. Quadratures (top angle and energy ledger) ride along under error
// control.
#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "chain_solver.hpp"
#include "integrator.hpp"
#include "sundials_compat.hpp"
#include "vectors.hpp"

namespace pydrill::detail {
namespace {

int rhs_fn(sunrealtype, N_Vector y, N_Vector ydot, void* ud) {
  const auto* d = static_cast<RunData*>(ud);
  d->chain->rhs(N_VGetArrayPointer(y), d->mode, N_VGetArrayPointer(ydot));
  return 0;
}

int quad_fn(sunrealtype, N_Vector y, N_Vector q, void* ud) {
  quadrature_rhs(*static_cast<RunData*>(ud), N_VGetArrayPointer(y), N_VGetArrayPointer(q));
  return 0;
}

// The error weights 1/(rtol·|y_i| + atol) in one pass: CVODES's own (cvEwtSetSS) makes four
// over the state at every step (|y|, ·rtol, +atol, 1/·), the same operations in the same
// order, so the weights are bit for bit the same. atol > 0 (kMinAtol): no weight is infinite.
int error_weights(N_Vector y, N_Vector w, void* ud) {
  const auto* d = static_cast<const RunData*>(ud);
  const double rtol = d->rtol, atol = d->atol;
  const double* yy = N_VGetArrayPointer(y);
  double* ww = N_VGetArrayPointer(w);
  const sunindextype n = N_VGetLength(y);
  for (sunindextype i = 0; i < n; ++i) ww[i] = 1.0 / (rtol * std::fabs(yy[i]) + atol);
  return 0;
}

struct CvodeDeleter {
  void operator()(void* mem) const { CVodeFree(&mem); }
};

std::string flag_text(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string s = name ? name : std::to_string(flag);
  free(name);
  return s;
}

class Cvodes final : public Integrator {
 public:
  Cvodes(Method method, RunData& data, const std::vector<double>& y0, const SimulationOptions& opt)
      : data_(data), opt_(opt), method_(method), n_(data.chain->size()) {
    y_.reset(make_vector(n_, ctx_));
    tmp_.reset(make_vector(n_, ctx_));
    q_.reset(make_vector(kQuads, ctx_));
    qtmp_.reset(make_vector(kQuads, ctx_));
    std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y_.get()));
    N_VConst(0.0, q_.get());

    mem_.reset(CVodeCreate(method == Method::BDF ? CV_BDF : CV_ADAMS, ctx_));
    if (!mem_) throw std::runtime_error("CVodeCreate failed");
    void* m = mem_.get();
    capture_cvode_messages(m, ctx_, &message_);
    check(CVodeInit(m, rhs_fn, 0.0, y_.get()), "CVodeInit");
    check(CVodeSetUserData(m, &data_), "CVodeSetUserData");
    check(CVodeWFtolerances(m, error_weights), "CVodeWFtolerances");
    check(CVodeSetMaxNumSteps(m, 1'000'000), "CVodeSetMaxNumSteps");
    check(CVodeSetMaxErrTestFails(m, 20), "CVodeSetMaxErrTestFails");
    check(CVodeSetMaxConvFails(m, 50), "CVodeSetMaxConvFails");
    if (opt.max_step > 0) check(CVodeSetMaxStep(m, opt.max_step), "CVodeSetMaxStep");
    if (opt.max_order > 0) check(CVodeSetMaxOrd(m, opt.max_order), "CVodeSetMaxOrd");
    check(CVodeSetStopTime(m, opt.t_end), "CVodeSetStopTime");
    check(CVodeRootInit(m, kRoots, root_callback), "CVodeRootInit");
    check(CVodeSetNoInactiveRootWarn(m), "CVodeSetNoInactiveRootWarn");
    set_directions();
    work_.assign(static_cast<std::size_t>(n_), 0.0);
    watch_.reset(data_, 0.0, state());
    check(CVodeQuadInit(m, quad_fn, q_.get()), "CVodeQuadInit");
    check(CVodeQuadSStolerances(m, opt.rtol, opt.atol), "CVodeQuadSStolerances");
    check(CVodeSetQuadErrCon(m, SUNTRUE), "CVodeSetQuadErrCon");
    if (method == Method::BDF) {
      ls_data_.cvode_mem = m;
      ls_data_.chain = data_.chain;
      ls_data_.mode = &data_.mode;
      ls_.reset(make_chain_solver(ctx_, &ls_data_));
      check(CVodeSetLinearSolver(m, ls_.get(), nullptr), "CVodeSetLinearSolver");
    } else {
      nls_.reset(SUNNonlinSol_FixedPoint(y_.get(), 0, ctx_));
      check(CVodeSetNonlinearSolver(m, nls_.get()), "CVodeSetNonlinearSolver");
    }
  }

  Status step(double t_end, double& t) override {
    const int flag = CVode(mem_.get(), t_end, y_.get(), &t, CV_ONE_STEP);
    if (flag < 0) {
      std::ostringstream o;
      o << "CVODES failed at t = " << t << " s (" << flag_text(flag) << "): " << message_;
      throw SolverError(o.str(), t);
    }
    sunrealtype tq;
    CVodeGetQuad(mem_.get(), &tq, q_.get());
    if (flag == CV_ROOT_RETURN) return Status::Root;
    // CVODES sees roots at sign changes between step ends; one that crossed and came back
    // inside the step is looked for here, on CVODES's own interpolant.
    auto at = [this](double tt, double* y) {
      CVodeGetDky(mem_.get(), tt, 0, tmp_.get());
      std::copy_n(N_VGetArrayPointer(tmp_.get()), n_, y);
    };
    double troot;
    if (watch_.check(data_, t, state(), at, work_.data(), troot, hidden_found_)) {
      std::copy_n(work_.data(), n_, state());
      CVodeGetQuadDky(mem_.get(), troot, 0, q_.get());
      t = troot;
      hidden_ = true;
      return Status::Root;
    }
    if (flag == CV_TSTOP_RETURN) return Status::Stop;
    return Status::Step;
  }

  double* state() override { return N_VGetArrayPointer(y_.get()); }
  double* quadratures() override { return N_VGetArrayPointer(q_.get()); }

  void interpolate(double t, double* y, double* q) override {
    CVodeGetDky(mem_.get(), t, 0, tmp_.get());
    CVodeGetQuadDky(mem_.get(), t, 0, qtmp_.get());
    std::copy_n(N_VGetArrayPointer(tmp_.get()), n_, y);
    std::copy_n(N_VGetArrayPointer(qtmp_.get()), kQuads, q);
  }

  void roots_found(int found[kRoots]) override {
    if (hidden_) {
      std::copy_n(hidden_found_, kRoots, found);
    } else {
      CVodeGetRootInfo(mem_.get(), found);
    }
  }

  void restart(double t) override {
    void* m = mem_.get();
    check(CVodeReInit(m, t, y_.get()), "CVodeReInit");
    check(CVodeQuadReInit(m, q_.get()), "CVodeQuadReInit");
    check(CVodeSetStopTime(m, opt_.t_end), "CVodeSetStopTime");
    set_directions();
    // The chain solver's factors depend on γ alone and the bit's row is refreshed at every
    // solve: they stay valid across a switch.
    base_ = counters();  // ReInit zeroes CVODES's counters
    hidden_ = false;
    watch_.reset(data_, t, state());
  }

  void collect(SolverStats& s) override {
    const Counters c = counters();
    s.method = method_;
    s.steps += c.steps - base_.steps;
    s.rhs_evals += c.rhs - base_.rhs;
    s.err_test_fails += c.etf - base_.etf;
    s.nonlin_iters += c.nni - base_.nni;
    s.nonlin_conv_fails += c.ncf - base_.ncf;
    s.root_evals += c.ge - base_.ge + watch_.evals() - watch_reported_;
    watch_reported_ = watch_.evals();
    // The chain solver is matrix-embedded: CVODES never calls a setup for it (cvLsInitialize
    // drops lsetup for such solvers, so CVodeGetNumLinSolvSetups stays 0). Its setups are the
    // refactorisations it does itself, inside a solve, when γ has moved.
    s.lin_setups += c.factorizations - base_.factorizations;
    s.jac_evals += c.factorizations - base_.factorizations;
    s.lin_solves += ls_data_.solves - base_.solves;
    base_ = c;
  }

  long steps_since_restart() override { return counters().steps - base_.steps; }

 private:
  struct Counters {
    long steps = 0, rhs = 0, etf = 0, nni = 0, ncf = 0, ge = 0;
    long factorizations = 0, solves = 0;
  };
  Counters counters() {
    void* m = mem_.get();
    Counters c;
    CVodeGetNumSteps(m, &c.steps);
    CVodeGetNumRhsEvals(m, &c.rhs);
    CVodeGetNumErrTestFails(m, &c.etf);
    CVodeGetNumNonlinSolvIters(m, &c.nni);
    CVodeGetNumNonlinSolvConvFails(m, &c.ncf);
    CVodeGetNumGEvals(m, &c.ge);
    c.factorizations = ls_data_.factorizations;
    c.solves = ls_data_.solves;
    return c;
  }
  void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + flag_text(flag) + " " + message_);
  }
  void set_directions() {
    int dir[kRoots];
    root_directions(data_, dir);
    check(CVodeSetRootDirection(mem_.get(), dir), "CVodeSetRootDirection");
  }

  RunData& data_;
  const SimulationOptions& opt_;
  StepWatch watch_;
  std::vector<double> work_;
  bool hidden_ = false;
  int hidden_found_[kRoots] = {};
  long watch_reported_ = 0;
  Method method_;
  int n_;
  Context ctx_;
  ChainSolverData ls_data_;
  VectorPtr y_, tmp_, q_, qtmp_;
  std::unique_ptr<void, CvodeDeleter> mem_;
  LinearSolverPtr ls_;
  NonlinearSolverPtr nls_;
  std::string message_;
  Counters base_;
};

}  // namespace

std::unique_ptr<Integrator> make_cvodes(Method method, RunData& data, const std::vector<double>& y0,
                                        const SimulationOptions& opt) {
  return std::make_unique<Cvodes>(method, data, y0, opt);
}

}  // namespace pydrill::detail
