#include "pydrill/stability.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <utility>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "band_lu.hpp"
#include "interrupt_poll.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/friction.hpp"
#include "shortest.hpp"

namespace pydrill {

// Shorthand for this file only: the public headers spell std::complex<double>.
using complex = std::complex<double>;

const char* crossing_type_name(CrossingType t) noexcept {
  switch (t) {
    case CrossingType::Hopf: return "hopf";
    case CrossingType::Fold: return "fold";
  }
  return "?";
}

CrossingType parse_crossing_type(const std::string& s) {
  if (s == "hopf") return CrossingType::Hopf;
  if (s == "fold") return CrossingType::Fold;
  throw std::invalid_argument("crossing type = '" + s + "' is not allowed: choose 'hopf' or 'fold'");
}

namespace {

double stribeck_factor(const Params& p) {
  return p.bit_radius * (p.stribeck_decay / p.stribeck_velocity) * (p.mu_static - p.mu_coulomb);
}

// Z_b = N/D with N and D rescaled at every element so that long strings
// neither overflow nor underflow; their ratio is all that matters.
struct Fraction {
  complex num, den;
};

Fraction bit_fraction(const Params& p, complex lambda) {
  const int n = p.dof();
  complex num = p.inertias[0] * lambda + p.top_damping, den = 1.0;
  for (int i = 0; i < n - 1; ++i) {
    // Spring i has impedance (k + cλ)/λ in series with everything above it.
    const complex spring = p.stiffnesses[i] + p.dampings[i] * lambda;
    const complex n_above = spring * num;
    const complex d_above = spring * den + lambda * num;
    const complex own = p.inertias[i + 1] * lambda + (i + 1 == n - 1 ? p.bit_damping : 0.0);
    num = own * d_above + n_above;
    den = d_above;
    // Rescale by a power of two (exact, cheap) before anything can overflow.
    const double big = std::max(std::max(std::fabs(num.real()), std::fabs(num.imag())),
                                std::max(std::fabs(den.real()), std::fabs(den.imag())));
    if (big > 1e100 || (big < 1e-100 && big > 0)) {
      const int e = std::ilogb(big);
      num = complex(std::ldexp(num.real(), -e), std::ldexp(num.imag(), -e));
      den = complex(std::ldexp(den.real(), -e), std::ldexp(den.imag(), -e));
    }
  }
  return {num, den};
}

// Z_b(λ) for a string already validated (the public bit_impedance checks first).
complex impedance(const Params& p, complex lambda) {
  const Fraction f = bit_fraction(p, lambda);
  return f.num / f.den;
}

// Natural frequencies of the undamped chain, with the bit clamped (the poles
// of Z_b, nearly) or free (its zeros, nearly): symmetric tridiagonal, O(dof²).
std::vector<double> undamped_frequencies(const Params& p, bool clamped, detail::InterruptPoll& poll) {
  const int n = clamped ? p.dof() - 1 : p.dof();
  Eigen::VectorXd diag(n), sub(std::max(n - 1, 1));
  for (int i = 0; i < n; ++i) {
    double k = 0.0;
    if (i > 0) k += p.stiffnesses[i - 1];
    if (i < p.dof() - 1) k += p.stiffnesses[i];  // the last spring holds a clamped bit
    diag(i) = k / p.inertias[i];
    if (i + 1 < n) sub(i) = -p.stiffnesses[i] / std::sqrt(p.inertias[i] * p.inertias[i + 1]);
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

// dλ/dδ = 1/Z_b'(λ) on the imaginary axis; its real part says which way the
// eigenvalues cross as δ grows.
int crossing_direction(const Params& p, double omega) {
  const double h = 1e-6 * std::max(omega, 1e-3);
  const complex dz = (impedance(p, complex(h, omega)) - impedance(p, complex(-h, omega))) / (2 * h);
  const double re = std::real(1.0 / dz);
  return re > 0 ? 1 : (re < 0 ? -1 : 0);
}

using Poly = std::vector<double>;  // ascending powers

Poly times_linear(const Poly& a, double c0, double c1) {  // a·(c0 + c1 λ)
  Poly r(a.size() + 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    r[i] += c0 * a[i];
    r[i + 1] += c1 * a[i];
  }
  return r;
}

// δ enters every linearisation as a number; a NaN or infinite one would come back as a
// "did not converge", a NaN spectrum or a stable count, none of which names it.
void check_delta(double delta) {
  if (!std::isfinite(delta)) {
    std::ostringstream o;
    o << "delta = " << detail::shortest(delta) << " is not allowed: the Stribeck slope must be a finite number (N·m·s/rad)";
    throw std::invalid_argument(o.str());
  }
}

Poly add(Poly a, const Poly& b) {
  if (b.size() > a.size()) a.resize(b.size(), 0.0);
  for (std::size_t i = 0; i < b.size(); ++i) a[i] += b[i];
  return a;
}

}  // namespace

double stribeck_slope(const Params& p, double wob, double omega) {
  p.validate();
  check_operating_point(wob, 0.0);
  if (!std::isfinite(omega) || !(omega >= 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: the Stribeck slope is defined at a finite bit velocity >= 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  return wob * stribeck_factor(p) * std::exp(-p.stribeck_decay * omega / p.stribeck_velocity);
}

double boundary_wob(const Params& p, double delta, double omega) {
  p.validate();
  check_delta(delta);
  // δ ∝ W_ob > 0: a slope <= 0 has no weight on bit (it came back as W_ob <= 0).
  if (!(delta > 0)) {
    throw std::invalid_argument("delta = " + detail::shortest(delta) +
                                " is not allowed: must be > 0 N·m·s/rad (the Stribeck slope of a weight on bit > 0)");
  }
  if (!std::isfinite(omega) || !(omega >= 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: a boundary is drawn at a finite bit velocity >= 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  return delta * std::exp(p.stribeck_decay * omega / p.stribeck_velocity) / stribeck_factor(p);
}

complex bit_impedance(const Params& p, complex lambda) {
  p.validate();
  if (!std::isfinite(lambda.real()) || !std::isfinite(lambda.imag())) {
    std::ostringstream o;
    o << "lambda = (" << detail::shortest(lambda.real()) << "," << detail::shortest(lambda.imag()) << ")" << " is not allowed: the impedance is evaluated at a finite complex number";
    throw std::invalid_argument(o.str());
  }
  return impedance(p, lambda);
}

namespace {

// The reduced Jacobian's entries, at(row, column) = value for each that is not zero: at most
// two neighbours either side of the diagonal (interleaved coordinates).
template <typename At>
void jacobian_entries(const Params& p, double delta, At&& at) {
  const int N = p.dof();
  for (int i = 0; i < N; ++i) {
    const int r = 2 * i;
    const double inv = 1.0 / p.inertias[i];
    double diag = (i == 0 ? -p.top_damping : 0.0) + (i == N - 1 ? -p.bit_damping + delta : 0.0);
    if (i > 0) {
      at(r, r - 2) = p.dampings[i - 1] * inv;
      at(r, r - 1) = p.stiffnesses[i - 1] * inv;
      diag -= p.dampings[i - 1];
    }
    if (i < N - 1) {
      at(r, r + 1) = -p.stiffnesses[i] * inv;
      at(r, r + 2) = p.dampings[i] * inv;
      diag -= p.dampings[i];
      at(r + 1, r) = 1.0;
      at(r + 1, r + 2) = -1.0;
    }
    at(r, r) = diag * inv;
  }
}

}  // namespace

std::vector<double> jacobian(const Params& p, double delta) {
  p.validate();
  check_delta(delta);
  const int n = 2 * p.dof() - 1;
  std::vector<double> J(static_cast<std::size_t>(n) * n, 0.0);
  jacobian_entries(p, delta, [&](int r, int c) -> double& { return J[static_cast<std::size_t>(r) * n + c]; });
  return J;
}

std::vector<complex> eigenvalues(const Params& p, double delta) {
  const std::vector<double> J = jacobian(p, delta);
  const int n = 2 * p.dof() - 1;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(
      J.data(), n, n);
  Eigen::EigenSolver<Eigen::MatrixXd> solver(M, false);
  if (solver.info() != Eigen::Success) throw std::runtime_error("eigenvalue solver did not converge");
  std::vector<complex> ev(solver.eigenvalues().data(), solver.eigenvalues().data() + n);
  std::sort(ev.begin(), ev.end(), [](complex a, complex b) {
    return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
  });
  return ev;
}

std::vector<double> characteristic_polynomial(const Params& p, double delta) {
  p.validate();
  check_delta(delta);
  const int N = p.dof();
  if (N > 12) {
    throw std::invalid_argument("dof = " + std::to_string(N) +
                                " is too large for the characteristic polynomial (its coefficients "
                                "lose all accuracy): allowed dof <= 12; use critical_deltas");
  }
  Poly num{p.top_damping, p.inertias[0]}, den{1.0};
  for (int i = 0; i < N - 1; ++i) {
    const Poly n_above = times_linear(num, p.stiffnesses[i], p.dampings[i]);
    const Poly d_above = add(times_linear(den, p.stiffnesses[i], p.dampings[i]), times_linear(num, 0.0, 1.0));
    const double own_c = (i + 1 == N - 1) ? p.bit_damping : 0.0;
    num = add(times_linear(d_above, own_c, p.inertias[i + 1]), n_above);
    den = d_above;
  }
  // det(λI − J) ∝ N_b(λ) − δ D_b(λ); the leading coefficient of N_b is Π I_i.
  Poly c = num;
  for (std::size_t i = 0; i < den.size(); ++i) c[i] -= delta * den[i];
  const double lead = c.back();
  for (double& v : c) v /= lead;
  return c;
}

std::vector<double> hurwitz_determinants(const std::vector<double>& a) {
  const int n = static_cast<int>(a.size()) - 1;
  if (n < 1) throw std::invalid_argument("hurwitz_determinants needs a polynomial of degree >= 1");
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i])) {
      std::ostringstream o;
      o << "ascending[" << i << "] = " << detail::shortest(a[i]) << " is not allowed: coefficients must be finite";
      throw std::invalid_argument(o.str());
    }
  }
  if (!(a.back() > 0)) {
    std::ostringstream o;
    o << "ascending[" << n << "] = " << detail::shortest(a.back())
      << " is not allowed: the leading coefficient (last) must be > 0";
    throw std::invalid_argument(o.str());
  }
  auto b = [&](int k) { return (k < 0 || k > n) ? 0.0 : a[static_cast<std::size_t>(n - k)]; };
  std::vector<double> out;
  for (int m = 1; m < n; ++m) {
    Eigen::MatrixXd H(m, m);
    for (int i = 1; i <= m; ++i)
      for (int j = 1; j <= m; ++j) H(i - 1, j - 1) = b(2 * j - i);
    out.push_back(H.determinant());
  }
  return out;
}

std::vector<double> hopf_deltas_dof2(const Params& p) {
  p.validate();
  if (p.dof() != 2) throw std::invalid_argument("the closed form of Eq. (51) is for dof = 2 (n' = 3)");
  const double Jr = p.inertias[0], Jb = p.inertias[1], kt = p.stiffnesses[0], ct = p.dampings[0];
  const double cr = p.top_damping, cb = p.bit_damping, P = Jb * Jr;
  // a_2 = (α2 − J_r δ)/P, a_1 = (α1 − β δ)/P, a_0 = (α0 − k_t δ)/P (Eq. 50 with d_b = −δ).
  const double a2c = Jr * (cb + ct) + Jb * (cr + ct), beta = ct + cr;
  const double a1c = cb * (cr + ct) + ct * cr + kt * (Jb + Jr), a0c = kt * (cb + cr);
  // P²Δ_2 = (α2 − J_r δ)(α1 − β δ) − P(α0 − k_t δ) = A δ² + B δ + C.
  const double A = Jr * beta, B = -(a2c * beta + Jr * a1c - P * kt), C = a2c * a1c - P * a0c;
  std::vector<double> roots;
  const double disc = B * B - 4 * A * C;
  if (A == 0.0) {
    if (B != 0.0) roots.push_back(-C / B);
  } else if (disc >= 0) {
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    roots.push_back(q / A);
    if (q != 0.0) roots.push_back(C / q);
  }
  std::vector<double> hopf;
  for (double d : roots) {
    // A Hopf point needs a_1 > 0 and a_0 > 0 there (the paper's set H_+).
    if (d > 0 && a1c - beta * d > 0 && a0c - kt * d > 0) hopf.push_back(d);
  }
  std::sort(hopf.begin(), hopf.end());
  return hopf;
}

std::vector<Crossing> critical_deltas(const Params& p, const std::function<bool()>& interrupt) {
  p.validate();
  const int N = p.dof();
  std::vector<Crossing> out;
  // Nearly all the time goes into O(dof) evaluations of the phase, thousands of them on a
  // long string; the poll hears of them once per grid point (below).
  detail::InterruptPoll poll(interrupt);

  // Fold: λ = 0 is an eigenvalue when δ = Z_b(0) = c_r + c_b.
  const double fold = p.top_damping + p.bit_damping;
  if (fold > 0) {
    const double h = 1e-7 * std::max(fold, 1e-12);
    const double dz = (std::real(impedance(p, complex(h, 0))) - std::real(impedance(p, complex(-h, 0)))) / (2 * h);
    out.push_back({CrossingType::Fold, fold, 0.0, dz > 0 ? 1 : -1, 1});
  }

  // Hopf: zeros of Im Z_b(iω) with Re Z_b > 0. No zero lies above the
  // highest natural frequency of the chain, where J_b ω dominates.
  double w2max = 0.0, rate = 0.0;
  double compliance = 0.0, inertia = 0.0;
  for (int i = 0; i < N; ++i) {
    double ks = 0.0, cs = (i == 0 ? p.top_damping : 0.0) + (i == N - 1 ? p.bit_damping : 0.0);
    if (i > 0) { ks += p.stiffnesses[i - 1]; cs += p.dampings[i - 1]; }
    if (i < N - 1) { ks += p.stiffnesses[i]; cs += p.dampings[i]; }
    w2max = std::max(w2max, 2.0 * ks / p.inertias[i]);
    rate = std::max(rate, 2.0 * cs / p.inertias[i]);
    if (i < N - 1) { compliance += 1.0 / p.stiffnesses[i]; inertia += p.inertias[i]; }
  }
  const double w_hi = 2.0 * std::sqrt(w2max) + rate + 1e-9;
  const double w_lo = 1e-4 * std::sqrt(1.0 / (compliance * inertia));
  // Start from a uniform grid (the dense upper spectrum) merged with a
  // geometric one (the low modes of long strings), then split every interval
  // over which arg Z_b turns by more than π/4 until it does not: a zero of
  // Im Z_b is a turn through a multiple of π, so none can hide inside.
  const int m = std::max(1000, 6 * N);
  std::vector<double> grid;
  grid.reserve(2 * static_cast<std::size_t>(m));
  for (int i = 1; i <= m; ++i) grid.push_back(w_hi * i / m);
  for (int i = 0; i < m; ++i) grid.push_back(w_lo * std::pow(w_hi / w_lo, static_cast<double>(i) / m));
  // Seed the resonances and anti-resonances of the undamped chain, and the
  // midpoints between them, so that clustered modes get their own intervals.
  std::vector<double> seeds = undamped_frequencies(p, true, poll);
  const std::vector<double> free = undamped_frequencies(p, false, poll);
  seeds.insert(seeds.end(), free.begin(), free.end());
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
    if (std::real(z) > 0 && std::fabs(std::imag(z)) <= 1e-6 * std::abs(z)) {
      out.push_back({CrossingType::Hopf, std::real(z), w, crossing_direction(p, w), 2});
    }
  };
  struct Piece {
    double wa, pa, wb, pb;
    int depth;
  };
  std::vector<Piece> stack;
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
    }
    w_prev = w;
    p_prev = ph;
  }
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) { return a.delta < b.delta; });
  return out;
}

