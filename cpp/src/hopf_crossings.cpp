// Where the steady states' stability changes as the Stribeck slope δ grows: the crossings
// (critical_deltas: the fold and the Hopf points, found on the bit impedance's phase) and the
// count of unstable eigenvalues they give. (The first Lyapunov coefficient at a Hopf point:
// lyapunov.cpp.)
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "interrupt_poll.hpp"
#include "pydrill/simulator.hpp"  // estimate_stiffness
#include "pydrill/stability.hpp"
#include "stability_internal.hpp"

namespace pydrill {

using detail::bit_fraction;
using detail::check_delta;
using detail::Fraction;
using detail::impedance;
using detail::impedance_slope;

namespace {

// Natural frequencies of the undamped chain, with the bit clamped (the poles
// of Z_b, nearly) or free (its zeros, nearly), and the top free or clamped (a top damping far
// above the string's, as on a laboratory string of 0.1 kg·m² held by 320 N·m·s/rad, holds it
// nearly still, and the zeros and poles move to those of the chain held there): symmetric
// tridiagonal, O(dof²). Empty where both ends are clamped on a string of 2.
std::vector<double> undamped_frequencies(const Params& p, bool clamped, detail::InterruptPoll& poll,
                                         bool top_clamped = false) {
  const int first = top_clamped ? 1 : 0;
  const int n = (clamped ? p.dof() - 1 : p.dof()) - first;
  if (n <= 0) return {};
  Eigen::VectorXd diag(n), sub(std::max(n - 1, 1));
  for (int r = 0; r < n; ++r) {
    const int i = r + first;  // a row of the free chain's matrix, whose principal part this is
    double k = 0.0;
    if (i > 0) k += p.stiffnesses[i - 1];        // the first spring holds a clamped top
    if (i < p.dof() - 1) k += p.stiffnesses[i];  // the last spring holds a clamped bit
    diag(r) = k / p.inertias[i];
    if (r + 1 < n) sub(r) = -p.stiffnesses[i] / std::sqrt(p.inertias[i] * p.inertias[i + 1]);
  }
  const Eigen::VectorXd ev = detail::tridiagonal_eigenvalues(diag, sub.head(std::max(n - 1, 0)), poll);
  std::vector<double> w;
  for (int i = 0; i < n; ++i) w.push_back(std::sqrt(std::max(ev(i), 0.0)));
  return w;
}

// arg Z_b(iω) in (−π, π].
double phase(const Params& p, double omega) {
  const Fraction f = bit_fraction(p, complex(0.0, omega));
  return std::arg(f.num * std::conj(f.den));
}

// Brent's method on a bracket [a, b] with f(a)·f(b) < 0.
template <typename F>
double brent(F f, double a, double b, double fa, double fb) {
  double c = a, fc = fa, d = b - a, e = d;
  for (int it = 0; it < 200; ++it) {
    if ((fb > 0) == (fc > 0)) {
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (std::fabs(fc) < std::fabs(fb)) {
      a = b; b = c; c = a;
      fa = fb; fb = fc; fc = fa;
    }
    const double tol = 2 * std::numeric_limits<double>::epsilon() * std::fabs(b);
    const double m = 0.5 * (c - b);
    if (std::fabs(m) <= tol || fb == 0.0) return b;
    if (std::fabs(e) >= tol && std::fabs(fa) > std::fabs(fb)) {
      double s = fb / fa, pp, q;
      if (a == c) {
        pp = 2 * m * s;
        q = 1 - s;
      } else {
        const double r = fb / fc, t = fa / fc;
        pp = s * (2 * m * t * (t - r) - (b - a) * (r - 1));
        q = (t - 1) * (r - 1) * (s - 1);
      }
      if (pp > 0) q = -q; else pp = -pp;
      if (2 * pp < std::min(3 * m * q - std::fabs(tol * q), std::fabs(e * q))) {
        e = d;
        d = pp / q;
      } else {
        d = m;
        e = d;
      }
    } else {
      d = m;
      e = d;
    }
    a = b;
    fa = fb;
    b += std::fabs(d) > tol ? d : (m > 0 ? tol : -tol);
    fb = f(b);
  }
  return b;
}

// Z_b'(λ), differentiated along the continued fraction (forward mode: each numerator and
// denominator with its derivative). A central difference with a step fixed in 1/s (1e-6 ×
// max(ω, 1e-3) at a Hopf point, 1e-7 × (c_r + c_b) at the fold) gave the wrong sign on a
// slow string, whose eigenvalues are no bigger than that step: the paper's string with
// inertias ×1e8 and dampings ×1e4 (the same string on a clock 1e4 times slower) had its
// fold's direction reversed, and from ×1e16 its Hopf points' too. Where the fraction
// overflows (an inertia near 1.8e308) the difference stands in, at a step of 1e-6 |λ|.
// (In detail, not here alone: first_lyapunov_coefficient checks its Hopf point with it.)
}  // namespace

complex detail::impedance_slope(const Params& p, complex lambda) {
  const int n = p.dof();
  complex num = p.inertias[0] * lambda + p.top_damping, dnum = p.inertias[0], den = 1.0, dden = 0.0;
  for (int i = 0; i < n - 1; ++i) {
    const complex spring = p.stiffnesses[i] + p.dampings[i] * lambda;
    const double dspring = p.dampings[i];
    const complex n_above = spring * num, dn_above = dspring * num + spring * dnum;
    const complex d_above = spring * den + lambda * num;
    const complex dd_above = dspring * den + spring * dden + num + lambda * dnum;
    const complex own = p.inertias[i + 1] * lambda + (i + 1 == n - 1 ? p.bit_damping : 0.0);
    num = own * d_above + n_above;
    dnum = p.inertias[i + 1] * d_above + own * dd_above + dn_above;
    den = d_above;
    dden = dd_above;
    const double big = std::max({std::abs(num), std::abs(dnum), std::abs(den), std::abs(dden)});
    if (big > 1e100 || (big < 1e-100 && big > 0)) {  // exact powers of two, as bit_fraction's
      const double f = std::ldexp(1.0, -std::ilogb(big));
      num *= f, dnum *= f, den *= f, dden *= f;
    }
  }
  const complex slope = (dnum * den - num * dden) / (den * den);
  if (std::isfinite(slope.real()) && std::isfinite(slope.imag())) return slope;
  const double h = 1e-6 * std::max(std::abs(lambda), estimate_stiffness(p).fundamental);
  return (impedance(p, lambda + h) - impedance(p, lambda - h)) / (2 * h);
}

namespace {

// dλ/dδ = 1/Z_b'(λ) on the imaginary axis; its real part says which way the
// eigenvalues cross as δ grows.
int crossing_direction(const Params& p, double omega) {
  const double re = std::real(1.0 / impedance_slope(p, complex(0.0, omega)));
  return re > 0 ? 1 : (re < 0 ? -1 : 0);
}

// Does the free chain's mode at ω strain none of the dampers? With the bit's amplitude 1, the
// spring below inertia i twists by ω² S_i / k_i, where S_i = Σ_{m>i} J_m x_m is the swing of
// everything below it; so a damper works on the mode unless S_i = 0 where it sits. (Its ends
// always move, so c_r = c_b = 0 is needed too; the caller checks that.) S_i is 0 up to
// rounding in such a mode (a symmetric string with one damper at its middle, say), and of the
// order of the swing below otherwise: relative 1e-9 tells the two apart.
bool strains_no_damper(const Params& p, double w) {
  const int n = p.dof();
  double x = 1.0, swing = p.inertias[n - 1], size = swing;
  for (int i = n - 2; i >= 0; --i) {
    if (p.dampings[i] != 0.0 && !(std::fabs(swing) <= 1e-9 * size)) return false;
    x -= w * w * swing / p.stiffnesses[i];  // the spring holds the swing below: k_i (x_i − x_{i+1}) = −ω² S_i
    swing += p.inertias[i] * x;
    size += p.inertias[i] * std::fabs(x);
  }
  return std::isfinite(size);
}

// Hopf points at δ = 0: the modes of a string with c_r = c_b = 0 that strain none of its
// dampers, every one of them on a string with no damping at all. Such a mode is an eigenvalue
// ±iω at δ = 0 with Z_b(iω) = 0 exactly, where Re Z_b >= 0 has its minimum 0; the phase the
// search below follows never passes through 0 there (on an undamped string Z_b(iω) = iX(ω) and
// the phase only jumps between ±π/2), so it found none of them, and an undamped string was
// called stable at every δ while each of its modes grows for any δ > 0. They all leave to the
// right: Z_b'(iω) = X'(ω) > 0 (Foster's reactance theorem). In a chain no mode has a node at
// the bit (the amplitudes follow from the bit's by the recurrence), so these are among the
// N − 1 nonzero modes of the free chain, which interlace strictly with the clamped chain's
// (Cauchy: its matrix is the free one's without the bit's row), the poles of Im Z_b.
std::vector<Crossing> hopf_at_zero(const Params& p, detail::InterruptPoll& poll) {
  std::vector<Crossing> out;
  if (p.top_damping != 0.0 || p.bit_damping != 0.0) return out;
  const std::vector<double> free = undamped_frequencies(p, false, poll);    // N, from 0
  const std::vector<double> clamped = undamped_frequencies(p, true, poll);  // N − 1
  auto x = [&](double w) { return std::imag(impedance(p, complex(0.0, w))); };
  for (std::size_t j = 1; j < free.size(); ++j) {
    poll.tick(p.dof());
    double w = free[j];
    if (!(w > 0) || !strains_no_damper(p, w)) continue;
    // The zero lies between the poles clamped[j − 1] and clamped[j] (or beyond the last one),
    // where Im Z_b rises through 0: bracket it halfway to each, and polish the eigenvalue.
    const double lo = 0.5 * (clamped[j - 1] + w);
    const double hi = j < clamped.size() ? 0.5 * (w + clamped[j]) : 2.0 * w;
    const double xlo = x(lo), xhi = x(hi);
    if (xlo < 0 && xhi > 0) w = brent(x, lo, hi, xlo, xhi);
    out.push_back({CrossingType::Hopf, 0.0, w, crossing_direction(p, w), 2});
  }
  return out;
}

}  // namespace

std::vector<Crossing> critical_deltas(const Params& p, const std::function<bool()>& interrupt) {
  p.validate();
  const int N = p.dof();
  std::vector<Crossing> out;
  // Nearly all the time goes into O(dof) evaluations of the phase, thousands of them on a
  // long string; the poll hears of them once per grid point (below).
  detail::InterruptPoll poll(interrupt);

  // Fold: λ = 0 is an eigenvalue when δ = Z_b(0) = c_r + c_b. With neither damping it is at
  // δ = 0: the string turns freely as one body, and any slope δ > 0 sets it accelerating (the
  // fold was left out then, and the count at δ > 0 was one short).
  const double fold = p.top_damping + p.bit_damping;
  const double dz = std::real(impedance_slope(p, complex(0.0)));
  out.push_back({CrossingType::Fold, fold, 0.0, dz > 0 ? 1 : -1, 1});
  const std::vector<Crossing> at_zero = hopf_at_zero(p, poll);
  out.insert(out.end(), at_zero.begin(), at_zero.end());
  const bool undamped = std::all_of(p.dampings.begin(), p.dampings.end(), [](double c) { return c == 0.0; }) &&
                        p.top_damping == 0.0 && p.bit_damping == 0.0;
  if (undamped) return out;  // (the fold first, at 0 too: in increasing δ already)

  // Hopf: zeros of Im Z_b(iω) with Re Z_b > 0. No zero lies above the
  // highest natural frequency of the chain, where J_b ω dominates.
  double w2max = 0.0, rate = 0.0;
  for (int i = 0; i < N; ++i) {
    double ks = 0.0, cs = (i == 0 ? p.top_damping : 0.0) + (i == N - 1 ? p.bit_damping : 0.0);
    if (i > 0) { ks += p.stiffnesses[i - 1]; cs += p.dampings[i - 1]; }
    if (i < N - 1) { ks += p.stiffnesses[i]; cs += p.dampings[i]; }
    w2max = std::max(w2max, 2.0 * ks / p.inertias[i]);
    rate = std::max(rate, 2.0 * cs / p.inertias[i]);
  }
  // The margin was 1e-9 rad/s on its own, which swamped the bound of a slow string (the
  // paper's with inertias x1e100 and dampings x1e50, modes near 1e-50 rad/s, lost two of its
  // six crossings): relative below 1 rad/s, unchanged above.
  const double w_bound = 2.0 * std::sqrt(w2max) + rate;
  const double w_hi = w_bound + 1e-9 * std::min(w_bound, 1.0);
  // The fundamental as estimate_stiffness gives it (the string on a still bit), safe from
  // overflow, or the bit's own mode on the whole string held at the top if that is slower: a
  // bit far heavier than the rest (or a top held by its damping) swings slower than the
  // fundamental, and a 2-DOF string with a top of 4e-14 kg·m² lost its Hopf point at 1.5 rad/s,
  // below a grid that began at 24 rad/s. Never 0 (a log below).
  const double fundamental = estimate_stiffness(p).fundamental;
  double above = 0.0;
  for (int i = 0; i < N - 1; ++i) above += p.inertias[i];
  const double bit_mode = fundamental * std::sqrt(above / p.inertias.back());
  const double w_lo = std::max(1e-4 * std::min(fundamental, bit_mode), std::numeric_limits<double>::denorm_min());
  // Start from a uniform grid (the dense upper spectrum) merged with a
  // geometric one (the low modes of long strings), then split every interval
  // over which arg Z_b turns by more than π/4 until it does not: a zero of
  // Im Z_b is a turn through a multiple of π, so none can hide inside.
  const int m = std::max(1000, 6 * N);
  std::vector<double> grid;
  grid.reserve(2 * static_cast<std::size_t>(m));
  for (int i = 1; i <= m; ++i) grid.push_back(w_hi * i / m);
  const double span = w_hi / w_lo;  // inf for a string of extreme rates: then in logs
  for (int i = 0; i < m; ++i) {
    const double x = static_cast<double>(i) / m;
    grid.push_back(std::isfinite(span) ? w_lo * std::pow(span, x)
                                       : std::exp(std::log(w_lo) + x * (std::log(w_hi) - std::log(w_lo))));
  }
  // Seed the resonances and anti-resonances of the undamped chain, and the
  // midpoints between them, so that clustered modes get their own intervals.
  // Held at the top too where c_r exceeds the top's own critical damping √(k_0 J_0), which
  // holds it nearly still (a string of 0.1 kg·m² inertias with c_r = 320 N·m·s/rad lost two Hopf
  // points at 2.88 and 2.93 rad/s, two zeros of Im Z_b inside one interval); not elsewhere,
  // where these seeds only lengthen the grid (1.6 times the time at 3000 pipes).
  const bool held = p.top_damping > std::sqrt(p.stiffnesses[0] * p.inertias[0]);
  std::vector<double> seeds;
  for (const auto& [bit_clamped, top_clamped] : {std::pair{true, false}, {false, false}, {false, true}, {true, true}}) {
    if (top_clamped && !held) continue;
    const std::vector<double> more = undamped_frequencies(p, bit_clamped, poll, top_clamped);
    seeds.insert(seeds.end(), more.begin(), more.end());
  }
  std::sort(seeds.begin(), seeds.end());
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    if (seeds[i] > w_lo && seeds[i] < w_hi) grid.push_back(seeds[i]);
    if (i + 1 < seeds.size() && seeds[i] > 0) grid.push_back(0.5 * (seeds[i] + seeds[i + 1]));
  }
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());

