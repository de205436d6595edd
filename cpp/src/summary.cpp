#include "summary.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

#include "hermite.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"
#include "stick_phases.hpp"
#include "swing.hpp"

namespace pydrill::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool is_held(Mode m) { return m == Mode::Stick || m == Mode::Band; }

// The extremes of v(t) from its samples and their slopes dv: on each interval between two
// samples, the cubic Hermite interpolant of both ends (fourth-order accurate) has its extreme
// where its slope vanishes. The samples sit at the integrator's steps, which on a smooth peak
// can straddle it: the largest bare sample of a 17.5 s stick-slip cycle's bit velocity came
// out 0.2 % low (0.5 % with only the steps). Velocities are smooth at their extremes: the
// friction's jumps happen at ω_b = 0, where the bit sticks or reverses.
// A sample taken at a switch carries the slope of the mode after it: the interval that ends
// there is left as sampled (an extreme is not where the bit sticks, slips or reverses).
std::pair<double, double> extremes(const std::vector<double>& t, const std::vector<double>& v,
                                   const std::vector<double>& dv,
                                   const std::vector<ModeChange>& modes) {
  if (v.empty()) return {0.0, 0.0};
  double lo = *std::min_element(v.begin(), v.end());
  double hi = *std::max_element(v.begin(), v.end());
  if (dv.size() != v.size()) return {lo, hi};
  std::size_t next = 0;  // the first switch at or after t[i + 1]
  for (std::size_t i = 0; i + 1 < v.size(); ++i) {
    while (next < modes.size() && modes[next].t < t[i + 1]) ++next;
    if (next < modes.size() && modes[next].t == t[i + 1]) continue;
    const double h = t[i + 1] - t[i];
    const double m0 = dv[i] * h, m1 = dv[i + 1] * h;  // slopes per unit of x = (t − t_i)/h
    double x, p;
    if (!(h > 0.0) || !hermite_turn(v[i], v[i + 1], m0, m1, x, p)) continue;
    if (m0 > 0.0) hi = std::max(hi, p);
    else lo = std::min(lo, p);
  }
  return {lo, hi};
}

// The mean of v(t) over the samples' span by the trapezoid rule: a weighted mean of the
// samples, so within their least and greatest (the first sample's value on a span of zero).
double trapezoid_mean(const std::vector<double>& t, const std::vector<double>& v) {
  double area = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i) area += 0.5 * (v[i - 1] + v[i]) * (t[i] - t[i - 1]);
  const double span = t.back() - t.front();
  return span > 0.0 ? std::clamp(area / span, *std::min_element(v.begin(), v.end()),
                                 *std::max_element(v.begin(), v.end()))
                    : v.front();
}

// The string's crossings (critical_deltas), kept for the last few strings this thread met:
// they depend on the string alone, not on W_ob or u, and cost ~0.3 ms on a 4-DOF string, as
// much as its 300 s run; a sweep over (W_ob, u) meets one string thousands of times, and
// every steady run asks (below). Keyed by every parameter, compared exactly.
std::vector<Crossing> string_crossings(const Params& p, const std::function<bool()>& interrupt) {
  struct Kept {
    Params params;
    std::vector<Crossing> crossings;
  };
  constexpr std::size_t kKept = 4;
  thread_local std::vector<Kept> kept;
  const auto same = [&p](const Params& q) {
    return q.inertias == p.inertias && q.stiffnesses == p.stiffnesses &&
           q.dampings == p.dampings && q.top_damping == p.top_damping &&
           q.bit_damping == p.bit_damping && q.bit_radius == p.bit_radius &&
           q.mu_coulomb == p.mu_coulomb && q.mu_static == p.mu_static &&
           q.stribeck_decay == p.stribeck_decay && q.stribeck_velocity == p.stribeck_velocity &&
           q.karnopp_band == p.karnopp_band;
  };
  for (const Kept& k : kept) {
    if (same(k.params)) return k.crossings;
  }
  std::vector<Crossing> found = critical_deltas(p, interrupt);  // may throw: nothing kept
  if (kept.size() >= kKept) kept.erase(kept.begin());
  kept.push_back({p, std::move(found)});
  return kept.back().crossings;
}

