// What every integrator backend shares: the discrete state of the friction
// (mode) and the root functions that end each smooth piece of the motion.
#pragma once

#include <sundials/sundials_nvector.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pydrill/model.hpp"

namespace pydrill::detail {

constexpr int kQuads = 4;  // φ_0, ∫u ω_0 dt, ∫viscous dissipation dt, ∫friction dissipation dt
constexpr int kRoots = 4;  // slots; unused ones hold a constant so they never fire

// Read by the right-hand side and the root functions, changed only at
// switches: the right-hand side stays pure.
struct RunData {
  const Chain* chain = nullptr;
  Mode mode = Mode::Stick;
  bool karnopp = false;
  double ts = 0.0, dv = 0.0;
  double rtol = 0.0, atol = 0.0;  // the run's tolerances (CVODES's error weights, in one pass)
};

// Right-hand side with the quadrature integrands riding along as four extra
// states (the explicit integrators have no separate quadratures).
inline void rhs_with_quadratures(const RunData& d, const double* y, double* f) {
  double* q = f + d.chain->size();
  q[0] = y[0];
  d.chain->rhs(y, d.mode, f, q + 1);
}

// Quadrature integrands (power balance and the top angle).
inline void quadrature_rhs(const RunData& d, const double* y, double* q) {
  q[0] = y[0];
  q[1] = d.chain->input_power(y);
  q[2] = d.chain->viscous_power(y, d.mode);
  q[3] = d.chain->friction_power(y, d.mode);
}

// Root functions of the current mode; each is non-zero right after its mode
// is entered, so CVODES/ARKODE never start on a blind zero.
void root_functions(const RunData& d, const double* y, double* g);
void root_directions(const RunData& d, int dir[kRoots]);

// dg/dt along the motion, from f = dy/dt: every root function is affine in y (ω_b ∓ D_v,
// T_e ∓ T_s, with T_e linear in the state), so its rate is its linear part applied to f.
void root_rates(const RunData& d, const double* f, double* gdot);

// Does g go from lo to hi across zero in the wanted direction (+1 rising, −1 falling, 0
// either)? A landing exactly on zero counts; leaving zero does not.
inline bool crosses(double lo, double hi, int dir) {
  return (lo < 0 && hi >= 0 && dir >= 0) || (lo > 0 && hi <= 0 && dir <= 0);
}

// Rootfinders look at the signs at both ends of a step, so a function that crosses zero and
// comes back within one step goes unseen: a stuck bit whose reaction torque rises past T_s
// and falls back within one long step stays stuck (seen: dof 2 held at T_e = 8.19 N·m with
// T_s = 8). The cubic through a function's values g and rates r at both ends of the step
// [t0, t1] says where it turns. The time of a turn towards zero that comes near it (closer
// than half its smaller end value: the cubic errs by far less), at which the interpolant
// must decide; NaN when there is none.
double hidden_turn(double t0, double t1, double g0, double g1, double r0, double r1, int dir);

// Illinois-modified regula falsi on an interpolant between tlo and thi, across which some
// active function crosses in its direction; all functions at once (as CVODE's rootfinder).
// state_at(t, y) writes the interpolated state. Returns the far end of a bracket narrower
// than 100 ulp of t; glo/ghi end as the functions at the bracket's ends, found as which
// crossed (+1 rising, −1 falling, 0 not).
struct RootBracket {
  double tlo, thi;
  double glo[kRoots], ghi[kRoots];
};
template <class StateAt>
double locate_root(const RunData& d, const int dir[kRoots], const bool active[kRoots],
                   StateAt&& state_at, double* y, RootBracket& b, int found[kRoots], long& evals);

// The same rates from the state alone, in O(1), for backends without f at hand.
void root_rates_at(const RunData& d, const double* y, double* gdot);

// What the SUNDIALS backends keep to catch a hidden crossing (DOP853 has it built in): the
// root functions and their rates at the end of the last step.
class StepWatch {
 public:
  // At a (re)start at t from state y, in the current mode.
  void reset(const RunData& d, double t, const double* y);
  // After a step to t1 (state y1) in which the backend found no root; state_at(t, y)
  // interpolates inside the step. On a hidden crossing: true, with the root's time in troot,
  // the state there in y (size of the state), and which functions fired in found.
  template <class StateAt>
  bool check(const RunData& d, double t1, const double* y1, StateAt&& state_at, double* y,
             double& troot, int found[kRoots]);
  long evals() const { return evals_; }

