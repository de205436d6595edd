#include "events.hpp"

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
