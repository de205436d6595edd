// Asking a caller's `interrupt` (stability.hpp) from inside a long loop, at no measurable cost;
// and Eigen's symmetric tridiagonal eigenvalues, one of those loops.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/Eigenvalues>

#include "pydrill/stability.hpp"

namespace pydrill::detail {

// tick(work) in the loop, with the work done since the last tick in chain elements (an
// impedance evaluation is dof of them, a few ns each): the clock is read once per 16384 of
// them (tens of µs), the callback asked once 0.1 s have passed since the start or since its
// last answer, and a yes throws StabilityInterrupted. Without a callback nothing is counted.
class InterruptPoll {
 public:
  explicit InterruptPoll(const std::function<bool()>& interrupt)
      : ask_(interrupt ? &interrupt : nullptr),
        next_(ask_ ? clock::now() + kEvery : clock::time_point{}) {}

  void tick(long work) {
    if (ask_ != nullptr && (work_ += work) >= kClockEvery) check();
  }

  // Reads the clock at once: before a step that cannot be asked inside (the dense eigensolver).
  // Out of line: inlined into the loops that tick, it kept their own work from being inlined.
#if defined(__GNUC__)
  [[gnu::noinline]]
#endif
  void check() {
    if (ask_ == nullptr) return;
    work_ = 0;
    if (clock::now() < next_) return;
    if ((*ask_)()) throw StabilityInterrupted();
    next_ = clock::now() + kEvery;
  }

 private:
  using clock = std::chrono::steady_clock;
  static constexpr long kClockEvery = 1L << 14;
  static constexpr std::chrono::milliseconds kEvery{100};
  const std::function<bool()>* ask_;
  long work_ = 0;
  clock::time_point next_;
};

// The eigenvalues of the symmetric tridiagonal matrix (diag, sub), ascending: what
// Eigen::SelfAdjointEigenSolver::computeFromTridiagonal(diag, sub, EigenvaluesOnly) gives, bit
// for bit (its loop, with its own QR step), asked on the way. O(n²): 1.5 s at n = 6000, in
// one piece inside Eigen. Unsorted, as Eigen leaves them, if it does not converge.
inline Eigen::VectorXd tridiagonal_eigenvalues(Eigen::VectorXd diag, Eigen::VectorXd sub,
                                               InterruptPoll& poll) {
  using Eigen::Index;
  const Index n = diag.size();
  const Index max_iterations = 30 * n;  // SelfAdjointEigenSolver's m_maxIterations · n
  const double zero = std::numeric_limits<double>::min();
  const double precision_inv = 1.0 / std::numeric_limits<double>::epsilon();
  Index end = n - 1, start = 0, iter = 0;
  while (end > 0) {
    for (Index i = start; i < end; ++i) {
      if (std::fabs(sub[i]) < zero) {
        sub[i] = 0.0;
      } else {
        const double scaled = precision_inv * sub[i];
        if (scaled * scaled <= std::fabs(diag[i]) + std::fabs(diag[i + 1])) sub[i] = 0.0;
      }
    }
    while (end > 0 && sub[end - 1] == 0.0) --end;
    if (end <= 0) break;
    if (++iter > max_iterations) return diag;
    start = end - 1;
    while (start > 0 && sub[start - 1] != 0.0) --start;
    poll.tick(static_cast<long>(end - start + 1));
    Eigen::internal::tridiagonal_qr_step<Eigen::ColMajor>(diag.data(), sub.data(), start, end,
                                                          static_cast<double*>(nullptr), n);
  }
  std::sort(diag.data(), diag.data() + n);
  return diag;
}

}  // namespace pydrill::detail
