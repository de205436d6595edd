// Judging the regime of a finished run (DESIGN.md §2, "Regimes").
#pragma once

#include <functional>
#include <vector>

#include "pydrill/model.hpp"
#include "pydrill/simulator.hpp"

namespace pydrill::detail {

// Samples of the run inside the judging window, in time order: the bit and top-drive
// velocities and their accelerations (dbit, dtop), which place the extremes between samples.
// Without accelerations (dbit, dtop empty) the extremes are the samples'.
struct Trace {
  std::vector<double> t, bit, top, dbit, dtop;
};

struct ModeChange {
  double t;
  Mode mode;
};

struct WindowAngles {
  double t0, t1;              // window start and end
  double top0, top1;          // φ_0 at both ends
  double bit0, bit1;          // φ_b at both ends
};

// steady_swing: the relative swing of the bit velocity that the integrator's tolerance
// cannot tell from its own ringing (see steady_swing_for_tolerance). A sustained swing
// below it is steady unless the steady state it circles is linearly unstable; below
// kSwingFloor it is steady.
// interrupt: passed to the crossings an ambiguous swing needs (O(dof²): seconds at thousands
// of inertias); StabilityInterrupted when it says stop.
Summary summarize(const Chain& chain, const Trace& trace, const std::vector<ModeChange>& modes,
                  const WindowAngles& angles, bool karnopp, double steady_swing = 2e-6,
                  const std::function<bool()>& interrupt = {});

// The relative swing below which a bit velocity is steady whatever the tolerance.
inline constexpr double kSwingFloor = 2e-6;

// 2e-6, or 2000·rtol if larger. A steady state near a Hopf point is weakly
// damped: each step's local error (~rtol) keeps it ringing at a floor that
// depends on the method (measured on the paper's dof-2 string at W_ob 120 N:
// relative swing 4e-6 for DOP853 at rtol 1e-8, 6e-8 at rtol 1e-10).
inline double steady_swing_for_tolerance(double rtol) {
  return rtol * 2000.0 > kSwingFloor ? rtol * 2000.0 : kSwingFloor;
}

}  // namespace pydrill::detail
