// Stability of steady drilling (DESIGN.md §3).
//
// Linearised about any steady state Ω > 0, the reduced Jacobian (twist
// coordinates, n' = 2·dof − 1) is J = A'_0 + (δ/J_b) e eᵀ: it depends on the
// operating point only through the Stribeck slope
//     δ(Ω, W_ob) = W_ob R_b (γ_b/v_f)(μ_sb − μ_cb) exp(−γ_b Ω / v_f) > 0.
// Its eigenvalues are the roots of Z_b(λ) = δ, with Z_b the mechanical
// impedance seen from the bit (a continued fraction along the chain). So the
// whole stability picture of a string is a handful of critical values δ_k,
// computed once, and every boundary W_ob(Ω) is closed-form.
#pragma once

#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pydrill/export.hpp"
#include "pydrill/params.hpp"

// Every function below throws std::invalid_argument for invalid Params (Params::validate)
// and for a slope δ that is not a finite number; other ranges are given with each one. None
// keeps state between calls: any number of threads may call them at once.
// Units: δ in N·m·s/rad, Ω and frequencies in rad/s, W_ob in N, torques in N·m, λ in 1/s.
namespace pydrill {

// Complex numbers are std::complex<double> throughout. (No pydrill::complex alias: after
// `using namespace std; using namespace pydrill;` it made every complex<double> ambiguous.)

// Stopping a long computation. critical_deltas, structured_eigenvalues, roots_of_impedance,
// stability_at_velocity and stability_at_torque are O(dof²): under a millisecond at a dozen
// inertias, 8 s at 6000, half an hour at the largest string (100000). Each takes an optional
// `interrupt`, as SimulationOptions::interrupt does: asked about every 0.1 s of wall time while
// the computation goes on (so never by one that ends sooner), true stops it with
// StabilityInterrupted (a Ctrl-C from Python, a cancel button in a program that embeds
// pydrill). Empty: never asked. The dense O(n'³) eigensolver is not asked inside, only before
// it starts (where structured_eigenvalues and the stability points fall back on it).
// A Cancelled (params.hpp), as a stopped run's Interrupted is.
class PYDRILL_API StabilityInterrupted : public Cancelled {};

// δ(Ω, W_ob), N·m·s/rad; W_ob > 0, Ω >= 0.
PYDRILL_API double stribeck_slope(const Params& params, double wob, double omega);
// The weight on bit (N) at which δ(Ω, W_ob) = delta; delta must be > 0 and Ω >= 0 (rad/s).
PYDRILL_API double boundary_wob(const Params& params, double delta, double omega);

// Z_b(λ) = J_b λ + c_b + Z_string(λ) in N·m·s/rad, λ in 1/s (finite), evaluated in O(dof).
PYDRILL_API std::complex<double> bit_impedance(const Params& params, std::complex<double> lambda);

// Dense reduced Jacobian at slope δ, row-major n' × n' (twist coordinates).
PYDRILL_API std::vector<double> jacobian(const Params& params, double delta);
// Its eigenvalues (brute force, O(n'³)); sorted by decreasing real part. Throws
// std::runtime_error if the dense eigenvalue solver does not converge.
PYDRILL_API std::vector<std::complex<double>> eigenvalues(const Params& params, double delta);
// The same eigenvalues in O(n'²), as the roots of Z_b(λ) = δ found all at once
// (Ehrlich–Aberth on the chain's recurrence, started from the free chain's modes
// with their modal damping): 0.67 s becomes 0.02 s at dof 303, and on overdamped
// real strings alike. Checked against the trace and conjugate symmetry; where a
// check fails (e.g. a multiple eigenvalue), the dense solver answers. `interrupt`: see
// StabilityInterrupted above.
PYDRILL_API std::vector<std::complex<double>> structured_eigenvalues(
    const Params& params, double delta, const std::function<bool()>& interrupt = {});
// Its O(n'²) part alone: true, with the sorted eigenvalues in `out`, when every
// check passed; false (and `out` untouched) when the dense solver is needed.
PYDRILL_API bool roots_of_impedance(const Params& params, double delta,
                                    std::vector<std::complex<double>>& out,
                                    const std::function<bool()>& interrupt = {});

// Characteristic polynomial det(λI − J) at slope δ, monic, coefficients in
// ascending powers a_0 … a_{n'} (a_{n'} = 1), from exact polynomial
// recurrences of the continued fraction. Meant for small strings (the
// coefficients span many decades as dof grows); std::invalid_argument above dof 12.
PYDRILL_API std::vector<double> characteristic_polynomial(const Params& params, double delta);
// Hurwitz determinants Δ_1 … Δ_{n−1} of a polynomial given in ascending
// powers (leading coefficient last, positive). std::invalid_argument for degree < 1,
// a coefficient that is not finite or a leading one <= 0.
PYDRILL_API std::vector<double> hurwitz_determinants(const std::vector<double>& ascending);
// The paper's n' = 3 closed form (dof 2, Eq. 50–51 with Δ_2 = a_2 a_1 − a_0):
// the δ at which Δ_2 = 0 inside the paper's H₊ (a_1 > 0 and a_0 > 0, i.e. below
// the fold δ = c_r + c_b), in increasing order (0, 1 or 2 values > 0). A Hopf
// point above the fold (a_0 < 0) is not among them: critical_deltas finds every
// crossing.
// std::invalid_argument unless dof = 2.
PYDRILL_API std::vector<double> hopf_deltas_dof2(const Params& params);

// How eigenvalues reach the imaginary axis.
enum class CrossingType {
  Hopf,  // a pair ±iω: an oscillation is born
  Fold,  // λ = 0: steady states meet (at δ = c_r + c_b)
};
// "hopf", "fold"; "?" for a value outside the enum.
PYDRILL_API const char* crossing_type_name(CrossingType t) noexcept;
// The inverse; std::invalid_argument for any other name.
PYDRILL_API CrossingType parse_crossing_type(const std::string& s);

// A value of δ at which eigenvalues reach the imaginary axis.
struct Crossing {
  CrossingType type = CrossingType::Hopf;
  double delta = 0;     // N·m·s/rad
  double frequency = 0; // rad/s; 0 for a fold
  int direction = 0;    // +1: the eigenvalues move into the right half-plane as δ grows
  int multiplicity = 0; // eigenvalues that cross: 2 (Hopf) or 1 (fold)
};

// Every crossing, in increasing δ (every δ >= 0). Found from the zeros of
// Im Z_b(iω) on a frequency grid fine enough to separate the string's modes,
// refined to machine precision; O(dof²) in all (`interrupt`: see StabilityInterrupted).
// A crossing at δ = 0 is the fold of a string with c_r = c_b = 0 (it turns freely as one
// body) and, on a string with no damping at all, every Hopf point too: each of its modes
// grows for any δ > 0, and none comes back.
PYDRILL_API std::vector<Crossing> critical_deltas(const Params& params,
                                                  const std::function<bool()>& interrupt = {});

// First Lyapunov coefficient of the Hopf point at slope δ with frequency ω
// (Kuznetsov's formula; the only nonlinearity is the bit friction, whose
// Taylor terms about Ω are T'' = δγ/v_f and T''' = −δ(γ/v_f)²). Negative:
// supercritical (a small stable oscillation is born); positive: subcritical
// (the motion jumps away, with hysteresis). frequency finite and > 0 (rad/s); std::invalid_argument
// too where the linearisation is singular (δ at the fold, c_r + c_b, unless δ = 0).
// At δ = 0 it is 0 (degenerate): the friction is flat about Ω to every order there.
// Normalisation: the eigenvector q of iω has unit Euclidean norm in twist coordinates
// (which mix rad and rad/s) and ⟨p, q⟩ = 1, so the value depends on that choice: use
// its sign, and compare sizes only between Hopf points of one string. O(dof): banded solves.
// (δ, ω) must be a Hopf point (a Crossing's delta and frequency: iω an eigenvalue at δ):
// std::invalid_argument, naming both, where iω lies more than 1 % of ω from every eigenvalue
// at δ (the distance estimated by a Newton step on Z_b(λ) = δ; a crossing's pair typed to six
// digits passes), whose coefficient would belong to no Hopf point.
PYDRILL_API double first_lyapunov_coefficient(const Params& params, double delta,
                                              double frequency);

// Number of eigenvalues with positive real part at slope δ, from the crossings (any
// finite δ; 0 below the first crossing, so for every δ <= 0).
PYDRILL_API int unstable_count(const std::vector<Crossing>& crossings, double delta);

struct StabilityPoint {
  // The steady state: Ω (rad/s; < 0 for a negative torque), W_ob (N), u (N·m), δ (N·m·s/rad).
  double omega = 0, wob = 0, torque = 0, delta = 0;
  int unstable = 0;                  // eigenvalues in the right half-plane
  bool stable = false;
  double delta_margin = 0;           // δ distance to the nearest crossing (> 0 inside the
                                     // stable region: how much δ may grow before it is lost)
  double spectral_abscissa = 0;      // max Re λ, 1/s
  std::vector<std::complex<double>> eigenvalues;  // λ in 1/s, sorted by decreasing real part
};

// Stability of the steady state at velocity Ω (finite, > 0; the torque it needs follows),
// W_ob > 0. These three take an `interrupt` as critical_deltas does (see StabilityInterrupted).
PYDRILL_API StabilityPoint stability_at_velocity(const Params& params, double wob, double omega,
                                                 const std::function<bool()>& interrupt = {});
// Stability of every steady state for (W_ob > 0, finite u): 0, 1 or 2 of them. For u < 0, the
// mirror image of |u|: the same points with Ω and u reversed.
PYDRILL_API std::vector<StabilityPoint> stability_at_torque(
    const Params& params, double wob, double torque, const std::function<bool()>& interrupt = {});
// The same with the string's crossings (critical_deltas(params)) already at hand: they
// depend on the string alone, and finding them costs more than the rest on a short
// string (a sweep over W_ob and u computes them once per string, not once per point).
// They come right after the string they belong to, so that stability_at_torque(p, wob, u, {})
// has one meaning (no interrupt). They must be this string's: its one fold, at δ = c_r + c_b
// (std::invalid_argument for an empty list, or another string's; crossings of another string
// with the same damping pass unnoticed).
PYDRILL_API std::vector<StabilityPoint> stability_at_torque(
    const Params& params, const std::vector<Crossing>& crossings, double wob, double torque,
    const std::function<bool()>& interrupt = {});

}  // namespace pydrill