double first_lyapunov_coefficient(const Params& p, double delta, double w) {
  if (!std::isfinite(w) || !(w > 0)) {
    std::ostringstream o;
    o << "frequency = " << detail::shortest(w) << " is not allowed: a Hopf point needs a finite frequency > 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  p.validate();
  check_delta(delta);
  const int n = 2 * p.dof() - 1, b = n - 1;
  // The Jacobian's band alone, J(r, c) at band[5r + c − r + 2]: built dense, it cost O(n'²)
  // time and memory (1.1 s and 1.2 GB at 6000 pipes).
  std::vector<double> band(static_cast<std::size_t>(n) * 5, 0.0);
  jacobian_entries(p, delta, [&](int r, int c) -> double& { return band[static_cast<std::size_t>(r) * 5 + (c - r + 2)]; });
  auto J = [&](int r, int c) { return band[static_cast<std::size_t>(r) * 5 + (c - r + 2)]; };
  using CVec = std::vector<complex>;
  const complex iw(0.0, w);
  // Every matrix below is s·A (or s·Aᵀ) + shift·I: banded like A (two neighbours either
  // side in the interleaved coordinates), so each solve is O(n'), not a dense O(n'³) LU
  // (2.6 s at 500 pipes).
  auto banded = [&](bool transpose, double scale, complex shift) {
    BandLU<complex> lu(n, 2, 2);
    for (int r = 0; r < n; ++r) {
      for (int c = std::max(0, r - 2); c <= std::min(n - 1, r + 2); ++c) {
        const double a = transpose ? J(c, r) : J(r, c);
        lu.at(r, c) = scale * a + (r == c ? shift : complex(0.0));
      }
    }
    lu.factor();
    return lu;
  };
  auto dot = [](const CVec& x, const CVec& y) {  // x̄ᵀy
    complex s(0.0);
    for (std::size_t i = 0; i < x.size(); ++i) s += std::conj(x[i]) * y[i];
    return s;
  };
  // Null vectors of A − iω and Aᵀ + iω by inverse iteration (the shift is an exact
  // eigenvalue up to rounding; a tiny offset keeps the LU regular).
  const complex offset(1e-10 * std::max(1.0, w), 0.0);
  auto null_vector = [&](const BandLU<complex>& lu) {
    CVec v(static_cast<std::size_t>(n), complex(1.0));
    for (int it = 0; it < 3; ++it) {
      lu.solve(v);
      const double norm = std::sqrt(std::real(dot(v, v)));
      for (auto& x : v) x /= norm;
    }
    return v;
  };
  const CVec q = null_vector(banded(false, 1.0, -iw - offset));
  CVec pv = null_vector(banded(true, 1.0, iw - offset));
  const complex norm = std::conj(dot(pv, q));  // ⟨p, q⟩ = p̄ᵀq = 1
  for (auto& x : pv) x /= norm;
  const double g = p.stribeck_decay / p.stribeck_velocity;
  // The friction's nonlinearity acts on the bit's velocity alone (the last state):
  // B(x, y) = β x_b y_b e_b and C(x, y, z) = κ x_b y_b z_b e_b.
  const double beta = -delta * g / p.inertias.back();
  const double kappa = delta * g * g / p.inertias.back();
  const complex qb = q[static_cast<std::size_t>(b)], pb = std::conj(pv[static_cast<std::size_t>(b)]);
  auto along_bit = [&](complex value) {
    CVec e(static_cast<std::size_t>(n), complex(0.0));
    e[static_cast<std::size_t>(b)] = value;
    return e;
  };
  CVec a1 = along_bit(beta * qb * std::conj(qb));  // A⁻¹ B(q, q̄)
  banded(false, 1.0, complex(0.0)).solve(a1);
  CVec a2 = along_bit(beta * qb * qb);  // (2iω − A)⁻¹ B(q, q)
  banded(false, -1.0, 2.0 * iw).solve(a2);
  const complex s = pb * kappa * qb * qb * std::conj(qb) - 2.0 * pb * beta * qb * a1[static_cast<std::size_t>(b)] +
                    pb * beta * std::conj(qb) * a2[static_cast<std::size_t>(b)];
  return std::real(s) / (2.0 * w);
}

int unstable_count(const std::vector<Crossing>& crossings, double delta) {
  check_delta(delta);
  int count = 0;
  for (const auto& c : crossings) {
    if (c.delta < delta) count += c.direction * c.multiplicity;
  }
  return count;
}

namespace {

// From this many inertias on, steady states get the structured eigenvalues (measured: 0.12
// against 0.29 ms at dof 24, 21 against 700 ms at dof 303). Below, both take a fraction of
// a millisecond, far less than the simulation beside them, and the dense solver is kept.
constexpr int kStructuredDof = 24;

// Crossings handed in must be the string's: the unstable counts come from them, and an empty
// or foreign list answered "stable" for every point. Every damped string has its fold at
// δ = c_r + c_b, an undamped one none; nothing else in a crossing names its string (the same
// test as Python's, which runs it first, with math.isclose's rel_tol = 1e-9).
void check_crossings(const Params& p, const std::vector<Crossing>& crossings) {
  const double fold = p.top_damping + p.bit_damping;
  std::vector<double> folds;
  for (const Crossing& c : crossings) {
    if (c.type == CrossingType::Fold) folds.push_back(c.delta);
  }
  const bool ok = fold > 0 ? folds.size() == 1 && std::fabs(folds[0] - fold) <=
                                                      1e-9 * std::max(std::fabs(folds[0]), fold)
                           : folds.empty();
  if (!ok) {
    std::ostringstream o;
    o << "crossings are not this string's ("
      << (folds.empty() ? std::string("no fold") : "a fold at delta = " + detail::shortest(folds[0]))
      << "; its own have "
      << (fold > 0 ? "one at c_r + c_b = " + detail::shortest(fold) : std::string("none"))
      << "): give critical_deltas(params) of the same params";
    throw std::invalid_argument(o.str());
  }
}

StabilityPoint point_at(const Params& p, double wob, double omega,
                        const std::vector<Crossing>& crossings,
                        const std::function<bool()>& interrupt) {
  if (!std::isfinite(omega) || !(omega > 0)) {
    std::ostringstream o;
    o << "omega = " << detail::shortest(omega) << " is not allowed: steady drilling needs a finite omega > 0 rad/s";
    throw std::invalid_argument(o.str());
  }
  StabilityPoint s;
  s.omega = omega;
  s.wob = wob;
  s.torque = equilibrium_torque(p, wob, omega);
  s.delta = stribeck_slope(p, wob, omega);
  s.unstable = unstable_count(crossings, s.delta);
  s.stable = s.unstable == 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& c : crossings) nearest = std::min(nearest, std::fabs(c.delta - s.delta));
  s.delta_margin = s.stable ? nearest : -nearest;
  // Long strings: the roots of Z_b = δ in O(n'²), kept only if as many lie in the right
  // half-plane as the crossings say; else (and on short strings, where it gains nothing)
  // the dense solver.
  detail::InterruptPoll poll(interrupt);
  std::vector<complex> roots;
  if (p.dof() >= kStructuredDof && roots_of_impedance(p, s.delta, roots, interrupt) &&
      std::count_if(roots.begin(), roots.end(), [](complex z) { return z.real() > 0; }) == s.unstable) {
    s.eigenvalues = std::move(roots);
  } else {
    poll.check();  // the dense solver cannot be stopped once started
    s.eigenvalues = eigenvalues(p, s.delta);
  }
  s.spectral_abscissa = s.eigenvalues.front().real();
  return s;
}

}  // namespace

