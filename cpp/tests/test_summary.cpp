// The regime judge on synthetic traces with known answers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pydrill/equilibrium.hpp"
#include "pydrill/model.hpp"
#include "pydrill/stability.hpp"
#include "summary.hpp"

using namespace pydrill;

namespace {
struct Synthetic {
  detail::Trace trace;
  detail::WindowAngles angles{};
};

// A bit velocity `bit` sampled finely over [t0, t1] beside a top turning steadily at
// `omega`; the bit's angles at the ends are `angle` (its exact integral), so the judged mean
// is the true one whatever the sampling.
template <class Bit, class Angle>
Synthetic sampled(Bit bit, Angle angle, double omega, double t0, double t1) {
  Synthetic s;
  const int n = 20000;
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + (t1 - t0) * i / n;
    s.trace.t.push_back(t);
    s.trace.bit.push_back(bit(t));
    s.trace.top.push_back(omega);
  }
  s.angles = {t0, t1, omega * t0, omega * t1, angle(t0), angle(t1)};
  return s;
}

// ω_b(t) = Ω + A e^{−σt} sin(2πt/T) sampled finely over [t0, t1]: the judged mean is Ω up to
// the oscillation's own contribution.
Synthetic sine(double omega, double amp, double sigma, double period, double t0, double t1) {
  const double w = 2 * M_PI / period;
  auto integral = [&](double t) {
    // ∫ A e^{−σt} sin(wt) dt = −A e^{−σt} (σ sin wt + w cos wt) / (σ² + w²)
    return omega * t - amp * std::exp(-sigma * t) * (sigma * std::sin(w * t) + w * std::cos(w * t)) /
                           (sigma * sigma + w * w);
  };
  auto bit = [&](double t) { return omega + amp * std::exp(-sigma * t) * std::sin(w * t); };
  return sampled(bit, integral, omega, t0, t1);
}
// The steady velocity of a chain that has exactly one (the approaches' target).
double only_steady_state(const Chain& chain) {
  const std::vector<double> omegas =
      equilibrium_velocities(chain.params(), chain.wob(), chain.torque());
  REQUIRE(omegas.size() == 1);
  return omegas[0];
}
}  // namespace

TEST_CASE("a sustained swing without sticking is an oscillation with its period", "[summary]") {
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const auto s = sine(30.0, 3.0, 0.0, 7.5, 500.0, 1000.0);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const Summary r = detail::summarize(chain, s.trace, modes, s.angles, false);
  CHECK(r.regime == Regime::Oscillation);
  CHECK(r.period == Approx(7.5).epsilon(1e-3));
  CHECK(r.bit_mean == Approx(30.0).epsilon(1e-3));
  CHECK(r.severity == Approx(0.1).epsilon(1e-3));
  CHECK(r.stuck_fraction == 0.0);
}

TEST_CASE("a decaying swing is steady", "[summary]") {
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const auto s = sine(30.0, 3.0, 0.01, 7.5, 500.0, 1000.0);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  CHECK(detail::summarize(chain, s.trace, modes, s.angles, false).regime == Regime::Steady);
}

TEST_CASE("a swing dying out slowly is steady, one growing slowly an oscillation that says so",
          "[summary]") {
  // Near a Hopf point the swing changes at the spectral abscissa's rate, a few thousandths
  // per second: over a 150 s window it falls (or grows) by a few tens of per cent only. The
  // judge used to need 30 % between the window's halves and called such a decay an
  // oscillation (seen at W_ob = 100 N, u = 6.189 N m, dof 4, from the equilibrium).
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const auto decay = sine(10.0, 0.05, 0.00343, 3.1, 150.0, 300.0);
  const Summary d = detail::summarize(chain, decay.trace, modes, decay.angles, false);
  CHECK(d.regime == Regime::Steady);
  CHECK(d.note.empty());
  CHECK(d.caveat.empty());
  const auto growth = sine(10.0, 0.05, -0.00343, 3.1, 150.0, 300.0);
  const Summary g = detail::summarize(chain, growth.trace, modes, growth.angles, false);
  CHECK(g.regime == Regime::Oscillation);
  CHECK(g.note.find("still growing") != std::string::npos);
  CHECK(g.caveat == "growing");
  CHECK(g.period == Approx(3.1).epsilon(1e-3));
  // Within the ±5 % band (a swing 3 % smaller at the end) it is sustained: no note.
  const auto flat = sine(10.0, 0.05, 0.0002, 3.1, 150.0, 300.0);
  const Summary f = detail::summarize(chain, flat.trace, modes, flat.angles, false);
  CHECK(f.regime == Regime::Oscillation);
  CHECK(f.note.empty());
}

