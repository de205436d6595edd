// pydrill from C++: simulate a laboratory string, judge its regime, and analyse the stability
// of its steady states.
//
//   pydrill_example [wob N] [torque N·m] [dof] [seconds of wall time allowed]
//   pydrill_example --help
//
// Each argument a plain decimal number (100, 8.3, -5, 1e2; not 0x10, inf or nan), named in
// messages as the library names it (wob, torque, dof). Without arguments: the paper's Fig. 4
// case, a 4-DOF string at wob = 100 N and torque = 8.3 N·m, which sticks and slips. Exit
// status 0, 2 for bad input (a string too large for this machine's memory included, as the
// pydrill command says), 3 when the integrator fails, 4 when the time allowed runs out.
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include <pydrill/simulator.hpp>
#include <pydrill/stability.hpp>
#include <pydrill/version.hpp>

namespace {

// A command-line number: a plain decimal one, all of it ("8.3", "-5", "1e2"). std::stod alone
// took "8.3x" for 8.3, and also read hexadecimal ("0x10" as 16), "inf", "nan" and leading
// blanks; a value beyond a double ("1e999") said "not a number". One too small for a double
// ("1e-400") is refused too: it rounded to 0, and the library then refused "wob = 0", a value
// nobody typed. A literal zero ("0", "0.0e5") stays 0.
double number(const char* text, const char* what) {
  const std::string s(text);
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t from = i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
    return i - from;
  };
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  const std::size_t start = i;
  std::size_t mantissa = digits();
  if (i < s.size() && s[i] == '.') {
    ++i;
    mantissa += digits();
  }
  const bool nonzero = s.find_first_not_of("0.", start) < i;  // a mantissa digit other than 0
  bool plain = mantissa > 0;
  if (plain && i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    plain = digits() > 0;
  }
  if (!plain || i != s.size()) {
    throw std::invalid_argument(std::string(what) + " = '" + s +
                                "' is not allowed: must be a decimal number such as 100, 8.3 or 1e2");
  }
  errno = 0;
  const double value = std::strtod(text, nullptr);
  if (errno == ERANGE && std::isinf(value)) {
    throw std::invalid_argument(std::string(what) + " = '" + s +
                                "' is out of range: must be a decimal number of size below 1.8e308");
  }
  if (value == 0.0 && nonzero) {
    throw std::invalid_argument(std::string(what) + " = '" + s +
                                "' is out of range: too small for a double, it would be read as 0 "
                                "(the smallest is 4.9e-324)");
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf(
        "usage: pydrill_example [wob N] [torque N·m] [dof] [seconds of wall time allowed]\n"
        "Simulates the reduced-scale string from rest for 300 s, judges its regime and the\n"
        "stability of its steady states. Defaults: wob 100, torque 8.3, dof 4, 60 s allowed.\n"
        "Exit status 0; 2 for bad input; 3 when the integrator fails; 4 out of time.\n");
    return 0;
  }
  try {
    const double wob = argc > 1 ? number(argv[1], "wob") : 100.0;         // N
    const double torque = argc > 2 ? number(argv[2], "torque") : 8.3;     // N·m
    const double dof_given = argc > 3 ? number(argv[3], "dof") : 4.0;
    if (!std::isfinite(dof_given) || dof_given != std::floor(dof_given)) {
      throw std::invalid_argument("dof = '" + std::string(argv[3]) + "' is not a whole number");
    }
    // Converting a double beyond int's range to int is undefined: refuse it first.
    if (std::fabs(dof_given) > 1e9) {
      throw std::invalid_argument("dof = '" + std::string(argv[3]) + "' is out of range");
    }
    const int dof = static_cast<int>(dof_given);  // preset() checks its range
    const double allowed = argc > 4 ? number(argv[4], "time allowed") : 60.0;  // s of wall time
    if (!(allowed > 0) || !std::isfinite(allowed)) {  // nan or inf would never stop the run
      throw std::invalid_argument("time allowed = '" + std::string(argv[4]) +
                                  "' is not allowed: must be a finite number of seconds > 0");
    }

    // Every call checks its input and throws std::invalid_argument naming what is wrong.
    const pydrill::Params params = pydrill::preset("reduced-scale", dof);
    pydrill::SimulationOptions options;
    options.t_end = 300.0;  // s of simulated time
    options.initial = pydrill::Initial::Rest;
    // Asked every 0.1 s of wall time: a program's cancel button, here a deadline.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(allowed);
    options.interrupt = [deadline] { return std::chrono::steady_clock::now() > deadline; };
    std::printf("pydrill %s: reduced-scale string, dof %d: wob %g N, torque %g N·m, from rest for %g s\n",
                pydrill::version(), dof, wob, torque, options.t_end);

    const pydrill::Result r = pydrill::simulate(params, wob, torque, options);
    const pydrill::Summary& s = r.summary;
    std::printf("regime: %s (judged on t = %g ... %g s)\n", pydrill::regime_name(s.regime),
                s.window_start, s.window_end);
    if (!s.note.empty()) std::printf("  note: %s\n", s.note.c_str());
    std::printf("in that window: bit velocity min %.4f  max %.4f  mean %.4f rad/s\n", s.bit_min,
                s.bit_max, s.bit_mean);
    if (s.regime == pydrill::Regime::StickSlip) {
      std::printf("in that window: period %.4f s, %ld stick events, stuck %.1f %% of the time\n",
                  s.period, s.stick_events, 100.0 * s.stuck_fraction);
    }
    std::printf("whole run: solver %s, %ld steps, %ld switches, %.3f ms\n",
                pydrill::method_name(r.stats.method), r.stats.steps, r.stats.switches,
                1e3 * r.stats.wall_time);

    // The steady states at the same (wob, torque) and their stability. The crossings depend on
    // the string alone: a program that visits many operating points finds them once.
    const std::vector<pydrill::Crossing> crossings = pydrill::critical_deltas(params, options.interrupt);
    for (const pydrill::Crossing& c : crossings) {
      if (c.type == pydrill::CrossingType::Hopf && c.direction > 0) {
        std::printf("first Hopf crossing at delta = %.5f N m s/rad (%.3f rad/s)\n", c.delta,
                    c.frequency);
        break;
      }
    }
    const std::vector<pydrill::StabilityPoint> points =
        pydrill::stability_at_torque(params, crossings, wob, torque, options.interrupt);
    if (points.empty()) std::printf("no steady state at this (wob, torque)\n");
    for (const pydrill::StabilityPoint& p : points) {
      std::printf("steady state at Omega = %.4f rad/s: %s (%d eigenvalues in the right half-plane)\n",
                  p.omega, p.stable ? "stable" : "unstable", p.unstable);
    }
    return 0;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "bad input: %s\n", e.what());
    return 2;
  } catch (const pydrill::SolverError& e) {
    std::fprintf(stderr, "the integrator failed at t = %g s: %s\n", e.t_reached(), e.what());
    return 3;
  } catch (const pydrill::Interrupted& e) {
    std::fprintf(stderr, "out of time at t = %g s of simulated time\n", e.t_reached());
    return 4;
  } catch (const pydrill::Cancelled&) {  // any other stopped computation: the stability's
    std::fprintf(stderr, "out of time in the stability analysis\n");
    return 4;
  } catch (const std::bad_alloc&) {
    // simulate keeps 2·dof − 1 doubles per output time (3001 of them here): a string of
    // 100000 inertias needs 4.8 GB, and without this the program ended in std::terminate.
    std::fprintf(stderr, "bad input: out of memory: ask for a smaller string (dof)\n");
    return 2;
  }
}
