// Judging the regime of a finished run (DESIGN.md §2, "Regimes").
#pragma once

#include <vector>

#include "pydrill/model.hpp"
#include "pydrill/simulator.hpp"

namespace pydrill::detail {

// Samples of the run inside the judging window, in time order.
struct Trace {
  std::vector<double> t, bit, top;
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

Summary summarize(const Chain& chain, const Trace& trace, const std::vector<ModeChange>& modes,
                  const WindowAngles& angles, bool karnopp);

}  // namespace pydrill::detail