TEST_CASE("velocity extremes between coarse samples come from their slopes", "[summary]") {
  // ω_b = 30 + 3 sin(2πt/7.5) sampled every 0.5 s (15 samples a period, none on a peak: the
  // nearest is 1/60 of a period off): the bare samples miss the extremes by 0.016; the
  // cubics through values and slopes find 33 and 27.
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const double w = 2 * M_PI / 7.5;
  detail::Trace tr;
  for (double t = 500.0; t <= 1000.0; t += 0.5) {
    tr.t.push_back(t);
    tr.bit.push_back(30.0 + 3.0 * std::sin(w * t));
    tr.dbit.push_back(3.0 * w * std::cos(w * t));
    tr.top.push_back(30.0);
    tr.dtop.push_back(0.0);
  }
  const double t1 = tr.t.back();
  const detail::WindowAngles angles{500.0, t1, 30.0 * 500.0, 30.0 * t1, 30.0 * 500.0, 30.0 * t1};
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const Summary r = detail::summarize(chain, tr, modes, angles, false);
  CHECK(r.bit_max == Approx(33.0).epsilon(1e-5));
  CHECK(r.bit_min == Approx(27.0).epsilon(1e-5));
  CHECK(r.severity == Approx(0.1).epsilon(1e-4));
  // Without slopes the samples' own extremes, no more.
  tr.dbit.clear();
  const Summary bare = detail::summarize(chain, tr, modes, angles, false);
  CHECK(bare.bit_max == *std::max_element(tr.bit.begin(), tr.bit.end()));
  CHECK(bare.bit_max < 32.99);
}

TEST_CASE("a sustained swing below the tolerance's floor is steady, above it oscillation",
          "[summary]") {
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  // Relative swing (max - min) / mean = 2 * 1.5e-4 / 30 = 1e-5, not decaying.
  const auto s = sine(30.0, 1.5e-4, 0.0, 7.5, 500.0, 1000.0);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  CHECK(detail::summarize(chain, s.trace, modes, s.angles, false).regime == Regime::Oscillation);
  CHECK(detail::summarize(chain, s.trace, modes, s.angles, false,
                          detail::steady_swing_for_tolerance(1e-8)).regime == Regime::Steady);
  CHECK(detail::summarize(chain, s.trace, modes, s.angles, false,
                          detail::steady_swing_for_tolerance(1e-10)).regime == Regime::Oscillation);
}

