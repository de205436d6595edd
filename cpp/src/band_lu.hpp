// LU factorisation of a band matrix with partial pivoting, in O(n kl (kl + ku)).
//
// The chain's Jacobian in interleaved coordinates (ω_0, φ_0, ω_1, …) couples each state to
// its two neighbours on either side: a band of kl = ku = 2. A dense LU of a 500-pipe string
// (n' = 1005) costs seconds; this one costs a fraction of a millisecond. The algorithm is
// LAPACK's unblocked gbtf2/gbtrs: row interchanges widen the upper band to kl + ku, and they
// are applied to the right-hand side step by step, as they were made.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>  // std::abs of the complex matrices it factors too
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace pydrill {

template <typename T>
class BandLU {
 public:
  // The n×n zero matrix with kl sub- and ku super-diagonals; fill it with at(), then factor().
  BandLU(int n, int kl, int ku)
      : n_(n), kl_(kl), ku_(ku), ld_(2 * kl + ku + 1), ab_(z(ld_) * z(n), T(0)), piv_(z(n)) {}

  int size() const { return n_; }

  // Entry (r, c), for c − ku ≤ r ≤ c + kl before factor(); the fill-in rows above hold U's
  // widened band afterwards.
  T& at(int r, int c) { return ab_[index(r, c)]; }
  const T& at(int r, int c) const { return ab_[index(r, c)]; }

  // Factorises in place; throws std::runtime_error when a pivot is exactly zero (singular).
  void factor() {
    const int up = kl_ + ku_;  // U's upper bandwidth after interchanges
    for (int j = 0; j < n_; ++j) {
      const int below = std::min(kl_, n_ - 1 - j);
      int p = 0;
      for (int i = 1; i <= below; ++i) {
        if (std::abs(at(j + i, j)) > std::abs(at(j + p, j))) p = i;
      }
      piv_[z(j)] = j + p;
      if (at(j + p, j) == T(0)) throw std::runtime_error("band LU: the matrix is singular");
      const int last = std::min(n_ - 1, j + up);
      if (p != 0) {
        for (int c = j; c <= last; ++c) std::swap(at(j, c), at(j + p, c));
      }
      const T pivot = at(j, j);
      for (int i = 1; i <= below; ++i) {
        const T l = at(j + i, j) / pivot;
        at(j + i, j) = l;
        for (int c = j + 1; c <= last; ++c) at(j + i, c) -= l * at(j, c);
      }
    }
  }

  // Solves A x = b in place (after factor()).
  void solve(std::vector<T>& b) const {
    if (static_cast<int>(b.size()) != n_) throw std::invalid_argument("band LU: right-hand side of the wrong size");
    const int up = kl_ + ku_;
    for (int j = 0; j < n_; ++j) {  // L⁻¹ P b, one interchange and one column at a time
      const int p = piv_[z(j)];
      if (p != j) std::swap(b[z(j)], b[z(p)]);
      const int below = std::min(kl_, n_ - 1 - j);
      for (int i = 1; i <= below; ++i) b[z(j + i)] -= at(j + i, j) * b[z(j)];
    }
    for (int j = n_ - 1; j >= 0; --j) {  // U⁻¹, column by column
      b[z(j)] /= at(j, j);
      const T x = b[z(j)];
      for (int i = std::max(0, j - up); i < j; ++i) b[z(i)] -= at(i, j) * x;
    }
  }

 private:
  static std::size_t z(int i) { return static_cast<std::size_t>(i); }

  // LAPACK's layout: column c holds rows c − (kl + ku) … c + kl, column-major.
  std::size_t index(int r, int c) const {
    return z(c) * z(ld_) + z(kl_ + ku_ + r - c);
  }

  int n_, kl_, ku_, ld_;
  std::vector<T> ab_;
  std::vector<int> piv_;
};

}  // namespace pydrill
