// Valid strings at the edges of the doubles (Params::validate refuses fast rates, not slow
// ones): found by the libFuzzer harness in cpp/fuzz/. Each answer must be the one the same
// string gives a few decades further in, not an overflow's inf, NaN or lost crossings.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "pydrill/equilibrium.hpp"
#include "pydrill/simulator.hpp"
#include "pydrill/stability.hpp"

using namespace pydrill;

namespace {

// The same crossings: count, kind, direction, and δ to 1e-9 (the frequency of a mode that the
// changed element carries moves with it, so it is not compared).
void same_crossings(const std::vector<Crossing>& a, const std::vector<Crossing>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].type == b[i].type);
    CHECK(a[i].direction == b[i].direction);
    CHECK(a[i].delta == Approx(b[i].delta).epsilon(1e-9));
  }
}

}  // namespace

TEST_CASE("a top inertia at the doubles' top keeps the string's crossings and stiffness",
          "[stability][extreme]") {
  // Measured before: the fundamental's compliance × inertia overflowed (fundamental 0,
  // stiffness_ratio inf), and the bit impedance's first product I_0·λ did too: its phase was
  // NaN above 2 rad/s, and critical_deltas found 2 of the 6 crossings that 1e307 has.
  Params p = preset("reduced-scale", 4);
  p.inertias[0] = 1e307;
  const auto reference = critical_deltas(p);
  REQUIRE(reference.size() == 6);
  p.inertias[0] = std::numeric_limits<double>::max();
  REQUIRE_NOTHROW(p.validate());
  same_crossings(critical_deltas(p), reference);
  const StiffnessEstimate e = estimate_stiffness(p);
  CHECK(e.fundamental > 0);
  CHECK(std::isfinite(stiffness_ratio(p)));
  // 1/√(compliance × inertia): 3 springs of 0.073 in series, and the top inertia (the others
  // vanish beside it).
  CHECK(e.fundamental == Approx(std::sqrt(0.073 / 3) / std::sqrt(std::numeric_limits<double>::max())).epsilon(1e-12));
  const std::complex<double> z = bit_impedance(p, {0.0, 5.0});
  CHECK(std::isfinite(z.real()));
  CHECK(std::isfinite(z.imag()));
}

TEST_CASE("a tiny stiffness keeps the string's crossings and stiffness", "[stability][extreme]") {
  // Measured before: with stiffnesses[0] = 1e-310 (subnormal, allowed then) 1/k = inf made the
  // fundamental 0 and critical_deltas' geometric frequency grid NaN (then sorted, which
  // std::sort does not allow), and a Hopf crossing came out twice. Subnormals are refused now
  // (below); the smallest normal stiffness keeps the crossings of 1e-300.
  Params p = preset("reduced-scale", 4);
  p.stiffnesses[0] = 1e-300;
  const auto reference = critical_deltas(p);
  p.stiffnesses[0] = std::numeric_limits<double>::min();
  REQUIRE_NOTHROW(p.validate());
  same_crossings(critical_deltas(p), reference);
  CHECK(estimate_stiffness(p).fundamental > 0);
  CHECK(std::isfinite(stiffness_ratio(p)));
}

TEST_CASE("a subnormal parameter is refused: a run reads it as 0", "[params][extreme]") {
  // Measured before: stiffnesses[0] = 5e-324 passed (> 0); the run, which flushes subnormal
  // numbers, read it as a broken spring, and critical_deltas found eight spurious Hopf points.
  Params p = preset("reduced-scale", 3);
  p.stiffnesses[0] = 5e-324;
  CHECK_THROWS_WITH(p.validate(), Catch::StartsWith("stiffnesses[0] = ") && Catch::Contains("e-324 is not allowed: a subnormal number"));
  p = preset("reduced-scale", 3);
  p.dampings[1] = 1e-310;
  CHECK_THROWS_WITH(p.validate(), Catch::StartsWith("dampings[1] = 1e-310 is not allowed") && Catch::Contains("give 0 or"));
  p = preset("reduced-scale", 3);
  p.mu_coulomb = 1e-320;
  CHECK_THROWS_WITH(p.validate(), Catch::StartsWith("mu_coulomb = ") && Catch::Contains("is not allowed: a subnormal number"));
  p = preset("reduced-scale", 3);
  p.inertias[2] = std::numeric_limits<double>::denorm_min();
  CHECK_THROWS_AS(p.validate(), std::invalid_argument);
  p.inertias[2] = 1e-300;  // tiny but normal: allowed, as is damping 0
  p.top_damping = 0.0;
  p.bit_damping = 0.0;
  p.dampings = {0.0, 0.0};
  CHECK_NOTHROW(p.validate());
}