  constexpr double pi = 3.14159265358979323846;
  auto turn = [&](double a, double b) {  // phase change from a to b, unwrapped to (−π, π]
    double d = b - a;
    while (d > pi) d -= 2 * pi;
    while (d <= -pi) d += 2 * pi;
    return d;
  };
  // Evaluations of the phase since the poll last heard of them, counted in a plain integer:
  // a call to the poll beside each one cost 5 % on a short string (the phase was no longer
  // inlined).
  long evaluations = 0;
  auto g = [&](double w) {  // Im Z_b / |Z_b| = sin(arg Z_b)
    ++evaluations;
    return std::sin(phase(p, w));
  };
  auto consider = [&](double wa, double pa, double wb, double pb) {
    const double ga = std::sin(pa), gb = std::sin(pb);
    // A zero of Im Z_b with Re Z_b > 0: the phase passes through 0.
    if ((ga < 0) == (gb < 0) || std::cos(pa) + std::cos(pb) <= 0) return;
    const double w = brent(g, wa, wb, ga, gb);
    const complex z = impedance(p, complex(0.0, w));
    // (At a mode of hopf_at_zero, Re Z_b is 0 up to rounding: that crossing is counted once.)
    const bool known = std::any_of(at_zero.begin(), at_zero.end(),
                                   [&](const Crossing& c) { return std::fabs(c.frequency - w) <= 1e-9 * w; });
    // Im Z_b is 0 there to 1e-6 of |Z_b|, or it changes sign within 8 ε ω of ω (Brent's
    // bracket): on a lightly damped string one ulp of ω moves Im Z_b by more than 1e-6 of |Z_b|
    // (a chain of J = 0.4, k = 2.5 with c_r = 1e-9: Re Z_b = 1e-9 at its destabilising Hopf
    // points, 1e9 at its restabilising ones), and 7 of its 13 crossings were dropped.
    auto converged = [&] {
      if (std::fabs(std::imag(z)) <= 1e-6 * std::abs(z)) return true;
      const double w_below = w * (1 - 8 * std::numeric_limits<double>::epsilon());
      const double w_above = w * (1 + 8 * std::numeric_limits<double>::epsilon());
      const complex zb = impedance(p, complex(0.0, w_below)), za = impedance(p, complex(0.0, w_above));
      // ... and Re Z_b, the crossing's δ, is the same across that bracket: where a resonance is
      // narrower than an ulp of ω (a top inertia of 1e40 and more), Re Z_b jumps tenfold from one
      // double to the next, and such a "crossing" had a δ and a direction of rounding alone.
      // (And Im Z_b is below Re Z_b even so, the phase within 45°: at a pole of Im Z_b, where
      // it changes sign through infinity, it is not.)
      const double re = std::real(z);
      return std::fabs(std::imag(z)) <= re && (std::imag(zb) < 0) != (std::imag(za) < 0) &&
             std::fabs(std::real(zb) - re) <= 1e-6 * re &&
             std::fabs(std::real(za) - re) <= 1e-6 * re;
    };
    if (!known && std::real(z) > 0 && converged()) {
      out.push_back({CrossingType::Hopf, std::real(z), w, crossing_direction(p, w), 2});
    }
  };
  struct Piece {
    double wa, pa, wb, pb;
    int depth;
  };
  // Two zeros of Im Z_b inside one piece, the phase dipping through 0 and back with both ends
  // on one side: the turn test cannot see them (the net turn is small), and the unstable window
  // of δ between the pair's two Hopf points was lost (on strings damped far beyond critical: a
  // pair 0.012 rad/s apart at 4.44 rad/s; 31 of 12000 random strings with element dampings
  // 1e-4 to 1e3 times critical, none since). Found from the phases already known, nothing
  // evaluated where they show nothing: a dip is a local minimum of |φ| among the pieces' ends,
  // near 0 (split_dip: the phase's slopes at the piece's ends, a cubic through them, and the
  // piece split while that cubic comes near 0); a narrow resonance in a phase small everywhere
  // swings by more than its distance from 0 across one piece (split_steep). The slopes at every
  // piece near 0 instead cost 2.3 to 5 times the search; these, 0 to 4 %.
  auto phase_slope = [&](double w) {  // dφ/dω = Re(Z_b'(iω) / Z_b(iω))
    const complex lambda(0.0, w);
    return std::real(impedance_slope(p, lambda) / impedance(p, lambda));
  };
  auto one_side = [](double pa, double pb) {  // both ends on one side of 0, with Re Z_b > 0
    return (pa < 0) == (pb < 0) && std::fabs(pa) < pi / 2 && std::fabs(pb) < pi / 2;
  };
  std::function<void(const Piece&)> split_dip = [&](const Piece& c) {
    if (c.depth >= 40 || !one_side(c.pa, c.pb)) return;
    const double side = c.pa + c.pb > 0 ? 1.0 : -1.0;  // |φ| = side · φ in the piece
    const double sa = side * phase_slope(c.wa), sb = side * phase_slope(c.wb);
    if (!(sa < 0 && sb > 0)) return;  // |φ| falls from neither end: no dip inside
    const double h = c.wb - c.wa, fa = side * c.pa, fb = side * c.pb;
    double lowest = std::min(fa, fb);
    for (int k = 1; k < 16; ++k) {  // the cubic Hermite interpolant's lowest value
      const double t = k / 16.0, t2 = t * t, t3 = t2 * t;
      lowest = std::min(lowest, (2 * t3 - 3 * t2 + 1) * fa + (t3 - 2 * t2 + t) * h * sa +
                                    (3 * t2 - 2 * t3) * fb + (t3 - t2) * h * sb);
    }
    if (!(lowest < 0.5 * std::min(fa, fb))) return;
    const double wm = 0.5 * (c.wa + c.wb), pm = phase(p, wm);
    for (const Piece& half : {Piece{c.wa, c.pa, wm, pm, c.depth + 1}, Piece{wm, pm, c.wb, c.pb, c.depth + 1}}) {
      consider(half.wa, half.pa, half.wb, half.pb);  // the pair, once it shows
      split_dip(half);
    }
  };
  // A piece over which |φ| changes by more than its distance from 0 (a narrow resonance's
  // swing in a phase that is small everywhere, as on a string damped far beyond critical):
  // split until each part changes by less, the pair then showing as two sign changes.
  std::function<void(const Piece&)> split_steep = [&](const Piece& c) {
    const double wm = 0.5 * (c.wa + c.wb), pm = phase(p, wm);
    for (const Piece& half : {Piece{c.wa, c.pa, wm, pm, c.depth + 1}, Piece{wm, pm, c.wb, c.pb, c.depth + 1}}) {
      consider(half.wa, half.pa, half.wb, half.pb);
      if (half.depth < 40 && one_side(half.pa, half.pb) &&
          std::fabs(half.pa - half.pb) > std::min(std::fabs(half.pa), std::fabs(half.pb)))
        split_steep(half);
    }
  };
  auto find_hidden_pairs = [&](const std::vector<Piece>& all) {
    auto crosses = [&](const Piece& c) { return (c.pa < 0) != (c.pb < 0); };
    for (std::size_t k = 1; k + 1 < all.size(); ++k) {
      const Piece& c = all[k];
      if (!one_side(c.pa, c.pb) || c.depth >= 40) continue;
      const double side = c.pa + c.pb > 0 ? 1.0 : -1.0;
      // |φ| falls into the piece and rises out of it, and moves by more than its distance
      // from 0 over a neighbouring piece: it may reach 0 inside.
      const double into = side * turn(all[k - 1].pa, c.pa), out_of = side * turn(c.pb, all[k + 1].pb);
      const double fa = side * c.pa, fb = side * c.pb, nearest = std::min(fa, fb);
      if (into < 0 && out_of > 0 && nearest < std::max(-into, out_of)) {
        split_dip(c);
      } else if (std::fabs(fa - fb) > nearest && !crosses(fa < fb ? all[k - 1] : all[k + 1])) {
        // (not where a zero lies just beyond the nearer end: |φ| is small there for that zero)
        split_steep(c);
      }
    }
  };
  std::vector<Piece> stack, pieces;
  pieces.reserve(2 * grid.size());
  double w_prev = grid.front(), p_prev = phase(p, w_prev);
  for (std::size_t i = 1; i < grid.size(); ++i) {
    poll.tick(++evaluations * N);
    evaluations = 0;
    const double w = grid[i], ph = phase(p, w);
    stack.push_back({w_prev, p_prev, w, ph, 0});
    while (!stack.empty()) {
      Piece c = stack.back();
      stack.pop_back();
      if (std::fabs(turn(c.pa, c.pb)) > pi / 4 && c.depth < 40) {
        ++evaluations;
        const double wm = 0.5 * (c.wa + c.wb), pm = phase(p, wm);
        stack.push_back({wm, pm, c.wb, c.pb, c.depth + 1});  // right half after the left
        stack.push_back({c.wa, c.pa, wm, pm, c.depth + 1});
        continue;
      }
      consider(c.wa, c.pa, c.wb, c.pb);
      pieces.push_back(c);
    }
    w_prev = w;
    p_prev = ph;
  }
  find_hidden_pairs(pieces);
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) { return a.delta < b.delta; });
  return out;
}

int unstable_count(const std::vector<Crossing>& crossings, double delta) {
  check_delta(delta);
  int count = 0;
  for (const auto& c : crossings) {
    if (c.delta < delta) count += c.direction * c.multiplicity;
  }
  return count;
}

}  // namespace pydrill