// Whether the steady state at `omega` has an eigenvalue in the right half-plane (from the
// string's crossings, O(dof²) the first time a thread meets the string).
bool unstable_at(const Chain& chain, double omega, const std::function<bool()>& interrupt) {
  if (!(std::fabs(omega) > 0.0)) return false;
  const auto& p = chain.params();
  const double delta = stribeck_slope(p, std::fabs(chain.wob()), std::fabs(omega));
  return unstable_count(string_crossings(p, interrupt), delta) > 0;
}

// Whether the mean bit velocity is still on its way, from `before` (the window's first half)
// to `after` (its second): moving by more than 1 % of itself, or towards a steady state more
// than 1 % away (a converged run's moves by 1e-4 or less; a bit damped by c_b = 1e-3 alone
// was judged steady at 238 rad/s on its way to 750). A swing that does not span whole periods
// moves a half-window's mean too, by at most its amplitude (`last` / 2) times period /
// (π · T / 2): the drift must exceed that as well. The period: the longest of the swing's
// cycles in the window, if it made four or more; else the string's `slowest`. (The slowest
// alone, 30 s against a swing of 8.5 s, hid a mean on its way from 231 to 291 rad/s behind a
// swing of 90 % of it.) `target`: the steady state ahead of it, the nearest in the direction
// it moves (NaN: none).
bool mean_moves(const Trace& tr, const Summary& s, double before, double after, double last,
                double slowest, double& target) {
  const double T = s.window_end - s.window_start;
  const double drift = std::fabs(after - before), size = std::fabs(s.bit_mean);
  double gap = std::numeric_limits<double>::infinity();  // to the nearest steady state
  for (double o : s.omega_equilibrium) gap = std::min(gap, std::fabs(after - o));
  const double period = longest_cycle(tr, s.bit_mean, s.window_start, s.window_end, slowest);
  const double faked = 2.0 * last * period / (kPi * T);
  target = std::numeric_limits<double>::quiet_NaN();
  if (!((drift > 0.01 * size || (drift > 1e-3 * size && gap > 0.01 * std::fabs(after))) &&
        drift > faked)) {
    return false;
  }
  const double way = after > before ? 1.0 : -1.0;
  for (double o : s.omega_equilibrium) {
    if (way * (o - after) > 0 && !(way * (o - target) >= 0)) target = o;
  }
  return true;
}

// The steady state nearest the run's mean bit velocity (NaN: none).
double nearest_state(const std::vector<double>& omegas, double mean) {
  double omega = std::numeric_limits<double>::quiet_NaN();
  for (double o : omegas) {
    if (!(std::fabs(o - mean) >= std::fabs(omega - mean))) omega = o;
  }
  return omega;
}

// Whether the steady state nearest the run's mean bit velocity has an eigenvalue in the
// right half-plane (from the string's crossings).
bool circles_unstable_state(const Chain& chain, const std::vector<double>& omegas, double mean,
                            const std::function<bool()>& interrupt) {
  const double omega = nearest_state(omegas, mean);
  return std::isfinite(omega) && unstable_at(chain, omega, interrupt);
}

// The Coulomb torque T_c = μ_cb R_b W_ob: the slip friction's limit as the bit speeds up.
double coulomb_torque(const Chain& chain) {
  const auto& p = chain.params();
  return p.mu_coulomb * p.bit_radius * std::fabs(chain.wob());
}

// Whether a bit that slipped through the whole window is running away: nothing at the top or
// the bit damps the string's rotation (c_r + c_b = 0), so the net torque on it as a whole is
// |u| − f_b(|ω_b|), and the slip friction f_b falls towards the Coulomb torque T_c as the bit
// speeds up. With |u| > T_c, a bit turning faster than its one steady state (there is none
// when |u| >= T_s, and it is unstable: every eigenvalue crosses at δ = 0) meets less
// friction the faster it turns, and speeds up without bound. Judged "steady" it once was,
// from a mean of 287 rad/s and a swing shrinking against it, beside a steady state at 0.77.
// `rise`: how much the mean bit velocity grew from the window's first half to its second.
bool runs_away(const Chain& chain, const Summary& s, double rise) {
  const auto& p = chain.params();
  if (p.top_damping + p.bit_damping != 0.0) return false;
  const double u = chain.torque(), dir = u < 0 ? -1.0 : 1.0;
  if (!(std::fabs(u) > coulomb_torque(chain))) return false;
  for (double o : s.omega_equilibrium) {
    if (!(dir * s.bit_mean > dir * o)) return false;
  }
  // The mean rises: by more than 1 % of itself across the window, which no bounded motion
  // about a steady state does once its swing has settled (and none exists above this one).
  return dir * rise > 0.01 * std::fabs(s.bit_mean);
}

}  // namespace

