// Dormand–Prince 8(5,3) explicit Runge–Kutta (Hairer & Wanner's DOP853) with
// its 7th-order dense output and our own event location.
//
// Why not ARKODE: on this problem the integrator's own bookkeeping, not the
// right-hand side, is the cost. A dof-4 right-hand side takes ~10 ns, while an
// ARKODE step spends microseconds in generic N_Vector calls; and its 7(8)
// Fehlberg pair needs about twice the steps of DOP853, whose error estimate
// combines the 5th- and 3rd-order embeddings. Here every stage is a tight loop
// over contiguous memory, the dense output (three extra stages) is formed only
// for a step that holds an output time or a sign change, and each root is
// refined by the Illinois method on that interpolant. A function that crosses zero
// and comes back within one step is caught from its rates at both ends.
//
// Step-size control, initial step and error norm follow scipy's DOP853 (the
// benchmark baseline), so both take the same steps for the same tolerances.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#define PYDRILL_DOP853_VARIANT generic
#include "dop853_kernels.hpp"
#include "integrator.hpp"

namespace pydrill::detail {
namespace {

namespace c = dop853;

constexpr double kSafety = 0.9, kMinFactor = 0.2, kMaxFactor = 10.0;
constexpr double kErrorExponent = -1.0 / 8.0;
constexpr double kTiny = std::numeric_limits<double>::min();

// AVX2+FMA doubles the width of every stage sum; the plain build runs anywhere.
const c::Kernels& select_kernels() {
#if defined(PYDRILL_DOP853_AVX2)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return c::kernels_avx2();
#endif
  return c::kernels_generic();
}

class Dop853 final : public Integrator {
 public:
  Dop853(RunData& data, const std::vector<double>& y0, const SimulationOptions& opt)
      : data_(data), opt_(opt), n_(data.chain->size()), m_(n_ + kQuads) {
    const auto m = static_cast<std::size_t>(m_);
    y_.assign(m, 0.0);
    yold_.assign(m, 0.0);
    ynew_.assign(m, 0.0);
    tmp_.assign(m, 0.0);
    k_.assign(m * c::kStagesExtended, 0.0);
    dense_.assign(m * c::kInterpolatorPower, 0.0);
    std::copy(y0.begin(), y0.end(), y_.begin());  // quadratures start at 0
    restart(0.0);
    h_ = initial_step(opt.t_end);
  }

  Status step(double t_end, double& t) override {
    // Row 0 must hold f(t_, y_): the last step's final stage (FSAL), or afresh.
    if (f0_ == F0::FromLastStage) std::copy_n(row(12), m_, row(0));
    if (f0_ == F0::Stale) rhs(t_, y_.data(), row(0));
    f0_ = F0::Current;
    yold_ = y_;
    told_ = t_;
    const double max_step = opt_.max_step > 0 ? opt_.max_step : std::numeric_limits<double>::infinity();
    double h_abs = std::min(h_, max_step);
    bool rejected = false;
    for (;;) {
      // Ten ulps of t (scipy's floor), but never below 1e-14 s: near t = 0 the ulp is
      // subnormal, and flushed to zero while a simulation runs, so a right-hand side gone
      // infinite would shrink the step for ever. The floor is absolute, not a fraction of
      // the span: a long run (t_end = 1e10 s) needs steps as short as a short one. A last
      // step cut short by t_end may be shorter still (t_end = 1e-20 s is a valid run).
      const double min_step = std::max(10.0 * std::fabs(std::nextafter(t_, INFINITY) - t_), 1e-14);
      if (!std::isfinite(h_abs) || (h_abs < min_step && h_abs < t_end - t_)) {
        std::ostringstream o;
        o << "DOP853 step size fell to " << h_abs << " s at t = " << t_
          << " s (below the floating-point resolution): the solution is not smooth or not "
             "finite here";
        t = t_;
        throw SolverError(o.str(), t_);
      }
      double tnew = t_ + h_abs;
      if (tnew > t_end) tnew = t_end;
      const double h = tnew - t_;
      const double err = attempt(h);
      if (err < 1.0) {
        double factor = err == 0.0 ? kMaxFactor : std::min(kMaxFactor, kSafety * std::pow(err, kErrorExponent));
        if (rejected) factor = std::min(1.0, factor);
        h_ = h * factor;
        hlast_ = h;
        t_ = tnew;
        break;
      }
      ++err_fails_;
      rejected = true;
      h_abs = h * std::max(kMinFactor, std::isfinite(err) ? kSafety * std::pow(err, kErrorExponent) : 0.0);
    }
    ++steps_;
    y_.swap(ynew_);
    dense_ready_ = false;
    // f at the new point is stage 12; row 0 keeps f(t_old) for the dense output
    // until the next step starts.
    f0_ = F0::FromLastStage;

    double g[kRoots];
    root_functions(data_, y_.data(), g);
    ++root_evals_;
    bool any = false;
    for (int i = 0; i < kRoots; ++i) {
      if (!active_[i]) {
        // A function that sat on zero at the restart joins once it leaves zero.
        if (g[i] != 0.0) active_[i] = true;
        continue;
      }
      if (crosses(gold_[i], g[i], dir_[i])) any = true;
    }
    if (any) {
      t = locate_root(g, t_);
      return Status::Root;
    }
    double tin, gin[kRoots];
    if (hidden_crossing(g, tin, gin)) {
      t = locate_root(gin, tin);
      return Status::Root;
    }
    std::copy_n(g, kRoots, gold_);
    t = t_;
    return t_ >= t_end ? Status::Stop : Status::Step;
  }