TEST_CASE("a slow string has the crossings of the fast one it is a time scaling of", "[stability][extreme]") {
  // Inertias ×s and dampings ×√s make the same string on a clock √s times slower: its
  // eigenvalues are the paper string's / √s, its crossings' δ ×√s, with the same directions.
  // Measured before: from s = 1e8 (modes near 1e-4 rad/s) the fold's direction was reversed
  // (its derivative was a difference with a step of 1e-7 (c_r + c_b), in 1/s), from 1e16 the
  // Hopf points' too (a step of at least 1e-9 1/s), and at 1e100 two of the six crossings were
  // lost (the frequency grid's top had 1e-9 rad/s added, far above all the modes).
  const Params paper = preset("reduced-scale", 4);
  const auto reference = critical_deltas(paper);
  REQUIRE(reference.size() == 6);
  for (double s : {1e8, 1e16, 1e100}) {
    Params p = paper;
    for (double& v : p.inertias) v *= s;
    for (double& v : p.dampings) v *= std::sqrt(s);
    p.top_damping *= std::sqrt(s);
    p.bit_damping *= std::sqrt(s);
    const auto crossings = critical_deltas(p);
    INFO("s = " << s);
    REQUIRE(crossings.size() == reference.size());
    for (std::size_t i = 0; i < crossings.size(); ++i) {
      CHECK(crossings[i].type == reference[i].type);
      CHECK(crossings[i].direction == reference[i].direction);
      CHECK(crossings[i].delta == Approx(reference[i].delta * std::sqrt(s)).epsilon(1e-9));
      CHECK(crossings[i].frequency * std::sqrt(s) == Approx(reference[i].frequency).epsilon(1e-9));
    }
  }
}