Summary summarize(const Chain& chain, const Trace& tr, const std::vector<ModeChange>& modes,
                  const WindowAngles& w, bool karnopp, double steady_swing,
                  const std::function<bool()>& interrupt) {
  Summary s;
  s.window_start = w.t0;
  s.window_end = w.t1;
  s.static_torque = chain.static_torque();
  // u < 0 turns the string backwards: the mirror image (φ → −φ) of the run at |u|, whose
  // steady states are the same velocities reversed.
  const double u = chain.torque();
  s.omega_equilibrium = equilibrium_velocities(chain.params(), chain.wob(), std::fabs(u));
  if (u < 0) {
    for (double& o : s.omega_equilibrium) o = -o;
    std::reverse(s.omega_equilibrium.begin(), s.omega_equilibrium.end());
  }
  const double T = w.t1 - w.t0;
  // The string's slowest period: what a judged window must span (below), and the longest a
  // swing that fakes a drift of its mean can have.
  const double slowest = 2.0 * kPi / estimate_stiffness(chain.params()).fundamental;

  if (!tr.t.empty()) {
    std::tie(s.bit_min, s.bit_max) = extremes(tr.t, tr.bit, tr.dbit, modes);
    std::tie(s.top_min, s.top_max) = extremes(tr.t, tr.top, tr.dtop, modes);
  }
  // Means from the angle advance over the window: exact, whatever the sampling, up to the
  // rounding of the angles, about ε·|φ| / T. On a window of a few ns or less (window_fraction
  // 1e-12 and below at 300 s) that is more than the velocity moves in it, and a mean of 19.2
  // rad/s came out beside a min and max of 18.30408: where the advance falls outside the
  // extremes, the samples' trapezoid mean stands in (within them, as every sample is).
  s.bit_mean = T > 0 ? (w.bit1 - w.bit0) / T : 0.0;
  s.top_mean = T > 0 ? (w.top1 - w.top0) / T : 0.0;
  if (!tr.t.empty()) {
    if (!(s.bit_mean >= s.bit_min && s.bit_mean <= s.bit_max)) s.bit_mean = trapezoid_mean(tr.t, tr.bit);
    if (!(s.top_mean >= s.top_min && s.top_mean <= s.top_max)) s.top_mean = trapezoid_mean(tr.t, tr.top);
  }
  s.severity = s.bit_mean != 0.0 ? (s.bit_max - s.bit_min) / (2.0 * std::fabs(s.bit_mean))
                                 : std::numeric_limits<double>::infinity();
  if (s.bit_max == s.bit_min) s.severity = 0.0;
  // The bit's fastest turn in the top drive's direction (bit_min when it turns backwards).
  const double fastest = s.top_mean > 0 ? s.bit_max : s.bit_min;
  s.bit_top_ratio = s.top_mean != 0.0 && fastest != 0.0 ? fastest / s.top_mean : 0.0;

  // Time held by the rock inside the window, and stick onsets in it.
  double held = 0.0;
  std::vector<double> onsets;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const double a = modes[i].t;
    const double b = (i + 1 < modes.size()) ? modes[i + 1].t : w.t1;
    if (is_held(modes[i].mode)) {
      held += std::max(0.0, std::min(b, w.t1) - std::max(a, w.t0));
      const bool onset = i > 0 && !is_held(modes[i - 1].mode);
      if (onset && a >= w.t0 && a <= w.t1) onsets.push_back(a);
    }
  }
  s.stuck_fraction = T > 0 ? std::clamp(held / T, 0.0, 1.0) : 0.0;
  s.stick_events = static_cast<long>(onsets.size());
  if (onsets.size() >= 2) {
    s.period = (onsets.back() - onsets.front()) / static_cast<double>(onsets.size() - 1);
  }

  const bool held_throughout = s.stuck_fraction >= 1.0 - 1e-12;
  bool growing = false;  // an oscillation still growing, or judged by its steady state's
  bool unresolved = false;  // stability: their notes may give way below
  bool approaching = false;  // steady, its mean still moving: so may its note
  if (held_throughout) {
    // In stick the string relaxes towards T_e = u. If |u| <= T_s the rock
    // holds it for good. Otherwise it must break free later: if it already
    // did once, the window caught one long stick phase of a stick-slip cycle;
    // if it never did, the run ended inside the first wind-up.
    const bool must_slip = std::fabs(chain.torque()) > chain.static_torque();
    const bool ever_slipped = modes.size() > 1 || !is_held(modes.front().mode);
    s.regime = must_slip && ever_slipped ? Regime::StickSlip : Regime::Stuck;
    if (must_slip && !ever_slipped) {
      s.caveat = "first-wind-up";
      s.note = "the bit has not broken free yet although |u| > T_s: the run ended during the "
               "first wind-up of the string; simulate longer to see the regime";
    } else if (must_slip) {
      s.caveat = "one-stick-phase";
      s.note = "the window holds a single stick phase of a slow stick-slip cycle; simulate longer "
               "for its period";
    }
    s.severity = 0.0;
    if (!karnopp) s.bit_mean = 0.0;  // exact stick: the bit does not move at all
  } else if (held > 0.0) {
    s.regime = Regime::StickSlip;
    // The mode the window opened in: the last change at or before its start.
    std::size_t first = 0;
    while (first + 1 < modes.size() && modes[first + 1].t <= w.t0) ++first;
    const bool held_at_start = is_held(modes[first].mode);
    const bool held_at_end = is_held(modes.back().mode);
    if (onsets.size() == 1 && !held_at_start && held_at_end &&
        std::fabs(chain.torque()) <= chain.static_torque()) {
      // Slipping, then one stick to the window's end with |u| <= T_s: the bit stuck once and
      // has not left, which is what stuck means, not a repeated stick and slip. A run a few
      // seconds longer had judged it stuck from a window held throughout.
      s.regime = Regime::Stuck;
      s.caveat = "late-stick";
      std::ostringstream o;
      o.precision(3);
      o << "the bit slipped for part of the window and has been stuck since t = " << onsets[0]
        << " s: |u| <= T_s lets the rock hold it, but the string's swing may still break it "
        << "free; simulate longer to be sure";
      s.note = o.str();
    } else if (onsets.empty()) {
      // Held when the window opened, slipping ever since: one break-away, no stick after
      // it. The next stick may be coming, or the bit may settle into steady drilling.
      s.caveat = "one-break-away";
      s.note = "the bit broke free once in the window and has not stuck again: simulate longer "
               "to tell stick-slip from steady drilling";
    } else if (const CycleEnd end = cycle_end(modes, w.t0, w.t1);
               end.kind == CycleEnd::Kind::Free ||
               (end.kind == CycleEnd::Kind::Stuck &&
                std::fabs(chain.torque()) <= chain.static_torque())) {
      // Sticks and slips that stopped inside the window: its last phase has outlasted every
      // one of its kind before it, over twice (a cycle's repeat within 4 %). Judged by the
      // last phase, as above: stuck for good (|u| <= T_s can hold the bit), or free since a
      // last break-away. 15 of 32 random strings whose 300 s stick-slip a 3000 s run found
      // steady or stuck were so, and none of 309 it confirmed.
      const bool stuck = end.kind == CycleEnd::Kind::Stuck;
      std::ostringstream o;
      o.precision(3);
      o << "the bit has " << (stuck ? "been stuck" : "turned without sticking") << " since t = "
        << end.since << " s, for " << w.t1 - end.since << " s: over " << kCycleEnded
        << " times its longest " << (stuck ? "stick" : "slip") << " phase before it in the "
        << "window (" << end.longest << " s)";
      if (stuck) {
        s.regime = Regime::Stuck;
        s.caveat = "late-stick";
        o << ": |u| <= T_s lets the rock hold it, but the string's swing may still break it "
          << "free; simulate longer to be sure";
      } else {
        s.caveat = "one-break-away";
        o << ": the stick-slip may have died out; simulate longer to tell stick-slip from "
          << "steady drilling";
      }
      s.note = o.str();
    }
  } else {
    // No sticking: steady if the bit velocity settles, oscillation if its swing is
    // sustained. A swing that shrinks across the window is a transient dying out, however
    // slowly: near a Hopf point a stable steady state is approached at the rate of its
    // spectral abscissa, a few thousandths per second here, so a judged window of 150 s sees
    // the swing fall by only a quarter or so — that is steady drilling, not a limit cycle.
    const double scale = std::max(std::fabs(s.bit_mean), 1e-12);
    const double floor = steady_swing * scale;
    double last = 0.0;
    const double trend = swing_trend(tr, w.t0, w.t1, 0.5 * floor, last);
    // ±5 %: what sampling the swing at the integrator's steps cannot fake.
    const double change = std::log(1.05);
    bool steady = trend < -change || last <= kSwingFloor * scale;
    if (!steady && last <= floor) {
      // A sustained swing the integrator cannot tell from its own ringing: the floor grows
      // with rtol (20 % of the mean at 1e-4), and a 7 % limit cycle about a Hopf-unstable
      // steady state passed for steady drilling there. Near the steady state the linear
      // analysis decides: it is kept only if no eigenvalue lies in the right half-plane.
      steady = !circles_unstable_state(chain, s.omega_equilibrium, s.bit_mean, interrupt);
      unresolved = !steady;
      if (unresolved) {
        std::ostringstream o;
        o.precision(2);
        o << "the bit velocity swings by " << 100.0 * last / scale << " % of its mean, within "
          << "what the tolerance resolves (" << 100.0 * floor / scale << " %), about a steady "
          << "state that is linearly unstable: judged an oscillation; a smaller rtol shows it "
          << "clearly";
        s.note = o.str();
      }
    }
    const double middle = 0.5 * (w.t0 + w.t1);
    const double before = sampled_mean(tr, w.t0, middle), after = sampled_mean(tr, middle, w.t1);
    double target = 0.0;  // the steady state ahead of a mean still on its way
    const bool moving = mean_moves(tr, s, before, after, last, slowest, target);
    // A swing that does not grow against a mean still on its way to a steady state that is
    // linearly stable: a bit spinning up, whose swing is the transient of where it is now,
    // not a limit cycle (a limit cycle's mean stays put), nor a steady state left (about one,
    // the swing grows from nothing). Near its steady state the swing dies out: steady by
    // where it is going. 11 of 11 random lightly damped strings so judged an oscillation at
    // 300 s (4 of them "growing", by their swing alone) were steady at 3000 s, their means
    // 25-35 % up across the window on their way to steady states of 1900-21000 rad/s.
    // The swing against the mean: its trend less the mean's, 2 ln(after / before) across the
    // window (the halves' means sit half a window apart).
    const double against =
        std::fabs(before) > 0.0 ? trend - 2.0 * std::log(std::fabs(after) / std::fabs(before))
                                : trend;
    const bool settling = !steady && !unresolved && against <= change && moving &&
                          std::isfinite(target) && !unstable_at(chain, target, interrupt);
    // A swing that dies out about a steady state that is linearly unstable: the decay seen is
    // that of the stable modes, and the unstable one, started from next to nothing and slower
    // than the window, has yet to show (a 4-DOF string from equilibrium, spectral abscissa
    // 5.8e-4 1/s: steady at 300 s, its swing growing 2.4-fold a window at 3000 s). The one
    // such run among 3831 random strings' steady ones at 300 s; its verdict is the linear
    // analysis's. (A swing below kSwingFloor is a run started on the state, and kept there:
    // steady, as the state is.)
    const double state = steady && !moving && last > kSwingFloor * scale
                             ? nearest_state(s.omega_equilibrium, s.bit_mean)
                             : std::numeric_limits<double>::quiet_NaN();
    const bool leaving = std::isfinite(state) && unstable_at(chain, state, interrupt);
    if (runs_away(chain, s, after - before)) {
      // Neither steady (it never settles) nor stick-slip: judged an oscillation, the one
      // label of a motion that never sticks and never settles, with the reason beside it.
      s.regime = Regime::Oscillation;
      s.period = -1.0;  // no cycle: the string swings about a mean that keeps rising
      s.caveat = "run-away";
      std::ostringstream o;
      o.precision(3);
      o << "no steady state holds the bit: nothing damps the string's rotation at the top or "
        << "the bit (c_r + c_b = 0) and |u| = " << std::fabs(chain.torque())
        << " N m exceeds the Coulomb torque T_c = "
        << coulomb_torque(chain) << " N m, so the bit speeds up without bound (mean "
        << std::fabs(before) << " rad/s in the window's first half, " << std::fabs(after)
        << " in its second): judged an oscillation "
        << "that never settles; give the top drive or the bit a damping (c_r, c_b)";
      s.note = o.str();
      unresolved = false;
    } else if ((steady || settling) && !leaving) {
      s.regime = Regime::Steady;
      if (moving) {  // settling, but not there yet: steady is where it is going
        approaching = true;
        s.caveat = "approaching";
        std::ostringstream o;
        o.precision(3);
        o << "the bit's mean velocity is still changing (" << before
          << " rad/s in the window's first half, " << after << " in its second)";
        if (settling) {
          o << " under a swing (" << 100.0 * last / std::fabs(after) << " % of it) that does "
            << "not grow against it";
        }
        if (std::isfinite(target)) {
          o << ", on its way to the steady state at " << target << " rad/s";
          if (settling) o << ", which is linearly stable";
        }
        o << ": judged steady by where it is going; simulate longer to see it settle";
        s.note = o.str();
      }
    } else {
      s.regime = Regime::Oscillation;
      s.period = crossing_period(tr, s.bit_mean);
      growing = trend > change || leaving;
      if (leaving) {
        const StabilityPoint at =
            stability_at_velocity(chain.params(), std::fabs(chain.wob()), std::fabs(state),
                                  interrupt);
        std::ostringstream o;
        o.precision(3);
        o << "the bit turns at its steady state (" << state << " rad/s; its swing, "
          << 100.0 * last / scale << " % of it, dies out across the window), but that state is "
          << "linearly unstable";
        if (at.spectral_abscissa > 0.0) {  // (at a crossing's edge it rounds to 0)
          o << ": its spectral abscissa, " << at.spectral_abscissa << " 1/s, grows a "
            << "disturbance e-fold every " << 1.0 / at.spectral_abscissa << " s";
        }
        o << ", slower than the window shows; judged an oscillation still growing; simulate "
          << "longer to see where it settles";
        s.note = o.str();
        s.caveat = "growing";
      } else if (growing) {
        std::ostringstream o;
        o.precision(2);
        o << "the oscillation is still growing (its swing by a factor " << std::exp(trend)
          << " across the window): the steady state is left, and the bit may end in "
          << "stick-slip; simulate longer to see where it settles";
        s.note = o.str();
        s.caveat = "growing";
      }
    }
  }
  // A regime is judged from a window that holds at least one swing of the string's slowest
  // mode: a shorter one sees part of a stick-slip cycle as an oscillation, or a slip phase
  // as steady (a 3 s window of a 17.5 s cycle did both). Not for a bit held for good.
  // Over a window that short a swing's trend says nothing either: this note replaces it.
  // Its advice names SimulationOptions::window_fraction, as simulate() takes it in C++ and in
  // Python; the command line's pydrill.cli_note says --window instead.
  const bool settled_stuck = s.regime == Regime::Stuck && s.note.empty();
  if (!settled_stuck && T < slowest && (s.note.empty() || growing || unresolved || approaching)) {
    std::ostringstream o;
    o.precision(3);
    o << "the judged window (" << T << " s) is shorter than the string's slowest period (about "
      << slowest << " s): too short to judge the regime; simulate longer, or judge a larger "
      << "fraction of the run (window_fraction)";
    s.note = o.str();
    s.caveat = "short-window";
  }
  return s;
}

}  // namespace pydrill::detail