  double* state() override { return y_.data(); }
  double* quadratures() override { return y_.data() + n_; }

  void interpolate(double t, double* y, double* q) override {
    evaluate_dense(t, tmp_.data());
    std::copy_n(tmp_.data(), n_, y);
    std::copy_n(tmp_.data() + n_, kQuads, q);
  }

  void roots_found(int found[kRoots]) override { std::copy_n(found_, kRoots, found); }

  void restart(double t) override {
    // The mode (and so the right-hand side) changed, or the state was edited:
    // f is evaluated afresh (by the starting-step estimate). A one-step method needs no
    // ramp-up, but the step carried over from the old mode is not trusted beyond Hairer's
    // starting step for the new one: a bit held for seconds had long steps, and such a step
    // at its break-away let the Stribeck instability run away inside it, to a state the error
    // test accepted because it scales the error by the new state itself (the paper's dof-4
    // stick-slip at rtol 1e-3: bit velocity 3.6e10 rad/s; dof 10 at 1e-4: 1e11). The estimate
    // costs one evaluation of f per switch.
    t_ = t;
    f0_ = F0::Stale;
    dense_ready_ = false;
    if (t_ < opt_.t_end) h_ = std::min(h_, initial_step(opt_.t_end));
    root_directions(data_, dir_);
    root_functions(data_, y_.data(), gold_);
    ++root_evals_;
    for (int i = 0; i < kRoots; ++i) {
      // A function that starts on zero (ω_b = 0 on entering slip) is armed
      // with the sign its direction waits to leave: if the bit at once moves
      // the wrong way, that is a root right here, not a motion to follow.
      // Without a direction it waits until it leaves zero.
      active_[i] = gold_[i] != 0.0 || dir_[i] != 0;
      if (gold_[i] == 0.0 && dir_[i] != 0) gold_[i] = dir_[i] < 0 ? kTiny : -kTiny;
    }
    std::fill_n(found_, kRoots, 0);
    base_steps_ = steps_;
  }

  void collect(SolverStats& s) override {
    s.method = Method::DOP853;
    s.steps += steps_ - reported_.steps;
    s.rhs_evals += rhs_evals_ - reported_.rhs;
    s.err_test_fails += err_fails_ - reported_.fails;
    s.root_evals += root_evals_ - reported_.roots;
    reported_ = {steps_, rhs_evals_, err_fails_, root_evals_};
  }

  long steps_since_restart() override { return steps_ - base_steps_; }

 private:
  double* row(int s) { return k_.data() + static_cast<std::size_t>(s) * m_; }

  void rhs(double t, const double* y, double* f) {
    (void)t;  // autonomous within a mode
    rhs_with_quadratures(data_, y, f);
    ++rhs_evals_;
  }

  static void rhs_callback(void* ctx, double t, const double* y, double* f) {
    static_cast<Dop853*>(ctx)->rhs(t, y, f);
  }

  // One trial step of size h from (t_, y_): the new state in ynew_, f there in
  // row 12, and the error norm (< 1 accepts).
  double attempt(double h) {
    double s5 = 0.0, s3 = 0.0;
    kernels_.trial_step(y_.data(), k_.data(), m_, t_, h, tmp_.data(), ynew_.data(), opt_.rtol,
                        opt_.atol, rhs_callback, this, &s5, &s3);
    if (s5 == 0.0 && s3 == 0.0) return 0.0;
    return std::fabs(h) * s5 / std::sqrt((s5 + 0.01 * s3) * m_);
  }