TEST_CASE("a swing within a coarse tolerance's floor is judged by the state it circles",
          "[summary]") {
  // At W_ob 140 N, u 8.3 N·m the dof-4 string has two steady states: Ω = 1.60 rad/s with
  // three eigenvalues in the right half-plane, and Ω = 6.79 rad/s, stable. A sustained swing
  // of 7 % of the mean lies within what rtol 1e-4 resolves (20 %): about the unstable state
  // it is an oscillation (a limit cycle passed for steady drilling there before), about
  // the stable one the integrator's ringing, steady.
  const Chain chain(preset("reduced-scale", 4), 140.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const double floor = detail::steady_swing_for_tolerance(1e-4);
  REQUIRE(floor == Approx(0.2));
  const auto near_unstable = sine(1.5987, 0.035 * 1.5987, 0.0, 7.5, 500.0, 1000.0);
  const Summary u = detail::summarize(chain, near_unstable.trace, modes, near_unstable.angles,
                                      false, floor);
  CHECK(u.regime == Regime::Oscillation);
  CHECK(u.note.find("linearly unstable") != std::string::npos);
  CHECK(u.period == Approx(7.5).epsilon(1e-3));
  const auto near_stable = sine(6.7932, 0.035 * 6.7932, 0.0, 7.5, 500.0, 1000.0);
  const Summary st = detail::summarize(chain, near_stable.trace, modes, near_stable.angles,
                                       false, floor);
  CHECK(st.regime == Regime::Steady);
  CHECK(st.note.empty());
  // Below 2e-6 of the mean a swing is steady whatever the state (a run started on it).
  const auto still = sine(1.5987, 5e-7 * 1.5987, 0.0, 7.5, 500.0, 1000.0);
  CHECK(detail::summarize(chain, still.trace, modes, still.angles, false, floor).regime ==
        Regime::Steady);
}

TEST_CASE("the judgement of a long string's ambiguous swing asks the interrupt", "[summary]") {
  // The crossings of 2003 inertias take seconds: the run's interrupt is asked meanwhile
  // (simulate turns StabilityInterrupted into Interrupted), and an empty one changes nothing.
  const Chain chain(preset("reduced-scale", 2003), 140.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const double floor = detail::steady_swing_for_tolerance(1e-4);
  const auto near_unstable = sine(1.5987, 0.035 * 1.5987, 0.0, 7.5, 500.0, 1000.0);
  int asked = 0;
  const auto stop = [&asked] {
    ++asked;
    return true;
  };
  CHECK_THROWS_AS(detail::summarize(chain, near_unstable.trace, modes, near_unstable.angles,
                                    false, floor, stop),
                  StabilityInterrupted);
  CHECK(asked == 1);
}

TEST_CASE("stick phases in the window make stick-slip, a stick covering it makes stuck",
          "[summary]") {
  const auto s = sine(10.0, 1.0, 0.0, 10.0, 150.0, 300.0);
  const std::vector<detail::ModeChange> cycle{{0.0, Mode::Stick},   {160.0, Mode::SlipPositive},
                                              {170.0, Mode::Stick}, {180.0, Mode::SlipPositive},
                                              {190.0, Mode::Stick}, {200.0, Mode::SlipPositive}};
  const Chain chain(preset("reduced-scale", 4), 100.0, 8.3);
  const Summary r = detail::summarize(chain, s.trace, cycle, s.angles, false);
  CHECK(r.regime == Regime::StickSlip);
  CHECK(r.stick_events == 2);  // onsets at 170 and 190 lie in [150, 300]
  CHECK(r.period == Approx(20.0));
  CHECK(r.stuck_fraction == Approx((10.0 + 10.0 + 10.0) / 150.0));

  // Held from before the window to its end, and u = 8.3 < T_s = 12.8 at W_ob = 160 N.
  const Chain heavy(preset("reduced-scale", 4), 160.0, 8.3);
  const std::vector<detail::ModeChange> held{{0.0, Mode::Stick}};
  const Summary stuck = detail::summarize(heavy, s.trace, held, s.angles, false);
  CHECK(stuck.regime == Regime::Stuck);
  CHECK(stuck.note.empty());
  // Same, but u > T_s: the bit must break free later; never having slipped, the run
  // ended in the first wind-up and says so.
  const Summary windup = detail::summarize(chain, s.trace, held, s.angles, false);
  CHECK(windup.regime == Regime::Stuck);
  CHECK_FALSE(windup.note.empty());
  CHECK(windup.caveat == "first-wind-up");
  // Slipped before the window, held all through it, and u > T_s: one long stick phase.
  const std::vector<detail::ModeChange> long_stick{{0.0, Mode::SlipPositive}, {100.0, Mode::Stick}};
  const Summary phase = detail::summarize(chain, s.trace, long_stick, s.angles, false);
  CHECK(phase.regime == Regime::StickSlip);
  CHECK(phase.caveat == "one-stick-phase");
  CHECK_THAT(phase.note, Catch::Contains("single stick phase"));
}

TEST_CASE("a window too short to judge says so", "[summary]") {
  // The dof-4 laboratory string: springs 3 x 0.073 N m/rad in series against the inertias
  // above the bit (0.518 + 0.025 + 0.0318 kg m^2): slowest period 2 pi sqrt(0.5748 * 3 / 0.073).
  const double slowest = 2 * M_PI * std::sqrt((0.518 + 0.025 + 0.0318) * 3 / 0.073);
  const Chain chain(preset("reduced-scale", 4), 100.0, 8.3);
  const std::vector<detail::ModeChange> slipping{{0.0, Mode::SlipPositive}};
  // 3 s of a 17.5 s stick-slip cycle's slip phase: looks like an oscillation, or steady.
  const auto part = sine(3.0, 1.0, 0.0, 17.5, 297.0, 300.0);
  const Summary r = detail::summarize(chain, part.trace, slipping, part.angles, false);
  CHECK_THAT(r.note, Catch::Contains("shorter than the string's slowest period"));
  CHECK(r.caveat == "short-window");
  std::ostringstream expected;
  expected.precision(3);
  expected << "(about " << slowest << " s)";
  CHECK_THAT(r.note, Catch::Contains(expected.str()));
  // The same swing judged over five slowest periods carries no such note.
  const auto whole = sine(3.0, 1.0, 0.0, 17.5, 300.0 - 5 * slowest, 300.0);
  CHECK(detail::summarize(chain, whole.trace, slipping, whole.angles, false).note.empty());
  // A bit held for good (u < T_s at 160 N) is stuck however short the window.
  const Chain heavy(preset("reduced-scale", 4), 160.0, 8.3);
  const std::vector<detail::ModeChange> held{{0.0, Mode::Stick}};
  const auto still = sine(0.0, 0.0, 0.0, 17.5, 297.0, 300.0);
  const Summary stuck = detail::summarize(heavy, still.trace, held, still.angles, false);
  CHECK(stuck.regime == Regime::Stuck);
  CHECK(stuck.note.empty());
}

TEST_CASE("one break-away in the window and no stick after it is flagged", "[summary]") {
  const auto s = sine(10.0, 1.0, 0.0, 10.0, 150.0, 300.0);
  const Chain chain(preset("reduced-scale", 4), 100.0, 8.3);
  // Stuck from before the window until 160 s, slipping to the end: stick-slip so far, with
  // no stick event to show a cycle.
  const std::vector<detail::ModeChange> once{{0.0, Mode::Stick}, {160.0, Mode::SlipPositive}};
  const Summary r = detail::summarize(chain, s.trace, once, s.angles, false);
  CHECK(r.regime == Regime::StickSlip);
  CHECK(r.stick_events == 0);
  CHECK_THAT(r.note, Catch::Contains("broke free once"));
  CHECK(r.caveat == "one-break-away");
  // Sticks after it that repeat (40 s slips, 10 s sticks) make a cycle: no note.
  const std::vector<detail::ModeChange> again{
      {0.0, Mode::Stick},         {160.0, Mode::SlipPositive}, {200.0, Mode::Stick},
      {210.0, Mode::SlipPositive}, {250.0, Mode::Stick},        {260.0, Mode::SlipPositive}};
  CHECK(detail::summarize(chain, s.trace, again, s.angles, false).note.empty());
}

TEST_CASE("slipping, then one stick to the window's end, is stuck when the rock can hold u",
          "[summary]") {
  const auto s = sine(10.0, 1.0, 0.0, 10.0, 150.0, 300.0);
  // Slipping since before the window, stuck from 240 s to its end.
  const std::vector<detail::ModeChange> late{{0.0, Mode::SlipPositive}, {240.0, Mode::Stick}};
  // u = 8.3 <= T_s = 12.8 at W_ob = 160 N: stuck once and not left, with a caveat.
  const Chain heavy(preset("reduced-scale", 4), 160.0, 8.3);
  const Summary r = detail::summarize(heavy, s.trace, late, s.angles, false);
  CHECK(r.regime == Regime::Stuck);
  CHECK(r.caveat == "late-stick");
  CHECK_THAT(r.note, Catch::Contains("t = 240 s"));
  CHECK(r.stick_events == 1);
  CHECK(r.stuck_fraction == Approx(60.0 / 150.0));
  // u = 8.3 > T_s = 8.0 at W_ob = 100 N: the bit must break free again, stick-slip.
  const Chain light(preset("reduced-scale", 4), 100.0, 8.3);
  CHECK(detail::summarize(light, s.trace, late, s.angles, false).regime == Regime::StickSlip);
  // Held when the window opened, free, then held again: two stick phases, stick-slip.
  const std::vector<detail::ModeChange> twice{
      {0.0, Mode::Stick}, {160.0, Mode::SlipPositive}, {240.0, Mode::Stick}};
  const Summary t = detail::summarize(heavy, s.trace, twice, s.angles, false);
  CHECK(t.regime == Regime::StickSlip);
  CHECK(t.caveat.empty());
}

TEST_CASE("a stick-slip cycle that ended in the window is judged by its last phase",
          "[summary]") {
  const auto s = sine(10.0, 1.0, 0.0, 10.0, 150.0, 300.0);
  const Chain heavy(preset("reduced-scale", 4), 160.0, 8.3);  // u = 8.3 <= T_s = 12.8
  const Chain light(preset("reduced-scale", 4), 100.0, 8.3);  // u = 8.3 >  T_s = 8.0
  // Sticks of 10 s every 25 s, then one from 225 s to the window's end: 75 s, over twice
  // the longest before it. With |u| <= T_s the bit is stuck (for good, as far as it saw).
  const std::vector<detail::ModeChange> stopped{
      {0.0, Mode::SlipPositive},   {150.0, Mode::Stick}, {160.0, Mode::SlipPositive},
      {175.0, Mode::Stick},        {185.0, Mode::SlipPositive}, {200.0, Mode::Stick},
      {210.0, Mode::SlipPositive}, {225.0, Mode::Stick}};
  const Summary r = detail::summarize(heavy, s.trace, stopped, s.angles, false);
  CHECK(r.regime == Regime::Stuck);
  CHECK(r.caveat == "late-stick");
  CHECK_THAT(r.note, Catch::Contains("stuck since t = 225 s, for 75 s"));
  CHECK_THAT(r.note, Catch::Contains("stick phase before it in the window (10 s)"));
  CHECK(r.stuck_fraction == Approx(105.0 / 150.0));
  // The rock cannot hold the bit at |u| > T_s: a long stick of a cycle, still stick-slip.
  const Summary l = detail::summarize(light, s.trace, stopped, s.angles, false);
  CHECK(l.regime == Regime::StickSlip);
  CHECK(l.caveat.empty());
  // The last stick only 1.9 times the longest (10 s, from 281 s): a cycle's, no caveat.
  std::vector<detail::ModeChange> cycling(stopped.begin(), stopped.end() - 1);
  cycling.push_back({235.0, Mode::Stick});
  cycling.push_back({245.0, Mode::SlipPositive});
  cycling.push_back({281.0, Mode::Stick});
  const Summary c = detail::summarize(heavy, s.trace, cycling, s.angles, false);
  CHECK(c.regime == Regime::StickSlip);
  CHECK(c.note.empty());
  // A stick phase that began before the window counts whole: held 0-160 s, free for 80 s,
  // then held 60 s to the end is a slow cycle (60 < 2 x 160), not a stuck bit.
  const std::vector<detail::ModeChange> slow{
      {0.0, Mode::Stick}, {160.0, Mode::SlipPositive}, {240.0, Mode::Stick}};
  CHECK(detail::summarize(heavy, s.trace, slow, s.angles, false).regime == Regime::StickSlip);

  // Slips of 15 s between sticks, then none since 195 s: 105 s, over twice the longest. The
  // stick-slip may have died out: still stick-slip (it stuck in the window), with a caveat.
  const std::vector<detail::ModeChange> freed{
      {0.0, Mode::SlipPositive}, {155.0, Mode::Stick}, {160.0, Mode::SlipPositive},
      {175.0, Mode::Stick},      {180.0, Mode::SlipPositive}, {190.0, Mode::Stick},
      {195.0, Mode::SlipPositive}};
  const Summary f = detail::summarize(light, s.trace, freed, s.angles, false);
  CHECK(f.regime == Regime::StickSlip);
  CHECK(f.caveat == "one-break-away");
  CHECK_THAT(f.note, Catch::Contains("without sticking since t = 195 s, for 105 s"));
  CHECK_THAT(f.note, Catch::Contains("slip phase before it in the window (15 s)"));
  // The last slip 1.9 times the longest (15 s, from 271.5 s on): a cycle's, no caveat.
  std::vector<detail::ModeChange> slipping(freed.begin(), freed.end() - 1);
  slipping.push_back({195.0, Mode::SlipPositive});
  slipping.push_back({210.0, Mode::Stick});
  slipping.push_back({243.0, Mode::SlipPositive});
  slipping.push_back({250.0, Mode::Stick});
  slipping.push_back({255.0, Mode::SlipPositive});
  slipping.push_back({270.0, Mode::Stick});
  slipping.push_back({271.5, Mode::SlipPositive});
  CHECK(detail::summarize(light, s.trace, slipping, s.angles, false).note.empty());
}

TEST_CASE("a big slow swing dying out moves its half-windows' means, and is not approaching",
          "[summary]") {
  // A swing of 60 % of the mean with a period of 28 s spans 2.7 periods in each half of a 150 s
  // window: the halves' means differ by several per cent with no drift at all. The caveat
  // "approaching" asks a drift beyond what such a swing can fake.
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const auto s = sine(10.0, 6.0, 0.003, 28.0, 150.0, 300.0);
  double first = 0.0, second = 0.0;
  int n1 = 0, n2 = 0;
  for (std::size_t i = 0; i < s.trace.t.size(); ++i) {
    if (s.trace.t[i] < 225.0) first += s.trace.bit[i], ++n1;
    else second += s.trace.bit[i], ++n2;
  }
  CHECK(std::fabs(second / n2 - first / n1) > 0.02 * 10.0);  // what a bare 1 % test would flag
  const Summary r = detail::summarize(chain, s.trace, modes, s.angles, false);
  CHECK(r.regime == Regime::Steady);
  CHECK(r.caveat.empty());
}

TEST_CASE("a slow approach still a few per cent short of its steady state is approaching",
          "[summary]") {
  // ω_b(t) = Ω (1 − 0.05 e^{−(t − 150)/600}): across the window [150, 300] its mean moves by
  // half a per cent only, but the steady state is still 4 % ahead of it. The caveat names it.
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const double omega = only_steady_state(chain);
  const auto bit = [&](double t) { return omega * (1.0 - 0.05 * std::exp(-(t - 150.0) / 600.0)); };
  const auto angle = [&](double t) {
    return omega * (t + 0.05 * 600.0 * std::exp(-(t - 150.0) / 600.0));
  };
  const Synthetic s = sampled(bit, angle, omega, 150.0, 300.0);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const Summary r = detail::summarize(chain, s.trace, modes, s.angles, false);
  CHECK(r.regime == Regime::Steady);
  CHECK(r.caveat == "approaching");
  std::ostringstream ahead;
  ahead.precision(3);
  ahead << "on its way to the steady state at " << omega << " rad/s";
  CHECK_THAT(r.note, Catch::Contains(ahead.str()));
  // The same approach 0.1 % short: there, no caveat.
  Synthetic near = s;
  for (double& v : near.trace.bit) v = omega - (omega - v) / 50.0;
  near.angles.bit0 = omega * 150.0 + (angle(150.0) - omega * 150.0) / 50.0;
  near.angles.bit1 = omega * 300.0 + (angle(300.0) - omega * 300.0) / 50.0;
  const Summary n = detail::summarize(chain, near.trace, modes, near.angles, false);
  CHECK(n.regime == Regime::Steady);
  CHECK(n.caveat.empty());
}

TEST_CASE("a mean on its way under a big fast swing is approaching, the swing alone is not",
          "[summary]") {
  // ω_b(t) = Ω (1 − 0.25 e^{−(t − 150)/300}) + 0.5 Ω e^{−(t − 150)/200} sin(2πt / 8.5 s): the
  // mean climbs by 5 % of Ω across the window under a swing of half of Ω. Bounded by the
  // string's slowest period (30 s), such a swing could fake a drift of 7 % of Ω and the
  // approach went unsaid; by its own cycles (8.5 s), 2 %.
  const Chain chain(preset("reduced-scale", 4), 40.0, 8.3);
  const double omega = only_steady_state(chain), sigma = 1.0 / 200.0, w = 2 * M_PI / 8.5;
  const auto swing = [&](double t) {
    return 0.5 * omega * std::exp(-sigma * (t - 150.0)) * std::sin(w * t);
  };
  const auto swing_integral = [&](double t) {
    return -0.5 * omega * std::exp(-sigma * (t - 150.0)) *
           (sigma * std::sin(w * t) + w * std::cos(w * t)) / (sigma * sigma + w * w);
  };
  const auto bit = [&](double t) {
    return omega * (1.0 - 0.25 * std::exp(-(t - 150.0) / 300.0)) + swing(t);
  };
  const auto angle = [&](double t) {
    return omega * (t + 75.0 * std::exp(-(t - 150.0) / 300.0)) + swing_integral(t);
  };
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const Synthetic s = sampled(bit, angle, omega, 150.0, 300.0);
  const Summary r = detail::summarize(chain, s.trace, modes, s.angles, false);
  CHECK(r.regime == Regime::Steady);
  CHECK(r.severity > 0.4);
  CHECK(r.caveat == "approaching");
  // The swing alone, about Ω: its halves' means differ too, by less than it can fake.
  const auto still = [&](double t) { return omega + swing(t); };
  const auto still_angle = [&](double t) { return omega * t + swing_integral(t); };
  const Synthetic q = sampled(still, still_angle, omega, 150.0, 300.0);
  const Summary n = detail::summarize(chain, q.trace, modes, q.angles, false);
  CHECK(n.regime == Regime::Steady);
  CHECK(n.caveat.empty());
}

TEST_CASE("a swing about a mean on its way to a stable steady state is steady, approaching",
          "[summary]") {
  // The dof-4 string at W_ob 140 N, u 8.3 N·m: steady states at Ω = 1.60 rad/s (unstable)
  // and 6.79 rad/s (stable). A swing that does not grow against a mean climbing towards 6.79
  // is a bit spinning up, not a limit cycle (whose mean stays put): steady by where it is
  // going. The same swing about a mean falling towards the unstable state stays an
  // oscillation, as it does about a mean that stays put; so does one that grows against it.
  const Chain chain(preset("reduced-scale", 4), 140.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const double stable = 6.7932, unstable = 1.5987, w = 2 * M_PI / 7.5;
  const auto p = chain.params();
  REQUIRE(unstable_count(critical_deltas(p), stribeck_slope(p, 140.0, stable)) == 0);
  REQUIRE(unstable_count(critical_deltas(p), stribeck_slope(p, 140.0, unstable)) > 0);
  // ω_b(t) = ω_0 + k s + (a + b s) sin(w t), s = t − 150, and its exact angle. A steady ramp
  // adds the same to each quarter's swing: with b = 0 the swing neither grows nor dies out.
  const auto run = [&](double omega0, double k, double a, double b) {
    const auto bit = [=](double t) {
      return omega0 + k * (t - 150.0) + (a + b * (t - 150.0)) * std::sin(w * t);
    };
    const auto angle = [=](double t) {
      const double s = t - 150.0;
      return omega0 * t + 0.5 * k * s * s - (a + b * s) * std::cos(w * t) / w +
             b * std::sin(w * t) / (w * w);
    };
    return sampled(bit, angle, omega0, 150.0, 300.0);
  };
  const Synthetic up = run(4.3, 1.0 / 150.0, 1.0, 0.0);  // halves' means 4.55 -> 5.05 rad/s
  const Summary r = detail::summarize(chain, up.trace, modes, up.angles, false);
  CHECK(r.regime == Regime::Steady);
  CHECK(r.caveat == "approaching");
  CHECK_THAT(r.note, Catch::Contains("does not grow against it"));
  CHECK_THAT(r.note, Catch::Contains("steady state at 6.79 rad/s, which is linearly stable"));
  // A swing of a fifth of a mean that climbs from 4.3 to 5.8 rad/s grows with it, by a third
  // across the window ("growing" by itself), and not against it: steady, approaching.
  const double k = 1.5 / 150.0;
  const Synthetic along = run(4.3, k, 0.2 * 4.3, 0.2 * k);
  const Summary g = detail::summarize(chain, along.trace, modes, along.angles, false);
  CHECK(g.regime == Regime::Steady);
  CHECK(g.caveat == "approaching");
  // The swing growing eightfold under the same mean: against it too, an oscillation growing.
  const Synthetic faster = run(4.3, k, 0.2, 1.4 / 150.0);
  const Summary f = detail::summarize(chain, faster.trace, modes, faster.angles, false);
  CHECK(f.regime == Regime::Oscillation);
  CHECK(f.caveat == "growing");
  const Synthetic down = run(4.6, -1.0 / 150.0, 1.0, 0.0);  // 4.35 -> 3.85 rad/s, to 1.60
  const Summary d = detail::summarize(chain, down.trace, modes, down.angles, false);
  CHECK(d.regime == Regime::Oscillation);
  CHECK(d.caveat.empty());
  const Synthetic put = run(5.0, 0.0, 1.0, 0.0);  // about 5 rad/s throughout
  const Summary q = detail::summarize(chain, put.trace, modes, put.angles, false);
  CHECK(q.regime == Regime::Oscillation);
  CHECK(q.period == Approx(7.5).epsilon(1e-3));
}

TEST_CASE("a swing dying out about a linearly unstable steady state is an oscillation growing",
          "[summary]") {
  // The dof-4 string at W_ob 140 N, u 8.3 N·m: steady states at Ω = 1.60 rad/s (unstable)
  // and 6.79 rad/s (stable). A swing shrinking across the window about either looks steady;
  // about the unstable one, the decay is the stable modes', and the linear analysis says the
  // state will be left: an oscillation still growing, its e-folding time in the note.
  const Chain chain(preset("reduced-scale", 4), 140.0, 8.3);
  const std::vector<detail::ModeChange> modes{{0.0, Mode::SlipPositive}};
  const double stable = 6.7932, unstable = 1.5987;
  const StabilityPoint at = stability_at_velocity(chain.params(), 140.0, unstable);
  REQUIRE(at.spectral_abscissa > 0.0);
  REQUIRE(stability_at_velocity(chain.params(), 140.0, stable).spectral_abscissa < 0.0);
  const auto about = [&](double omega) {
    const Synthetic s = sine(omega, 1e-3 * omega, 0.01, 3.1, 150.0, 300.0);
    return detail::summarize(chain, s.trace, modes, s.angles, false);
  };
  const Summary kept = about(stable);
  CHECK(kept.regime == Regime::Steady);
  CHECK(kept.caveat.empty());
  const Summary left = about(unstable);
  CHECK(left.regime == Regime::Oscillation);
  CHECK(left.caveat == "growing");
  CHECK_THAT(left.note, Catch::Contains("(1.6 rad/s; its swing"));
  CHECK_THAT(left.note, Catch::Contains("but that state is linearly unstable"));
  std::ostringstream efold;
  efold.precision(3);
  efold << "e-fold every " << 1.0 / at.spectral_abscissa << " s";
  CHECK_THAT(left.note, Catch::Contains(efold.str()));
}