TEST_CASE("a bit friction beyond the doubles is refused, not run or linearised as inf or NaN",
          "[stability][extreme]") {
  // Measured before: mu_static = 1.8e308 (valid alone) ran as a bit stuck against an infinite
  // static_torque and was reported as a success; every number 1e150 gave a stribeck_slope of
  // inf × exp(−1e150) = NaN; a slope at rest beyond the doubles a friction magnitude of
  // inf × 0 = NaN at rest (an infinite stribeck_decay / stribeck_velocity is now refused by
  // validate, see below).
  const Params paper = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = 1.0;
  Params p = paper;
  p.mu_static = std::numeric_limits<double>::max();
  REQUIRE_NOTHROW(p.validate());
  CHECK_THROWS_WITH(simulate(p, 100.0, 8.3, o),
                    Catch::StartsWith("wob = 100 is not allowed with bit_radius = 0.1, mu_static = 1.7976931348623157e+308:") &&
                        Catch::Contains("static torque"));
  CHECK_THROWS_AS(stribeck_slope(p, 100.0, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(stability_at_torque(p, 100.0, 8.3), std::invalid_argument);
  p = paper;
  p.stribeck_decay = 1e300;
  p.stribeck_velocity = 1e-5;
  REQUIRE_NOTHROW(p.validate());
  CHECK_THROWS_WITH(simulate(p, 1e15, 8.3, o), Catch::Contains("Stribeck slope at rest"));
  CHECK_THROWS_AS(equilibrium_velocities(p, 1e15, 8.3), std::invalid_argument);
  p = paper;
  p.bit_radius = 1e150;
  p.mu_coulomb = 1e150;
  p.mu_static = 1e300;
  CHECK_THROWS_AS(stribeck_slope(p, 1e150, 1e150), std::invalid_argument);
  // What a real string needs stays allowed, however heavy the weight.
  CHECK_NOTHROW(stribeck_slope(preset("real-string", 2), 1e15, 1.0));
}

TEST_CASE("first_lyapunov_coefficient at the fold is refused, naming delta", "[stability][extreme]") {
  // Measured before: an undamped string (c_r = c_b = 0, allowed) at δ = 0 threw BandLU's bare
  // std::runtime_error "band LU: the matrix is singular", undocumented and naming nothing; a
  // damped one at its fold δ = c_r + c_b returned -1.5e12 from a rounded singular solve.
  Params p = preset("reduced-scale", 4);
  CHECK_THROWS_WITH(first_lyapunov_coefficient(p, 0.19, 1.0),
                    Catch::StartsWith("delta = 0.19 is not allowed with frequency = 1: the linearisation there is singular"));
  p.top_damping = 0.0;
  p.bit_damping = 0.0;
  // At δ = 0, the fold of this string, the friction is flat (every Taylor term ∝ δ): the
  // coefficient is 0, degenerate, not a singular solve (an undamped string's Hopf points are
  // all there).
  CHECK(first_lyapunov_coefficient(p, 0.0, 1.0) == 0.0);
  CHECK_THROWS_AS(first_lyapunov_coefficient(p, -0.0, 0.0), std::invalid_argument);  // frequency 0
  // Beside it, at this string's Hopf points above δ = 0, the solves are regular again.
  int hopf = 0;
  for (const Crossing& c : critical_deltas(p)) {
    if (c.type != CrossingType::Hopf || !(c.delta > 0.0)) continue;
    CHECK(std::isfinite(first_lyapunov_coefficient(p, c.delta, c.frequency)));
    ++hopf;
  }
  CHECK(hopf > 0);
}

TEST_CASE("equilibrium_velocities returns no steady state that a double cannot hold", "[stability][extreme]") {
  // Measured before: u = 1.8e308 N·m with c_r + c_b = 0.19 needs Ω ≈ 9.5e308 rad/s, beyond the
  // doubles; the search's bracket ran to inf and 2^1023 rad/s came back as a root, where the
  // torque curve is 1.7e307 N·m. As without damping, no steady state is returned.
  const Params p = preset("reduced-scale", 4);
  CHECK(equilibrium_velocities(p, 100.0, std::numeric_limits<double>::max()).empty());
  CHECK(stability_at_torque(p, 100.0, std::numeric_limits<double>::max()).empty());
  // One that fits is still found, and holds its torque.
  const auto omegas = equilibrium_velocities(p, 100.0, 1e300);
  REQUIRE(omegas.size() == 1);
  CHECK(equilibrium_torque(p, 100.0, omegas[0]) == Approx(1e300).epsilon(1e-12));
}

TEST_CASE("a Hopf point slower than the string's fundamental is found", "[stability][extreme]") {
  // A 2-DOF string whose top (4e-14 kg·m², held by its damping: 1.5e11 /s) is far lighter than
  // its bit swings at 1.5 rad/s, the bit on the spring, far below the fundamental of the string
  // on a still bit (2.4e5 rad/s). Measured before: the frequency grid began at 1e-4 of that,
  // 24 rad/s, and critical_deltas missed the Hopf point the closed form finds, so its unstable
  // counts were 2 too low (-1 past the fold).
  Params p = preset("reduced-scale", 2);
  p.inertias = {4e-14, 9.834e-4};
  p.stiffnesses = {2.393e-3};
  p.dampings = {3.278e-6};
  p.top_damping = 5.9e-3;
  p.bit_damping = 3.278e-4;
  const auto closed_form = hopf_deltas_dof2(p);
  REQUIRE(closed_form.size() == 1);
  const auto crossings = critical_deltas(p);
  REQUIRE(crossings.size() == 2);
  CHECK(crossings[0].type == CrossingType::Hopf);
  CHECK(crossings[0].delta == Approx(closed_form[0]).epsilon(1e-9));
  CHECK(crossings[0].direction == 1);
  for (double delta : {1e-3, 1e-2, 1.0}) {
    int dense = 0;
    for (const auto& z : eigenvalues(p, delta)) dense += z.real() > 0;
    CHECK(unstable_count(crossings, delta) == dense);
  }
}

TEST_CASE("a t_end beyond 1e10 s is refused, as Python refuses it", "[simulate][extreme]") {
  // Measured before: t_end = 1.8e308 s (finite, so allowed) made the n_out grid
  // t_end·i/(n_out − 1) inf, and a run of 9 outputs returned 2; with a top inertia of 5.9e307
  // ERK returned NaN states and called the run "stuck", BDF a bit still after 1.8e308 s.
  const Params p = preset("reduced-scale", 4);
  SimulationOptions o;
  o.t_end = std::numeric_limits<double>::max();
  o.n_out = 9;
  CHECK_THROWS_WITH(simulate(p, 1e-300, 0.0, o),
                    Catch::StartsWith("t_end = 1.7976931348623157e+308 is not allowed: need 0 < t_end <= 1e+10 s"));
  o.t_end = 1.0000001e10;
  CHECK_THROWS_AS(o.validate(4), std::invalid_argument);
  o.t_end = kMaxTEnd;
  CHECK_NOTHROW(o.validate(4));
}

TEST_CASE("an overflowing friction rate is refused, and a vanishing slope is 0, not NaN",
          "[stability][extreme]") {
  // Measured before, each on a valid string: stribeck_decay 1.76e308 / stribeck_velocity 0.03
  // = inf made boundary_wob inf / inf = NaN; stribeck_slope at wob 2.2e-308 with mu_static
  // 8.7e307 and stribeck_decay 1e300 was inf × exp(−1.6e299) = NaN.
  Params p = preset("reduced-scale", 4);
  p.stribeck_decay = 1.76e308;
  p.stribeck_velocity = 0.03;
  CHECK_THROWS_WITH(p.validate(), Catch::StartsWith("stribeck_decay = 1.76e+308 is not allowed: with stribeck_velocity = 0.03"));
  p = preset("reduced-scale", 4);
  p.mu_static = 8.7e307;
  p.stribeck_decay = 1e300;
  const double slope = stribeck_slope(p, std::numeric_limits<double>::min(), 0.158);
  CHECK(slope == 0.0);  // e^(−1.6e299): no slope left
}

TEST_CASE("a stiff string's dense eigenvalues agree with its crossings", "[stability][extreme]") {
  // A 2-DOF string with a bit of 4e-9 kg·m² on a spring of 3e8 N·m/rad rings at 2.7e8 rad/s
  // (valid: the limit is 1e150). Measured before: the unbalanced dense QR put a real eigenvalue
  // of +5.7e8 /s at δ = 1e-4, below the first crossing, and 242 of 341 slopes from 1e-6 to 1e4
  // had counts of unstable eigenvalues other than the crossings' (10 already at 2.7e7 rad/s).
  Params p = preset("reduced-scale", 2);
  p.inertias = {0.0686, 4e-9};
  p.stiffnesses = {3e8};
  p.dampings = {3.16e-9};
  p.top_damping = 0.00569;
  p.bit_damping = 0.000316;
  const auto crossings = critical_deltas(p);
  REQUIRE(!crossings.empty());
  for (double delta = 1e-6; delta < 1e4; delta *= 1.07) {
    bool near = false;
    for (const Crossing& c : crossings) near = near || std::fabs(c.delta - delta) < 1e-3 * delta;
    if (near) continue;
    int dense = 0;
    for (const auto& z : eigenvalues(p, delta)) dense += z.real() > 0;
    INFO("delta = " << delta);
    CHECK(dense == unstable_count(crossings, delta));
  }
}

namespace {

// Unstable eigenvalues of the dense Jacobian against the crossings' count, at slopes from
// 1e-2 to 1e4 away from the crossings and where no eigenvalue is too near the axis to count.
void dense_agrees_with_crossings(const Params& p, const std::vector<Crossing>& crossings) {
  for (double delta = 1e-2; delta < 1e4; delta *= 1.05) {
    bool near = false;
    for (const Crossing& c : crossings) near = near || std::fabs(c.delta - delta) < 1e-3 * delta;
    const auto ev = eigenvalues(p, delta);
    double scale = 1.0;
    for (const auto& z : ev) scale = std::max(scale, std::abs(z));
    int dense = 0;
    for (const auto& z : ev) {
      near = near || std::fabs(z.real()) < 1e-10 * scale;
      dense += z.real() > 0;
    }
    if (near) continue;
    INFO("delta = " << delta);
    CHECK(dense == unstable_count(crossings, delta));
  }
}

// The Hopf points of `crossings` within 1e-3 of `omega`.
int hopf_near(const std::vector<Crossing>& crossings, double omega) {
  return static_cast<int>(std::count_if(crossings.begin(), crossings.end(), [&](const Crossing& c) {
    return c.type == CrossingType::Hopf && std::fabs(c.frequency - omega) < 1e-3 * omega;
  }));
}

// A string of these inertias, springs and dampers, friction as the reduced-scale preset's;
// critical_deltas must find its Hopf points at `w1` and `w2` (a pair once lost), count
// `unstable` eigenvalues at `delta` (between them) and agree with the dense eigenvalues.
void finds_the_pair(std::vector<double> inertias, std::vector<double> stiffnesses, std::vector<double> dampings,
                    double top_damping, double bit_damping, double w1, double w2, double delta, int unstable) {
  Params p = preset("reduced-scale", static_cast<int>(inertias.size()));
  p.inertias = std::move(inertias);
  p.stiffnesses = std::move(stiffnesses);
  p.dampings = std::move(dampings);
  p.top_damping = top_damping;
  p.bit_damping = bit_damping;
  const auto crossings = critical_deltas(p);
  CHECK(hopf_near(crossings, w1) == 1);
  CHECK(hopf_near(crossings, w2) == 1);
  CHECK(unstable_count(crossings, delta) == unstable);
  dense_agrees_with_crossings(p, crossings);
}

}  // namespace

TEST_CASE("a pair of Hopf points closer than the frequency grid is found", "[stability][extreme]") {
  // Random strings with element dampings from 1e-3 to 1e3 times critical (found by comparing
  // with dense eigenvalues; 31 such strings in 12000 before). Measured before on this one: the
  // phase of Z_b dips through 0 at 4.4368 and 4.4491 rad/s and back inside one interval of the
  // search's grid, both ends on one side, and the pair was lost: 1 unstable eigenvalue counted
  // where there are 3 for 39.05 < δ < 51.56.
  finds_the_pair({0.2685607068690699, 0.5433872284147917, 0.116369023709137, 2.590494241623353, 6.757267046423591},
                 {3.7641177244566, 20.454021690757738, 9.032104663348365, 1.3989036030466184},
                 {0.009631269957358518, 1051.0750255889982, 0.005083489317476456, 810.9141443857354},
                 23.548018842019736, 5.135972244293806, 4.4368, 4.4491, 45.0, 3);
}

TEST_CASE("a narrow resonance's swing through 0 in a small phase is found", "[stability][extreme]") {
  // A string whose phase is small everywhere (below 0.06 rad from 4 to 4.35 rad/s) but for
  // one narrow resonance: it rises to 0.059 at 4.13 rad/s and falls through 0 at 4.158 and
  // back at 4.184 within one grid interval, not a local minimum among the grid's phases.
  // Measured before: that pair was lost, 4 unstable eigenvalues counted where there are 6 for
  // 359.1 < δ < 372.5.
  finds_the_pair({0.20167507995573897, 9.4405393208522, 1.9860507536438758, 2.328587328124708, 7.953001467912811,
                  0.15486049312010966, 0.37447072031177964, 0.24695084222056876, 0.7051775634048744, 4.670938240902948,
                  3.413175887626113, 0.411134806205964, 2.341284111555948, 1.2767854384007786, 5.4372218790019495,
                  0.18261621642774473, 0.8691469204787676, 0.1406866613751774, 9.224592886015593, 0.958406650107127,
                  5.125392169815665, 3.812995112987473, 1.1885638127600617, 0.5130080398560501, 2.7858966744866756},
                 {6.9605321640792654, 82.78063093042111, 7.001474757645239, 45.65666626521577, 5.4673230434481495,
                  1.0253126374240242, 23.901407812060594, 22.916469934377357, 42.30570472620405, 73.71284405961681,
                  3.0103723197122942, 10.064469675885062, 43.51956396437718, 17.94016323583256, 48.0715020574243,
                  9.125043858026846, 2.1978624859375127, 3.631572700000019, 2.599369767999425, 1.191283148869408,
                  42.45271634925981, 35.543497439663746, 7.514042703556018, 12.01937870139699},
                 {1734.6517945031778, 1866.6254761965272, 0.07781857127503185, 0.04801734005279419, 1.2335437146374408,
                  16.8187082819092, 0.4044076401616295, 0.3464174699765573, 0.5732586327178225, 5380.105374937323,
                  5.619415693957417, 2.5576898297814132, 6.497786403249785, 2.517378781192988, 2.8155395217336707,
                  515.4766691360131, 2.4042762958397956, 164.36226306062713, 25.965631808754576, 0.10887645569119996,
                  0.03036067859880153, 291.30144364176414, 14.484889877646403, 0.029828780575492063},
                 132.1844455321466, 353.2834780149066, 4.158, 4.1837, 364.8, 6);
}
