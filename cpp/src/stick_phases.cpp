#include "stick_phases.hpp"

#include <algorithm>

namespace pydrill::detail {
namespace {

bool held(Mode m) { return m == Mode::Stick || m == Mode::Band; }

}  // namespace

std::vector<std::pair<double, double>> held_phases(const std::vector<ModeChange>& modes,
                                                   double t_end) {
  std::vector<std::pair<double, double>> phases;
  bool in = false;
  for (const ModeChange& m : modes) {
    if (held(m.mode) && !in) phases.emplace_back(m.t, t_end);
    if (!held(m.mode) && in) phases.back().second = m.t;
    in = held(m.mode);
  }
  return phases;
}

CycleEnd cycle_end(const std::vector<ModeChange>& modes, double t0, double t1) {
  CycleEnd end;
  if (modes.empty()) return end;
  const auto phases = held_phases(modes, t1);
  if (phases.empty()) return end;
  const bool held_at_end = held(modes.back().mode);
  if (held_at_end) {
    // Stick phases before the last one that ended inside the window, whole (one under way
    // when the window opened counts with its start before it: a slow cycle's long stick).
    for (std::size_t k = 0; k + 1 < phases.size(); ++k) {
      if (phases[k].second > t0) {
        end.longest = std::max(end.longest, phases[k].second - phases[k].first);
      }
    }
    end.since = phases.back().first;
    if (end.longest > 0.0 && t1 - end.since > kCycleEnded * end.longest) {
      end.kind = CycleEnd::Kind::Stuck;
    }
  } else {
    // Slip phases between two stick phases, the second beginning inside the window.
    for (std::size_t k = 0; k + 1 < phases.size(); ++k) {
      if (phases[k + 1].first > t0) {
        end.longest = std::max(end.longest, phases[k + 1].first - phases[k].second);
      }
    }
    end.since = phases.back().second;
    if (end.longest > 0.0 && t1 - end.since > kCycleEnded * end.longest) {
      end.kind = CycleEnd::Kind::Free;
    }
  }
  return end;
}

}  // namespace pydrill::detail
