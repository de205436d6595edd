// Event-driven simulation of the drillstring (DESIGN.md §2) with one of four integrators:
// DOP853 (explicit Runge–Kutta 8(5,3), our own; what Method::Auto picks for non-stiff
// strings), BDF or Adams (SUNDIALS CVODES), ERK (SUNDIALS ARKODE, Fehlberg 7(8)).
//
// Every stick/slip/reversal switch is located as a root of the integrator's interpolant
// (CVODES's and ARKODE's rootfinding, DOP853's dense output) and the integrator is
// restarted there, so no smoothing band is ever used for the exact friction law and no
// chattering occurs.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pydrill/export.hpp"
#include "pydrill/model.hpp"
#include "pydrill/params.hpp"

namespace pydrill {

enum class Method { Auto, BDF, Adams, ERK, DOP853 };
enum class FrictionLaw { Exact, Karnopp };
enum class Initial { Rest, Equilibrium, State };

// What a run is judged to be (DESIGN.md §2, "Regimes"), on the last window_fraction of it.
enum class Regime {
  Steady,       // the bit velocity settles at a steady Ω (paper Fig. 9)
  StickSlip,    // the bit sticks and slips again and again (Fig. 4)
  Stuck,        // the bit sticks and stays stuck (Fig. 7)
  Oscillation,  // a sustained torsional oscillation that never sticks (a Hopf limit cycle)
};

// Names and their parsers: the names Python, the command line and an atlas use. A name
// function returns "?" for a value outside its enum (a static_cast of any int); a parser
// throws std::invalid_argument for any other name.
PYDRILL_API const char* method_name(Method m) noexcept;  // "auto", "bdf", "adams", "erk", "dop853"
PYDRILL_API const char* regime_name(Regime r) noexcept;  // "steady", "stick-slip", "stuck", "oscillation"
PYDRILL_API Method parse_method(const std::string& s);
PYDRILL_API FrictionLaw parse_friction(const std::string& s);  // "exact", "karnopp"
PYDRILL_API Initial parse_initial(const std::string& s);       // "rest", "equilibrium", "state"
PYDRILL_API Regime parse_regime(const std::string& s);

// Tolerance floors: a double resolves ~2.2e-16 relative, and CVODES and ARKODE give up near
// rtol 1e-16; 1e-14 keeps a margin (the paper's dof-4 case runs with every method down to
// 2.3e-16). An atol below 1e-20 only makes the steps collapse at components sitting on 0.
constexpr double kMinRtol = 1e-14;
constexpr double kMinAtol = 1e-20;
// Tolerance ceilings: beyond them a step's error misjudges the regime. Measured with every
// method on the paper's dof-4 cases (W_ob 100 N stick-slip, 40 N steady) and its real string
// (W_ob 100 kN, u 11 kN·m, steady): at rtol 0.05 BDF called the dof-4 steady case stick-slip,
// Adams the real string's, and DOP853's bit reached 1e13 rad/s; at atol 1e-2 (rad, rad/s) BDF
// failed on the stick-slip case and called both steady cases an oscillation, as DOP853 and
// Adams did at 0.1 (the regime judge's noise floor follows rtol, 2000·rtol of the bit
// velocity, not atol). At rtol 1e-2 and atol 1e-3 every method judged every case right.
constexpr double kMaxRtol = 1e-2;
constexpr double kMaxAtol = 1e-3;
// The longest run, s (317 years, as Python's MAX_T_END): near the top of the doubles a run's
// times overflow (t_end = 1.8e308 s: the n_out grid t_end·i/(n_out − 1) was inf, a run of 9
// outputs came back with 2, ERK returned NaN states as a success), and no bit lasts longer.
constexpr double kMaxTEnd = 1e10;

// validate() (called by simulate) throws std::invalid_argument naming the option, its value
// and the allowed range, for any value outside the ranges below.
struct PYDRILL_API SimulationOptions {
  double t_end = 300.0;              // s, 0 < t_end <= kMaxTEnd (1e10)
  std::vector<double> t_out;         // s, strictly increasing in [0, t_end], each 0 or normal
                                     // (>= 2.2e-308: a run flushes subnormals); empty: n_out
                                     // uniform, at least 2.2e-308 s apart
  int n_out = 3001;                  // used when t_out is empty; 2 .. 1e8 (each keeps 2·dof + 5 doubles and an int)
  Method method = Method::Auto;
  FrictionLaw friction = FrictionLaw::Exact;
  // Rest: every velocity and twist 0. Equilibrium: the fastest steady state Ω of (wob, |torque|)
  // (equilibrium.hpp; mirrored for torque < 0) with the bit nudged by `perturbation`; when
  // there is none (the torque cannot balance the bit friction) simulate throws
  // std::invalid_argument. State: `state` as given.
  Initial initial = Initial::Rest;
  std::vector<double> state;         // Initial::State: 2·dof − 1 finite numbers, layout of model.hpp;
                                     // empty otherwise (a state the run would ignore is refused)
  double perturbation = 1e-3;        // Initial::Equilibrium: ω_b = (1 + perturbation)·Ω; |.| < 1
  // Error tolerances per step. rtol: kMinRtol <= rtol <= kMaxRtol. atol: one scalar for every
  // state component (twists in rad, velocities in rad/s), kMinAtol <= atol <= kMaxAtol.
  double rtol = 1e-8;
  double atol = 1e-8;
  double max_step = 0.0;             // s, the longest internal step; 0: no limit; else normal (>= 2.2e-308)
  int max_order = 0;                 // 0: the method's default; BDF 1..5, Adams 1..12, others 0
  long max_steps = 50'000'000;       // internal steps over the whole run (>= 1), then SolverError
  double window_fraction = 0.5;      // last fraction of the run judged for the regime, in (0, 1]
  // Chattering guard (> 0, switches per simulated second): a run is stopped when 50 switches
  // come within less than 50 / max_switch_rate s of the switch 50 before (a burst whose mean
  // rate is above it), not by its mean rate over the run; 50 switches or fewer never are.
  double max_switch_rate = 1e4;
  // Asked about every 0.1 s of wall time while the run goes on (and while its regime is
  // judged: a long string's crossings take seconds); true stops it with
  // Interrupted (a Ctrl-C from Python, a cancel button in a program that embeds pydrill).
  // Empty: never asked.
  std::function<bool()> interrupt;
  // `dof`: the string's, Params::dof() (>= 2; what `state` is sized for).
  void validate(int dof) const;
};

enum class SwitchKind { Stick, Slip, Reversal, BandEnter, BandLeave };
// "stick", "slip", "reversal", "band-enter", "band-leave"; "?" outside the enum.
PYDRILL_API const char* switch_kind_name(SwitchKind k) noexcept;

struct Switch {
  double t = 0;                          // s
  SwitchKind kind = SwitchKind::Stick;
  int direction = 0;                     // bit direction after the switch: +1, −1, 0 (stuck)
  double reaction = 0;                   // T_e at the switch, N·m
  double root_residual = 0;              // value of the triggering root function at t (≈ 0)
};

// Counts over the whole run, summed over its smooth pieces (the integrator restarts at each
// switch). Those of the Newton iteration and its linear solves are BDF's (0 for the others);
// Adams iterates to a fixed point (nonlin_iters, no Jacobian); DOP853 and ERK are explicit.
struct SolverStats {
  Method method = Method::Auto;  // what actually ran: DOP853, BDF, Adams or ERK (never Auto)
  std::string method_reason;     // why Method::Auto chose it ("requested" when not Auto)
  double stiffness_ratio = 0;  // stiffness_ratio(params), the estimate "auto" decides from
  long steps = 0;              // internal steps taken (what max_steps bounds)
  long rhs_evals = 0;          // right-hand side evaluations
  long jac_evals = 0;          // BDF: Newton matrices I − γJ formed and factored, one per new γ
                               // (the bit's row, which the state and mode change, is refreshed
                               // at every solve without a new factorisation)
  long lin_setups = 0;         // BDF: setups of the chain solver, the times it refactored
                               // I − γJ (at a solve that found γ moved, or after a failed
                               // factorisation): what jac_evals counts, as forming the matrix
                               // and factoring it are one operation here
  long lin_solves = 0;         // BDF: linear solves with the chain solver
  long nonlin_iters = 0, nonlin_conv_fails = 0;  // BDF's Newton or Adams's fixed-point iterations
                                                 // and their convergence failures
  long err_test_fails = 0;     // steps rejected by the error test
  long root_evals = 0;         // evaluations of the switch (root) functions
  long reinits = 0;            // integrator restarts (one per mode change)
  long switches = 0;           // switches.size()
  double wall_time = 0;        // s spent in the core
};

// The regime judged on the window [window_start, window_end] (the last window_fraction of
// the run): velocities, severity, fractions, period and stick_events describe that window.
struct Summary {
  Regime regime = Regime::Steady;  // regime_name(regime) for its name; see `note` for doubts
  double window_start = 0, window_end = 0;        // s
  double bit_min = 0, bit_max = 0, bit_mean = 0;  // bit velocity ω_b, rad/s
  double top_min = 0, top_max = 0, top_mean = 0;  // top-drive velocity ω_0, rad/s
  double severity = 0;         // (max ω_b − min ω_b) / (2 mean ω_b)
  double bit_top_ratio = 0;    // max ω_b / mean ω_top (min ω_b / mean ω_top when mean ω_top < 0:
                               // the bit's fastest turn in the top drive's direction, which
                               // is u's but for a window where the string swings back); 0
                               // when mean ω_top or that turn is 0
  double stuck_fraction = 0;   // fraction of the window spent in stick
  double period = -1;          // s; < 0 when there is none
  long stick_events = 0;       // slip→stick transitions in the window
  double static_torque = 0;    // T_s = μ_sb W_ob R_b, N·m
  std::vector<double> omega_equilibrium;  // rad/s, every steady Ω for (W_ob, u): > 0, or < 0 when u < 0
  std::string note;            // caveat about the judgement, empty when there is none
  // The note's kind, for tables (a sweep's atlas keeps this, not the text): "first-wind-up",
  // "one-stick-phase", "one-break-away", "late-stick", "growing" (an oscillation still growing
  // away from its steady state, or a swing dying out about one that is linearly unstable:
  // judged an oscillation), "short-window", "run-away"
  // (c_r + c_b = 0 and |u| > T_c: no steady state holds the bit, which speeds up without
  // bound; judged an oscillation), "approaching" (judged steady, its mean bit velocity still
  // moving by over 1 % across the window, or towards a steady state over 1 % away); empty
  // without a note.
  std::string caveat;
};

struct Result {
  int dof = 0;
  double wob = 0, torque = 0;   // the run's W_ob (N) and u (N·m)
  std::vector<double> t;        // output times, s: options.t_out, or n_out uniform in [0, t_end]
  std::vector<double> states;   // row-major (t.size(), 2·dof−1), twist coordinates (model.hpp)
  std::vector<double> top_angle;  // φ_0 at the output times, rad (φ_0(0) = 0)
  // Energy ledger at the output times (J). The three integrals count from t = 0 (zero
  // there); the stored energy E is not zero at a start in motion (Initial::Equilibrium
  // or a state). The balance to check is W_in − D_visc − D_fric = E(t) − E(0), with
  // E(0) = energy.front() when the outputs start at t = 0 (as the n_out grid does).
  std::vector<double> work_input;        // W_in = ∫ u ω_0 dt
  std::vector<double> viscous_loss;      // D_visc = ∫ viscous dissipation dt
  std::vector<double> friction_loss;     // D_fric = ∫ T_f ω_b dt
  std::vector<double> energy;            // E = kinetic + elastic at the output times
  std::vector<int> modes;                // static_cast<int>(Mode) (model.hpp) at each output time
  std::vector<Switch> switches;
  SolverStats stats;
  Summary summary;
};

// A solver failure: the integrator's message (CVODES's or ARKODE's own text, or DOP853's
// or the run's: step size too small, max_steps reached, chattering) and the time reached.
class PYDRILL_API SolverError : public std::runtime_error {
 public:
  SolverError(const std::string& what, double t_reached)
      : std::runtime_error(what), t_reached_(t_reached) {}
  double t_reached() const { return t_reached_; }

