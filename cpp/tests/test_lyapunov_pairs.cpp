// first_lyapunov_coefficient and the pair (δ, ω) it is given: a Hopf point's, or refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <vector>

#include "pydrill/stability.hpp"

using namespace pydrill;

namespace {

// The distance from iω to the nearest eigenvalue at δ, by the dense eigensolver: nothing the
// check in first_lyapunov_coefficient shares (it takes a Newton step on the bit impedance).
double distance_to_spectrum(const Params& p, double delta, double w) {
  double d = std::numeric_limits<double>::infinity();
  for (const std::complex<double>& l : eigenvalues(p, delta)) {
    d = std::min(d, std::abs(l - std::complex<double>(0.0, w)));
  }
  return d;
}

}  // namespace

TEST_CASE("first_lyapunov_coefficient refuses a pair that is no Hopf point", "[stability][lyapunov]") {
  // Before, any (δ, ω) had a coefficient: δ = 0.01, ω = 1 on this string gave 0.036
  // ("subcritical"), though its nearest eigenvalue at δ = 0.01 lies 0.27 rad/s from i.
  for (const int dof : {2, 4, 12}) {
    const Params p = preset("reduced-scale", dof);
    std::vector<double> deltas{0.01, 0.05, 0.5, 3.0}, freqs{0.3, 1.0, 2.0, 5.0, 40.0};
    for (const Crossing& c : critical_deltas(p)) {
      if (c.type != CrossingType::Hopf) continue;
      // Every crossing passes, and the same δ with ω 5 % off, or ω with δ elsewhere, are tried.
      CHECK(std::isfinite(first_lyapunov_coefficient(p, c.delta, c.frequency)));
      deltas.push_back(c.delta);
      freqs.push_back(c.frequency * 1.05);
      freqs.push_back(c.frequency);
    }
    int refused = 0, passed = 0;
    for (const double delta : deltas) {
      for (const double w : freqs) {
        const double d = distance_to_spectrum(p, delta, w);
        INFO("dof " << dof << ": delta " << delta << ", frequency " << w << ", nearest eigenvalue "
                    << d << " rad/s away");
        if (d > 0.05 * w) {  // clearly none: refused, naming both and what is allowed
          CHECK_THROWS_WITH(first_lyapunov_coefficient(p, delta, w),
                            Catch::Contains("are not a Hopf point of this string") &&
                                Catch::Contains("frequency = ") &&
                                Catch::Contains("allowed within 1 % of frequency"));
          ++refused;
        } else if (d < 1e-6 * w) {  // a Hopf point (δ one of a crossing's): a coefficient
          CHECK(std::isfinite(first_lyapunov_coefficient(p, delta, w)));
          ++passed;
        }
      }
    }
    CHECK(refused > 10);  // (both kinds met on every string)
    CHECK(passed > 1);
  }
}

TEST_CASE("a Hopf pair typed to six digits still has its coefficient", "[stability][lyapunov]") {
  // What a reader copies from a table: the coefficient is the crossing's, to about as many
  // digits as the pair has.
  const Params p = preset("reduced-scale", 20);
  int checked = 0;
  for (const Crossing& c : critical_deltas(p)) {
    if (c.type != CrossingType::Hopf) continue;
    const auto six = [](double x) {
      const double scale = std::pow(10.0, std::floor(std::log10(x)) - 5);
      return std::round(x / scale) * scale;
    };
    const double exact = first_lyapunov_coefficient(p, c.delta, c.frequency);
    const double typed = first_lyapunov_coefficient(p, six(c.delta), six(c.frequency));
    CHECK(typed == Approx(exact).epsilon(1e-2));
    ++checked;
  }
  CHECK(checked > 10);
}
