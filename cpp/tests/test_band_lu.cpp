#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

#include "band_lu.hpp"

using pydrill::BandLU;
using cplx = std::complex<double>;

namespace {

std::size_t z(int i) { return static_cast<std::size_t>(i); }

// A random band matrix, kept densely too for the residual; with zero_diagonal, every
// other diagonal entry is 0, so that the factorisation must interchange rows.
struct Case {
  int n, kl, ku;
  std::vector<cplx> dense;  // row-major
  BandLU<cplx> lu;
};

Case random_band(int n, int kl, int ku, bool zero_diagonal, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c{n, kl, ku, std::vector<cplx>(z(n) * z(n)), BandLU<cplx>(n, kl, ku)};
  for (int r = 0; r < n; ++r) {
    for (int col = std::max(0, r - kl); col <= std::min(n - 1, r + ku); ++col) {
      cplx a(u(gen), u(gen));
      if (r == col && zero_diagonal && r % 2 == 0) a = 0.0;
      c.dense[z(r) * n + col] = a;
      c.lu.at(r, col) = a;
    }
  }
  return c;
}

}  // namespace

TEST_CASE("band LU solves band systems to rounding, with and without row interchanges", "[band]") {
  for (bool zero_diagonal : {false, true}) {
    for (auto [kl, ku] : {std::pair{2, 2}, std::pair{1, 3}, std::pair{3, 1}, std::pair{0, 2}}) {
      if (zero_diagonal && kl == 0) continue;  // no row below to swap with: singular
      const int n = 60;
      Case c = random_band(n, kl, ku, zero_diagonal, 7u + static_cast<unsigned>(kl * 10 + ku));
      c.lu.factor();
      std::vector<cplx> x_true(z(n)), b(z(n), 0.0);
      for (int i = 0; i < n; ++i) x_true[z(i)] = cplx(std::sin(i + 1.0), std::cos(3.0 * i));
      for (int r = 0; r < n; ++r) {
        for (int col = 0; col < n; ++col) {
          b[z(r)] += c.dense[z(r) * n + col] * x_true[z(col)];
        }
      }
      std::vector<cplx> x = b;
      c.lu.solve(x);
      // The residual, against the dense matrix, is at rounding level.
      double residual = 0.0, scale = 0.0;
      for (int r = 0; r < n; ++r) {
        cplx s = -b[z(r)];
        for (int col = 0; col < n; ++col) s += c.dense[z(r) * n + col] * x[z(col)];
        residual = std::max(residual, std::abs(s));
        scale = std::max(scale, std::abs(b[z(r)]));
      }
      INFO("kl = " << kl << ", ku = " << ku << ", zero diagonal: " << zero_diagonal);
      CHECK(residual < 1e-12 * scale);
      // And the solution is the one the right-hand side was made from (well conditioned).
      double err = 0.0;
      for (int i = 0; i < n; ++i) err = std::max(err, std::abs(x[z(i)] - x_true[z(i)]));
      CHECK(err < 1e-9);
    }
  }
}

TEST_CASE("band LU refuses a singular matrix and a right-hand side of the wrong size", "[band]") {
  BandLU<double> zero(5, 1, 1);
  CHECK_THROWS_AS(zero.factor(), std::runtime_error);
  BandLU<double> eye(3, 1, 1);
  for (int i = 0; i < 3; ++i) eye.at(i, i) = 1.0;
  eye.factor();
  std::vector<double> wrong(4, 1.0);
  CHECK_THROWS_AS(eye.solve(wrong), std::invalid_argument);
}