 private:
  double t0_ = 0.0, g0_[kRoots] = {}, r0_[kRoots] = {};
  int dir_[kRoots] = {};
  bool active_[kRoots] = {};
  long evals_ = 0;
};

// SUNDIALS callback shape (user data = RunData).
int root_callback(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data);

}  // namespace pydrill::detail

namespace pydrill::detail {

template <class StateAt>
double locate_root(const RunData& d, const int dir[kRoots], const bool active[kRoots],
                   StateAt&& state_at, double* y, RootBracket& b, int found[kRoots], long& evals) {
  const double ttol =
      100.0 * std::numeric_limits<double>::epsilon() * (std::fabs(b.thi) + std::fabs(b.thi - b.tlo));
  auto any_crossing = [&](const double* lo, const double* hi) {
    for (int i = 0; i < kRoots; ++i)
      if (active[i] && crosses(lo[i], hi[i], dir[i])) return true;
    return false;
  };
  double gmid[kRoots];
  double alpha = 1.0;
  int last = 0;  // +1: thi moved last time, −1: tlo moved
  for (int iter = 0; b.thi - b.tlo > ttol && iter < 200; ++iter) {
    // The function whose secant root lies earliest decides the trial point.
    double tmid = 0.5 * (b.tlo + b.thi);
    if (iter < 100) {
      double best = -1.0;
      for (int i = 0; i < kRoots; ++i) {
        if (!active[i] || !crosses(b.glo[i], b.ghi[i], dir[i])) continue;
        const double denom = b.ghi[i] - alpha * b.glo[i];
        const double frac = denom != 0.0 ? b.ghi[i] / denom : 0.5;
        if (frac > best) {
          best = frac;
          tmid = b.thi - (b.thi - b.tlo) * frac;
        }
      }
    }
    const double margin = 0.5 * ttol;
    tmid = std::clamp(tmid, b.tlo + margin, b.thi - margin);
    state_at(tmid, y);
    root_functions(d, y, gmid);
    ++evals;
    if (any_crossing(b.glo, gmid)) {
      b.thi = tmid;
      std::copy_n(gmid, kRoots, b.ghi);
      alpha = last == 1 ? 0.5 : 1.0;
      last = 1;
    } else {
      b.tlo = tmid;
      std::copy_n(gmid, kRoots, b.glo);
      alpha = last == -1 ? 2.0 : 1.0;
      last = -1;
    }
  }
  for (int i = 0; i < kRoots; ++i)
    found[i] = (active[i] && crosses(b.glo[i], b.ghi[i], dir[i])) ? (b.ghi[i] > b.glo[i] ? 1 : -1) : 0;
  return b.thi;
}

}  // namespace pydrill::detail

namespace pydrill::detail {

template <class StateAt>
bool StepWatch::check(const RunData& d, double t1, const double* y1, StateAt&& state_at,
                      double* y, double& troot, int found[kRoots]) {
  double g1[kRoots], r1[kRoots], gin[kRoots];
  root_functions(d, y1, g1);
  root_rates_at(d, y1, r1);
  ++evals_;
  for (int i = 0; i < kRoots; ++i) {
    if (!active_[i]) continue;
    const double tt = hidden_turn(t0_, t1, g0_[i], g1[i], r0_[i], r1[i], dir_[i]);
    if (std::isnan(tt)) continue;
    state_at(tt, y);
    root_functions(d, y, gin);
    ++evals_;
    bool crossed = false;
    for (int j = 0; j < kRoots; ++j) crossed = crossed || (active_[j] && crosses(g0_[j], gin[j], dir_[j]));
    if (!crossed) continue;
    RootBracket b{t0_, tt, {}, {}};
    std::copy_n(g0_, kRoots, b.glo);
    std::copy_n(gin, kRoots, b.ghi);
    troot = locate_root(d, dir_, active_, state_at, y, b, found, evals_);
    state_at(troot, y);
    return true;
  }
  t0_ = t1;
  std::copy_n(g1, kRoots, g0_);
  std::copy_n(r1, kRoots, r0_);
  for (int i = 0; i < kRoots; ++i) active_[i] = active_[i] || g1[i] != 0.0;
  return false;
}

}  // namespace pydrill::detail