  // Hairer's starting step (as scipy's select_initial_step, order 7), judged on the state
  // alone: the quadratures start at 0 with a slope, and from a steady start their weight
  // 1/atol gave a first step below the floor (atol 1e-18: "step size fell" at t = 0).
  double initial_step(double t_end) {
    const double span = t_end - t_;
    if (span <= 0) return 0.0;
    rhs(t_, y_.data(), row(0));
    f0_ = F0::Current;
    const double* f0 = row(0);
    double d0 = 0, d1 = 0;
    for (int i = 0; i < n_; ++i) {
      const double sc = opt_.atol + std::fabs(y_[i]) * opt_.rtol;
      d0 += (y_[i] / sc) * (y_[i] / sc);
      d1 += (f0[i] / sc) * (f0[i] / sc);
    }
    d0 = std::sqrt(d0 / n_);
    d1 = std::sqrt(d1 / n_);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, span);
    for (int i = 0; i < m_; ++i) tmp_[i] = y_[i] + h0 * f0[i];
    rhs(t_ + h0, tmp_.data(), row(1));
    double d2 = 0;
    for (int i = 0; i < n_; ++i) {
      const double sc = opt_.atol + std::fabs(y_[i]) * opt_.rtol;
      const double v = (row(1)[i] - f0[i]) / sc;
      d2 += v * v;
    }
    d2 = std::sqrt(d2 / n_) / h0;
    const double h1 = (d1 <= 1e-15 && d2 <= 1e-15) ? std::max(1e-6, h0 * 1e-3)
                                                    : std::pow(0.01 / std::max(d1, d2), 1.0 / 8.0);
    double h = std::min({100 * h0, h1, span});
    if (opt_.max_step > 0) h = std::min(h, opt_.max_step);
    return h;
  }

  // The three extra stages and the coefficients of the 7th-order interpolant
  // of the last step [told_, told_ + hlast_] (y_ still the step's end state).
  void prepare_dense() {
    if (dense_ready_) return;
    kernels_.prepare_dense(yold_.data(), y_.data(), k_.data(), m_, told_, hlast_, tmp_.data(),
                           dense_.data(), rhs_callback, this);
    dense_ready_ = true;
  }

  void evaluate_dense(double t, double* out) {
    prepare_dense();
    kernels_.evaluate_dense(yold_.data(), dense_.data(), m_, (t - told_) / hlast_, out);
  }

  // A function with the same sign at both ends of the step that crossed zero and came back
  // inside it (events.hpp, hidden_turn): the rates are free, f at both ends is at hand. On a
  // crossing: the time inside the step where the dense output shows it, and the functions.
  bool hidden_crossing(const double* gnew, double& tin, double* gin) {
    double r0[kRoots], r1[kRoots];
    root_rates(data_, row(0), r0);
    root_rates(data_, row(12), r1);
    for (int i = 0; i < kRoots; ++i) {
      if (!active_[i]) continue;
      const double tt = hidden_turn(told_, t_, gold_[i], gnew[i], r0[i], r1[i], dir_[i]);
      if (std::isnan(tt)) continue;
      evaluate_dense(tt, tmp_.data());
      root_functions(data_, tmp_.data(), gin);
      ++root_evals_;
      for (int j = 0; j < kRoots; ++j) {
        if (active_[j] && crosses(gold_[j], gin[j], dir_[j])) {
          tin = tt;
          return true;
        }
      }
    }
    return false;
  }

  // The root between the last point and `tend` (the step's end, or a point inside it where a
  // function has crossed), located on the dense output; the state there becomes y_.
  double locate_root(const double* gnew, double tend) {
    RootBracket b{told_, tend, {}, {}};
    std::copy_n(gold_, kRoots, b.glo);
    std::copy_n(gnew, kRoots, b.ghi);
    auto at = [this](double t, double* y) { evaluate_dense(t, y); };
    const double thi = detail::locate_root(data_, dir_, active_, at, tmp_.data(), b, found_, root_evals_);
    evaluate_dense(thi, tmp_.data());
    y_.swap(tmp_);  // y_ no longer the step's end: the dense output is already formed
    t_ = thi;
    f0_ = F0::Stale;
    return thi;
  }

  RunData& data_;
  const SimulationOptions& opt_;
  const c::Kernels& kernels_ = select_kernels();
  int n_, m_;
  std::vector<double> y_, yold_, ynew_, tmp_, k_, dense_;
  double t_ = 0, told_ = 0, h_ = 0, hlast_ = 0;
  enum class F0 { Current, FromLastStage, Stale } f0_ = F0::Stale;
  bool dense_ready_ = false;
  double gold_[kRoots] = {0, 0, 0, 0};
  int dir_[kRoots] = {0, 0, 0, 0};
  bool active_[kRoots] = {true, true, true, true};
  int found_[kRoots] = {0, 0, 0, 0};
  long steps_ = 0, rhs_evals_ = 0, err_fails_ = 0, root_evals_ = 0;
  long base_steps_ = 0;
  struct {
    long steps = 0, rhs = 0, fails = 0, roots = 0;
  } reported_;
};

}  // namespace

namespace dop853 {
const Kernels& kernels_generic() {
  static const Kernels k{generic::trial_step, generic::prepare_dense, generic::evaluate_dense};
  return k;
}
}  // namespace dop853

std::unique_ptr<Integrator> make_dop853(RunData& data, const std::vector<double>& y0,
                                        const SimulationOptions& opt) {
  return std::make_unique<Dop853>(data, y0, opt);
}

}  // namespace pydrill::detail
