// The bit's stick phases in a finished run, and whether its stick-slip cycle has ended
// inside the judged window (DESIGN.md §2, "Regimes").
#pragma once

#include <utility>
#include <vector>

#include "summary.hpp"

namespace pydrill::detail {

// The phases in which the rock holds the bit, [start, end), in time order: consecutive held
// modes (stick, the Karnopp band) make one phase; one under way at `t_end` ends there.
std::vector<std::pair<double, double>> held_phases(const std::vector<ModeChange>& modes,
                                                   double t_end);

// A stick-slip cycle repeats itself: the phase under way when the window ends (t1) can last no
// longer than the same phase of an earlier cycle (1.04 times the longest at most, over 309
// random strings whose stick-slip a run ten times longer confirmed). A last phase of over
// kCycleEnded times the longest of its kind that ended in the window says the cycle has
// ended before the window did: the bit stuck, or broke free, for good, as far as the run saw.
inline constexpr double kCycleEnded = 2.0;

struct CycleEnd {
  enum class Kind { None, Stuck, Free } kind = Kind::None;
  double since = 0.0;    // when the last phase began: the last stick onset, or break-away
  double longest = 0.0;  // the longest phase of the same kind before it, ended in the window
};

// Whether the run's stick-slip cycle ended within [t0, t1]: held from the last onset to t1,
// over kCycleEnded times its longest stick phase ending after t0 (Stuck); or slipping since
// the last break-away, over kCycleEnded times its longest slip between two stick phases
// ending after t0 (Free). None when the window holds no earlier phase of that kind.
CycleEnd cycle_end(const std::vector<ModeChange>& modes, double t0, double t1);

}  // namespace pydrill::detail