StabilityPoint stability_at_velocity(const Params& p, double wob, double omega,
                                     const std::function<bool()>& interrupt) {
  return point_at(p, wob, omega, critical_deltas(p, interrupt), interrupt);
}

std::vector<StabilityPoint> stability_at_torque(const Params& p, double wob, double torque,
                                                const std::function<bool()>& interrupt) {
  if (equilibrium_velocities(p, wob, std::fabs(torque)).empty()) return {};
  // Once per string.
  return stability_at_torque(p, critical_deltas(p, interrupt), wob, torque, interrupt);
}

std::vector<StabilityPoint> stability_at_torque(const Params& p, const std::vector<Crossing>& crossings,
                                                double wob, double torque,
                                                const std::function<bool()>& interrupt) {
  p.validate();
  check_crossings(p, crossings);
  std::vector<StabilityPoint> out;
  for (double omega : equilibrium_velocities(p, wob, std::fabs(torque))) {
    out.push_back(point_at(p, wob, omega, crossings, interrupt));
  }
  if (torque < 0) {
    // Turning backwards is the mirror image (φ → −φ) of turning forwards at |u|: the same
    // steady states reversed, with the same eigenvalues (the friction's slope is even in Ω).
    std::reverse(out.begin(), out.end());
    for (auto& s : out) s.omega = -s.omega, s.torque = -s.torque;
  }
  return out;
}

}  // namespace pydrill
