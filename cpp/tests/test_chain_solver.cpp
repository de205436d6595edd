// The chain solver's setup count, checked against a count kept outside it.
#include <catch2/catch.hpp>

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>

#include <cmath>
#include <vector>

#include "chain_solver.hpp"
#include "pydrill/simulator.hpp"
#include "sundials_compat.hpp"
#include "vectors.hpp"

using namespace pydrill;

namespace {

// A watcher around the chain solver's solve: it reads γ from CVODES itself at every solve and
// counts the solves that must refactor (γ differs from the last solve's, or the last solve
// failed), without looking at the solver's own counters.
struct Watch {
  int (*inner_solve)(SUNLinearSolver, SUNMatrix, N_Vector, N_Vector, sunrealtype) = nullptr;
  void* cvode_mem = nullptr;
  long solves = 0, gamma_changes = 0, failures = 0;
  bool have_last = false, last_failed = false;
  double last_gamma = 0.0;
};
Watch* watch = nullptr;

int watched_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, sunrealtype tol) {
  double gamma = 0.0;
  CVodeGetCurrentGamma(watch->cvode_mem, &gamma);
  if (!watch->have_last || gamma != watch->last_gamma || watch->last_failed) ++watch->gamma_changes;
  watch->have_last = true;
  watch->last_gamma = gamma;
  const int flag = watch->inner_solve(S, A, x, b, tol);
  watch->last_failed = flag != detail::kLinSolSuccess;
  watch->failures += watch->last_failed;
  ++watch->solves;
  return flag;
}

int chain_rhs(sunrealtype, N_Vector y, N_Vector ydot, void* ud) {
  const auto* chain = static_cast<const Chain*>(ud);
  chain->rhs(N_VGetArrayPointer(y), Mode::Stick, N_VGetArrayPointer(ydot));
  return 0;
}

}  // namespace

TEST_CASE("the chain solver's setups are the times it refactored, as counted from outside",
          "[simulator][methods]") {
  // A stiff string (overdamped springs, decay 1e4 times faster than the wind-up) held at the
  // bit, wound up from rest by the surface torque: BDF changes its step size again and again.
  Params p = preset("reduced-scale", 12);
  for (double& c : p.dampings) c = 20.0;
  REQUIRE(stiffness_ratio(p) > 1e3);
  const Chain chain(p, 100.0, 8.3);
  const Mode mode = Mode::Stick;
  detail::Context ctx;
  const int n = chain.size();
  detail::VectorPtr y(detail::make_vector(n, ctx));
  N_VConst(0.0, y.get());
  void* mem = CVodeCreate(CV_BDF, ctx);
  REQUIRE(mem != nullptr);
  REQUIRE(CVodeInit(mem, chain_rhs, 0.0, y.get()) == CV_SUCCESS);
  REQUIRE(CVodeSetUserData(mem, const_cast<Chain*>(&chain)) == CV_SUCCESS);
  REQUIRE(CVodeSStolerances(mem, 1e-8, 1e-8) == CV_SUCCESS);
  detail::ChainSolverData data;
  data.cvode_mem = mem;
  data.chain = &chain;
  data.mode = &mode;
  detail::LinearSolverPtr ls(detail::make_chain_solver(ctx, &data));
  Watch w;
  w.inner_solve = ls->ops->solve;
  w.cvode_mem = mem;
  watch = &w;
  ls->ops->solve = watched_solve;
  REQUIRE(CVodeSetLinearSolver(mem, ls.get(), nullptr) == CV_SUCCESS);
  double t = 0.0;
  REQUIRE(CVode(mem, 200.0, y.get(), &t, CV_NORMAL) == CV_SUCCESS);
  long steps = 0, nni = 0, etf = 0, ncf = 0;
  CVodeGetNumSteps(mem, &steps);
  CVodeGetNumNonlinSolvIters(mem, &nni);
  CVodeGetNumErrTestFails(mem, &etf);
  CVodeGetNumNonlinSolvConvFails(mem, &ncf);
  CVodeFree(&mem);
  watch = nullptr;

  CHECK(data.factorizations == w.gamma_changes);
  CHECK(data.factorizations > 10);
  // One γ per step attempt (a step, or a retry after an error test or a Newton failure).
  CHECK(data.factorizations <= steps + etf + ncf);
  // Far fewer than the solves: γ is kept while the step size holds.
  CHECK(data.factorizations * 2 < w.solves);
  CHECK(data.solves == w.solves - w.failures);
  CHECK(data.solves <= nni);  // at most one solve per Newton iteration
}

TEST_CASE("SolverStats::lin_setups counts BDF's refactorisations, and 0 without a linear solver",
          "[simulator][methods]") {
  // Stick-slip on a 12-inertia string: six switches, seven smooth pieces (the stiff tally
  // string of test_simulator.cpp checks the same on a stiff run).
  Params p = preset("reduced-scale", 12);
  for (double& c : p.dampings) c = 0.05;
  SimulationOptions o;
  o.t_end = 300.0;
  o.method = Method::BDF;
  const Result r = simulate(p, 100.0, 8.3, o);
  const SolverStats& s = r.stats;
  REQUIRE(s.switches > 0);  // several smooth pieces: the counts are summed across restarts
  CHECK(s.lin_setups > s.reinits);  // at least one per piece: every restart starts a new step size
  CHECK(s.lin_setups <= s.steps + s.err_test_fails + s.nonlin_conv_fails);
  CHECK(s.lin_setups * 2 < s.lin_solves);
  CHECK(s.lin_solves <= s.nonlin_iters);
  CHECK(s.lin_setups == s.jac_evals);
  for (Method m : {Method::Adams, Method::DOP853, Method::ERK}) {
    o.method = m;
    CHECK(simulate(p, 100.0, 8.3, o).stats.lin_setups == 0);
  }
}
