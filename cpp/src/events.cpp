#include "events.hpp"

#include "hermite.hpp"

namespace pydrill::detail {

void root_functions(const RunData& d, const double* Y, double* g) {
  const double wb = Y[d.chain->bit_index()];
  g[0] = g[1] = g[2] = g[3] = 1.0;
  switch (d.mode) {
    case Mode::SlipPositive: g[0] = d.karnopp ? wb - d.dv : wb; break;
    case Mode::SlipNegative: g[0] = d.karnopp ? wb + d.dv : wb; break;
    case Mode::Stick: {
      // Held by the rock (exact friction, or inside the Karnopp band): only
      // the reaction torque reaching ±T_s ends it.
      const double te = d.chain->reaction_torque(Y);
      g[0] = te - d.ts;
      g[1] = te + d.ts;
      break;
    }
    case Mode::Band: {
      // Creeping inside the Karnopp band (|T_e| > T_s): the bit leaves the
      // band, or T_e falls back inside ±T_s and the rock holds it again.
      const double te = d.chain->reaction_torque(Y);
      g[0] = wb - d.dv;
      g[1] = wb + d.dv;
      g[2] = te - d.ts;
      g[3] = te + d.ts;
      break;
    }
  }
}

void root_rates(const RunData& d, const double* f, double* gdot) {
  const double wb = f[d.chain->bit_index()];
  gdot[0] = gdot[1] = gdot[2] = gdot[3] = 0.0;
  switch (d.mode) {
    case Mode::SlipPositive:
    case Mode::SlipNegative: gdot[0] = wb; break;
    case Mode::Stick: gdot[0] = gdot[1] = d.chain->reaction_torque(f); break;
    case Mode::Band: {
      const double te = d.chain->reaction_torque(f);
      gdot[0] = gdot[1] = wb;
      gdot[2] = gdot[3] = te;
      break;
    }
  }
}

double hidden_turn(double t0, double t1, double g0, double g1, double r0, double r1, int dir) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  const double h = t1 - t0;
  // Same sign at both ends, and a crossing from g0's side wanted.
  if (!(h > 0.0) || g0 == 0.0 || (g0 > 0) != (g1 > 0) || !crosses(g0, -g0, dir)) return none;
  const double m0 = h * r0, m1 = h * r1;
  // Towards zero at the start, away from it at the end: a turn inside the step.
  if (!(m0 * g0 < 0.0 && m1 * g1 > 0.0)) return none;
  double x, p;
  if (!hermite_turn(g0, g1, m0, m1, x, p)) return none;
  if ((g0 > 0 ? p : -p) > 0.5 * std::min(std::fabs(g0), std::fabs(g1))) return none;
  return t0 + x * h;
}

void root_rates_at(const RunData& d, const double* y, double* gdot) {
  gdot[0] = gdot[1] = gdot[2] = gdot[3] = 0.0;
  switch (d.mode) {
    case Mode::SlipPositive:
    case Mode::SlipNegative: gdot[0] = d.chain->bit_acceleration(y, d.mode); break;
    case Mode::Stick: gdot[0] = gdot[1] = d.chain->reaction_rate(y, d.mode); break;
    case Mode::Band: {
      const double wb = d.chain->bit_acceleration(y, d.mode), te = d.chain->reaction_rate(y, d.mode);
      gdot[0] = gdot[1] = wb;
      gdot[2] = gdot[3] = te;
      break;
    }
  }
}

void StepWatch::reset(const RunData& d, double t, const double* y) {
  t0_ = t;
  root_directions(d, dir_);
  root_functions(d, y, g0_);
  root_rates_at(d, y, r0_);
  // A function on zero (ω_b = 0 entering slip) waits until it leaves zero, as in CVODE.
  for (int i = 0; i < kRoots; ++i) active_[i] = g0_[i] != 0.0;
}

void root_directions(const RunData& d, int dir[kRoots]) {
  dir[0] = dir[1] = dir[2] = dir[3] = 0;
  switch (d.mode) {
    case Mode::SlipPositive: dir[0] = -1; break;
    case Mode::SlipNegative: dir[0] = +1; break;
    case Mode::Stick: dir[0] = +1; dir[1] = -1; break;
    case Mode::Band:
      dir[0] = +1;
      dir[1] = -1;
      dir[2] = -1;  // T_e falls back below T_s
      dir[3] = +1;  // T_e rises back above −T_s
      break;
  }
}

int root_callback(sunrealtype, N_Vector y, sunrealtype* g, void* user_data) {
  root_functions(*static_cast<const RunData*>(user_data), N_VGetArrayPointer(y), g);
  return 0;
}

}  // namespace pydrill::detail
