#include "pydrill/model.hpp"

#include <algorithm>
#include <cmath>

#include "bit_jacobian.hpp"

namespace pydrill {

namespace detail {

void bit_jacobian_row(const Chain& chain, const double* y, Mode mode, double* row) {
  // Row b of J: ∂(dω_b/dt)/∂(ω_{N−2}, θ_{N−2}, ω_b). The spring above the bit and c_b act in
  // every mode but stick; the slip friction adds its slope.
  const Params& p = chain.params();
  const int N = chain.dof(), b = chain.bit_index();
  const double inv = 1.0 / p.inertias[static_cast<std::size_t>(N - 1)];
  const double k = p.stiffnesses.back(), c = p.dampings.back();
  bool held = false;  // the rock holds the bit: friction cancels T_e, the row is zero
  double slope = 0.0;
  switch (mode) {
    case Mode::SlipPositive: slope = chain.friction().slip_torque_slope(y[b], 1); break;
    case Mode::SlipNegative: slope = chain.friction().slip_torque_slope(y[b], -1); break;
    case Mode::Stick: held = true; break;
    case Mode::Band: held = std::fabs(chain.reaction_torque(y)) <= chain.static_torque(); break;
  }
  row[0] = held ? 0.0 : c * inv;
  row[1] = held ? 0.0 : k * inv;
  row[2] = held ? 0.0 : -(c + p.bit_damping + slope) * inv;
}

}  // namespace detail

const char* mode_name(Mode m) noexcept {
  switch (m) {
    case Mode::SlipPositive: return "slip+";
    case Mode::SlipNegative: return "slip-";
    case Mode::Stick: return "stick";
    case Mode::Band: return "band";
  }
  return "?";
}

Chain::Chain(const Params& params, double wob, double torque)
    : params_(params), friction_(params, wob), dof_(params.dof()), wob_(wob), torque_(torque) {
  params_.validate();
  check_operating_point(wob, torque);
  inv_inertia_.resize(params_.inertias.size());
  for (std::size_t i = 0; i < inv_inertia_.size(); ++i) inv_inertia_[i] = 1.0 / params_.inertias[i];
}

double Chain::reaction_torque(const double* y) const {
  const int b = bit_index();
  const double k = params_.stiffnesses.back(), c = params_.dampings.back();
  return k * y[b - 1] + c * (y[b - 2] - y[b]) - params_.bit_damping * y[b];
}

double Chain::friction_torque(const double* y, Mode mode) const {
  const double wb = y[bit_index()];
  switch (mode) {
    case Mode::SlipPositive: return friction_.slip_torque(wb, +1);
    case Mode::SlipNegative: return friction_.slip_torque(wb, -1);
    case Mode::Stick: return reaction_torque(y);
    case Mode::Band: {
      const double ts = friction_.static_torque();
      return std::clamp(reaction_torque(y), -ts, ts);
    }
  }
  return 0.0;
}

double Chain::top_acceleration(const double* y) const {
  const double s = params_.stiffnesses[0] * y[1] + params_.dampings[0] * (y[0] - y[2]);
  return (torque_ - params_.top_damping * y[0] - s) * inv_inertia_[0];
}

double Chain::bit_acceleration(const double* y, Mode mode) const {
  if (mode == Mode::Stick) return 0.0;  // as in rhs(): the rock holds the bit
  return (reaction_torque(y) - friction_torque(y, mode)) * inv_inertia_[dof_ - 1];
}

double Chain::reaction_rate(const double* y, Mode mode) const {
  // T_e = k θ + c (ω_a − ω_b) − c_b ω_b with a = N − 2, the inertia above the bit.
  const int a = dof_ - 2, b = bit_index();
  const double* k = params_.stiffnesses.data();
  const double* c = params_.dampings.data();
  const double below = k[a] * y[2 * a + 1] + c[a] * (y[2 * a] - y[b]);
  const double above = a == 0 ? torque_ - params_.top_damping * y[0]
                              : k[a - 1] * y[2 * a - 1] + c[a - 1] * (y[2 * a - 2] - y[2 * a]);
  const double wa_dot = (above - below) * inv_inertia_[a];
  const double wb_dot = bit_acceleration(y, mode);
  return k[a] * (y[2 * a] - y[b]) + c[a] * (wa_dot - wb_dot) - params_.bit_damping * wb_dot;
}

void Chain::rhs(const double* y, Mode mode, double* ydot, double* power) const {
  const int N = dof_;
  const double* k = params_.stiffnesses.data();
  const double* c = params_.dampings.data();
  // Spring torques s_i = k_i θ_i + c_i (ω_i − ω_{i+1}) are computed once and
  // used by both neighbours (Newton's third law holds exactly).
  double s_prev = 0.0, viscous = 0.0;
  for (int i = 0; i < N - 1; ++i) {
    const double wi = y[2 * i], wn = y[2 * i + 2];
    const double dw = wi - wn;
    const double s = k[i] * y[2 * i + 1] + c[i] * dw;
    const double external = (i == 0) ? torque_ - params_.top_damping * wi : s_prev;
    ydot[2 * i] = (external - s) * inv_inertia_[i];
    ydot[2 * i + 1] = dw;
    viscous += c[i] * dw * dw;
    s_prev = s;
  }
  const int b = bit_index();
  const double wb = y[b];
  const double te = s_prev - params_.bit_damping * wb;
  // Stick: the rock holds the bit (exact friction: ω_b stays 0; Karnopp:
  // frozen inside the band) and its torque is T_e itself.
  const double tf = mode == Mode::Stick ? te : friction_torque(y, mode);
  ydot[b] = mode == Mode::Stick ? 0.0 : (te - tf) * inv_inertia_[N - 1];
  if (power) {
    power[0] = torque_ * y[0];
    power[1] = viscous + params_.top_damping * y[0] * y[0] + params_.bit_damping * wb * wb;
    power[2] = tf * wb;
  }
}

void Chain::jacobian_band(const double* y, Mode mode, double* band) const {
  const int N = dof_, n = size();
  const double* k = params_.stiffnesses.data();
  const double* c = params_.dampings.data();
  std::fill(band, band + 5 * n, 0.0);
  auto at = [&](int r, int col) -> double& { return band[5 * r + (col - r + 2)]; };
  for (int i = 0; i < N; ++i) {
    const int r = 2 * i;
    const double inv = inv_inertia_[i];
    double diag = 0.0;
    if (i == 0) diag -= params_.top_damping;
    if (i > 0) {  // spring i−1 above
      at(r, r - 2) = c[i - 1] * inv;
      at(r, r - 1) = k[i - 1] * inv;
      diag -= c[i - 1];
    }
    if (i < N - 1) {  // spring i below
      at(r, r + 1) = -k[i] * inv;
      at(r, r + 2) = c[i] * inv;
      diag -= c[i];
      at(r + 1, r) = 1.0;       // θ̇_i = ω_i − ω_{i+1}
      at(r + 1, r + 2) = -1.0;
    }
    at(r, r) = diag * inv;
  }
  const int b = bit_index();
  detail::bit_jacobian_row(*this, y, mode, &band[5 * b]);
}

double Chain::viscous_power(const double* y, Mode) const {
  const int N = dof_;
  const double* c = params_.dampings.data();
  double p = params_.top_damping * y[0] * y[0];
  for (int i = 0; i < N - 1; ++i) {
    const double dw = y[2 * i] - y[2 * i + 2];
    p += c[i] * dw * dw;
  }
  const double wb = y[bit_index()];  // 0 in exact stick; frozen inside the Karnopp band
  return p + params_.bit_damping * wb * wb;
}

double Chain::friction_power(const double* y, Mode mode) const {
  return friction_torque(y, mode) * y[bit_index()];
}

double Chain::energy(const double* y) const {
  double e = 0.0;
  for (int i = 0; i < dof_; ++i) e += 0.5 * params_.inertias[i] * y[2 * i] * y[2 * i];
  for (int i = 0; i < dof_ - 1; ++i) e += 0.5 * params_.stiffnesses[i] * y[2 * i + 1] * y[2 * i + 1];
  return e;
}

Mode Chain::initial_mode(const double* y, bool karnopp) const {
  const double wb = y[bit_index()];
  if (karnopp) {
    if (wb >= params_.karnopp_band) return Mode::SlipPositive;
    if (wb <= -params_.karnopp_band) return Mode::SlipNegative;
    return std::fabs(reaction_torque(y)) <= friction_.static_torque() ? Mode::Stick : Mode::Band;
  }
  if (wb > 0) return Mode::SlipPositive;
  if (wb < 0) return Mode::SlipNegative;
  const double te = reaction_torque(y), ts = friction_.static_torque();
  if (te > ts) return Mode::SlipPositive;
  if (te < -ts) return Mode::SlipNegative;
  return Mode::Stick;
}

}  // namespace pydrill
