// The bit velocity's swing over a run's judged window, from its samples: its cycles, how it
// grows or dies out, and the mean it swings about (DESIGN.md §2, "Regimes").
#pragma once

#include <vector>

#include "summary.hpp"

namespace pydrill::detail {

// Mean spacing of upward crossings of `level`; < 0 when fewer than two crossings exist.
double crossing_period(const Trace& tr, double level);

// The longest of the swing's cycles about `level` between t0 and t1 (spacing of upward
// crossings), when it makes at least four whole cycles there; the string's `slowest`
// period otherwise.
double longest_cycle(const Trace& tr, double level, double t0, double t1, double slowest);

// The trend of the bit velocity's swing over the window: the least-squares slope of
// log(swing) over its four quarters, times the window's length (so 0 is sustained, ln 0.5 a
// swing halved across the window). `floor` stands in for a quarter without any swing;
// `last` is the last quarter's swing.
double swing_trend(const Trace& tr, double t0, double t1, double floor, double& last);

// The bit's mean velocity over [a, b], from the samples (trapezoids).
double sampled_mean(const Trace& tr, double a, double b);

}  // namespace pydrill::detail