 private:
  double t_reached_;
};

// A run stopped because options.interrupt said so; t_reached is where. A Cancelled, as a
// stopped stability computation is.
class PYDRILL_API Interrupted : public Cancelled {
 public:
  explicit Interrupted(double t_reached) : t_reached_(t_reached) {}
  double t_reached() const { return t_reached_; }

 private:
  double t_reached_;
};

// Stiffness estimate behind Method::Auto, from Gershgorin bounds and a
// Rayleigh estimate of the fundamental (the string clamped at a still bit).
// These three throw std::invalid_argument for invalid Params.
struct StiffnessEstimate {
  double fastest_decay = 0;      // 1/s, bound on the largest decay rate (M⁻¹C)
  double fastest_frequency = 0;  // rad/s, bound on the highest natural frequency (M⁻¹K)
  double fundamental = 0;        // rad/s, lowest natural frequency
};
PYDRILL_API StiffnessEstimate estimate_stiffness(const Params& params);
// fastest_decay / fundamental: how much faster the fastest mode dies than the
// slowest one moves.
PYDRILL_API double stiffness_ratio(const Params& params);
// What Method::Auto runs: DOP853, or BDF for a stiff string; `reason` (if given) says why.
PYDRILL_API Method choose_method(const Params& params, std::string* reason = nullptr);

// Runs one simulation at weight on bit `wob` (N, finite, 0 < wob <= 1e15) and surface torque
// `torque` (N·m, finite, |torque| <= 1e15: beyond, the bit's speeds overflow a double) from
// t = 0 to options.t_end. Throws std::invalid_argument on bad input (nothing is
// computed), SolverError if the integrator fails, Interrupted if options.interrupt
// says so, and whatever options.interrupt itself throws; std::bad_alloc if memory runs out.
// Thread-safe: it keeps no state between calls that a result depends on (each thread caches
// the Hopf crossings of the last few strings it judged, which depend on the string alone), so
// any number of threads may simulate at once, sharing `params` and `options` if they like
// (they are only read). While it runs, its thread
// flushes subnormal numbers to zero (they cost ~100x at a string's wave front); the caller's
// setting is back on when it returns or throws, and while options.interrupt is asked (on the
// calling thread).
PYDRILL_API Result simulate(const Params& params, double wob, double torque,
                            const SimulationOptions& options);

}  // namespace pydrill
