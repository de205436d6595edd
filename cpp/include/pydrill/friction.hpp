// Bit–rock friction of DESIGN.md §2: static torque T_s = μ_sb·W_ob·R_b and a
// slip torque with an exponential Stribeck decay towards the Coulomb level.
#pragma once

#include <cmath>

#include "pydrill/params.hpp"

namespace pydrill {

struct BitFriction {
  double scale;       // W_ob·R_b, N·m
  double mu_c;        // μ_cb
  double mu_s;        // μ_sb
  double decay;       // γ_b / v_f, s/rad

  // Checks the friction law and W_ob first (std::invalid_argument naming the bad one): a
  // zero v_f or μ_sb < μ_cb would otherwise come back as silent NaN or negative torques, and
  // a static torque or slope beyond the doubles as inf (check_bit_friction).
  BitFriction(const Params& p, double wob)
      : scale((check(p, wob), wob * p.bit_radius)),
        mu_c(p.mu_coulomb),
        mu_s(p.mu_static),
        decay(p.stribeck_decay / p.stribeck_velocity) {}

  // Largest torque the rock holds on a still bit.
  double static_torque() const { return mu_s * scale; }

  // Slip friction magnitude f_b(|ω|) = R_b W_ob μ_b(ω); equals T_s at ω = 0⁺,
  // so there is no torque jump at break-away.
  double magnitude(double omega) const {
    return scale * (mu_c + (mu_s - mu_c) * std::exp(-decay * std::fabs(omega)));
  }

  // Signed slip torque T_fb(ω) = f_b(|ω|)·sgn(ω) for a bit that slips in
  // direction `dir` (+1 or -1), written dir·f_b(dir·ω). The direction is the
  // mode's, not sgn(ω), and f_b is continued analytically past ω = 0: a trial
  // stage of the integrator a hair across zero sees neither a flipped sign nor
  // the kink of |ω|, so the steps that reach a stick event stay long.
  double slip_torque(double omega, int dir) const {
    return dir * scale * (mu_c + (mu_s - mu_c) * std::exp(-decay * dir * omega));
  }

  // d slip_torque / dω for the same smooth continuation.
  double slip_torque_slope(double omega, int dir) const {
    return -scale * (mu_s - mu_c) * decay * std::exp(-decay * dir * omega);
  }

  // d T_fb / dω in slip (both directions): −scale·(μ_s−μ_c)·decay·e^{−decay|ω|}.
  double slip_slope(double omega) const {
    return -scale * (mu_s - mu_c) * decay * std::exp(-decay * std::fabs(omega));
  }

  // Stribeck slope δ(Ω) = −dT_fb/dω at Ω > 0 (DESIGN.md §3).
  double delta(double omega) const { return -slip_slope(omega); }

 private:
  static int check(const Params& p, double wob) {
    p.validate();
    check_operating_point(wob, 0.0);
    check_bit_friction(p, wob);
    return 0;
  }
};

}  // namespace pydrill
