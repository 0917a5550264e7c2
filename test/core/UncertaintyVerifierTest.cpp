// The verifier under bounded anchor and tool-point uncertainty on the reference robot (docs/uncertainty.md):
// max-error brackets, SAFE / UNSAFE / uncertainty-sensitive verdicts checked independently, strategy (b) (bisecting
// the geometry), the faces, nominal invariance, a singular workspace; regression test for a problem once found.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "MpfrGough.hpp"
#include "TestRobots.hpp"
#include "UncertaintyFixtures.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using namespace pkm_accuracy::test;  // the MPFR reference toolkit (MpfrGough.hpp)
using verify::UndecidedReason;
using verify::Verdict;
using namespace pkm_accuracy::test::uncertainty;  // the uncertain robot (UncertaintyFixtures.hpp)

// =====================================================================================================================
// Evidence on the reference robot
// =====================================================================================================================

namespace {

/// Smallest f_k over the geometries sampled at pose q (worst vertices for the minimum included).
double sampledMinimum(const Uncertain& u, const DVec& q, int k, std::mt19937_64& rng) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Geometry& g : sampleGeometries(u, q, rng, true)) lowest = std::min(lowest, u.error(g, q)[k]);
  for (int s = 0; s < 20; ++s)
    lowest = std::min(lowest, u.error(s % 2 ? u.randomVertex(rng) : u.randomInterior(rng), q)[k]);
  return lowest;
}

Geometry toGeometry(const std::vector<double>& v) { return Geometry(v.begin(), v.end()); }

/// Every value of a reported geometry is admissible as given: g_p in [nominal_p - h_p, nominal_p + h_p] as real
/// numbers (not merely in the model's ranges, which are rounded outward).
bool admissible(const Uncertain& u, const std::vector<double>& g) {
  if (static_cast<int>(g.size()) != u.count()) return false;
  for (int p = 0; p < u.count(); ++p)
    if (!test::withinHalfWidth(g[p], u.nominal[p], u.coords[p].half)) return false;
  return true;
}

/// Checks a max-error result against independent evaluations: converged brackets of the sampled maxima, and the
/// lower bound attained at (argmax, argmax geometry) in double and MPFR, or, when no geometry is given (the bound
/// holds for every geometry), at every sampled geometry including the minimising vertices.
void checkMaxError(const verify::VerifierResult& r, const Uncertain& u, const IVec& box, const Sampled& s, double alpha,
                   std::mt19937_64& rng) {
  EXPECT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.max_lower.size(), 6);
  ASSERT_EQ(r.max_upper.size(), 6);
  ASSERT_EQ(r.max_argmax.size(), 6u);
  ASSERT_EQ(r.max_argmax_geometry.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_GE(r.max_upper[k], s.max[k]) << k;
    EXPECT_LE(r.max_lower[k], r.max_upper[k]) << k;
    EXPECT_LE(r.max_upper[k] - r.max_lower[k], alpha * r.max_lower[k] * (1 + 1e-9)) << k;
    ASSERT_EQ(r.max_argmax[k].size(), 6) << k;
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(box[i].contains(r.max_argmax[k][i])) << k;
    const std::vector<double>& g = r.max_argmax_geometry[k];
    if (!g.empty()) {
      ASSERT_TRUE(admissible(u, g)) << k;
      EXPECT_GE(u.error(toGeometry(g), r.max_argmax[k])[k], r.max_lower[k] * (1 - 1e-9)) << k;
      EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(u.at(toGeometry(g)), r.max_argmax[k])[k], r.max_lower[k])) << k;
    } else {
      EXPECT_GE(sampledMinimum(u, r.max_argmax[k], k, rng), r.max_lower[k] * (1 - 1e-9)) << k;
    }
  }
}

/// Checks an uncertainty-sensitive pose independently: inside the box, its failing geometry admissible and above
/// the threshold (double and MPFR, and at least the certified failing_lower), its passing geometry (if any) below.
void checkSensitivePose(const verify::SensitivePose& sp, const Uncertain& u, const IVec& box, const DVec& thresholds) {
  const int k = sp.component;
  ASSERT_GE(k, 0);
  ASSERT_LT(k, 6);
  ASSERT_EQ(sp.point.size(), 6);
  ASSERT_EQ(sp.pose.size(), 6);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(box[i].contains(sp.point[i]));
    EXPECT_TRUE(sp.pose[i].contains(sp.point[i]));
    EXPECT_TRUE(sp.region[i].contains(sp.point[i]));
  }
  ASSERT_TRUE(admissible(u, sp.failing_geometry));
  EXPECT_GT(sp.failing_lower, thresholds[k]);
  EXPECT_GT(u.error(toGeometry(sp.failing_geometry), sp.point)[k], thresholds[k]) << where(sp.point);
  EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(u.at(toGeometry(sp.failing_geometry)), sp.point)[k], sp.failing_lower));
  if (!sp.passing_geometry.empty()) {
    ASSERT_TRUE(admissible(u, sp.passing_geometry));
    const DVec fp = u.error(toGeometry(sp.passing_geometry), sp.point);
    EXPECT_LE(fp[k], thresholds[k]) << where(sp.point);
    EXPECT_TRUE(mpLessEqual(mpfrWorstError(u.at(toGeometry(sp.passing_geometry)), sp.point)[k], sp.passing_upper));
    if (sp.passes_all) {
      for (int j = 0; j < 6; ++j) EXPECT_LE(fp[j], thresholds[j]) << j;
    }
  }
}

/// Checks an UNSAFE witness independently: inside the box, and above the threshold for every sampled geometry
/// (the minimising vertices included); every component's certified lower bound at most its sampled minimum.
void checkWitness(const verify::VerifierResult& r, const Uncertain& u, const IVec& box, const DVec& thresholds,
                  std::mt19937_64& rng) {
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  const int k = r.witness_component;
  ASSERT_GE(k, 0);
  ASSERT_EQ(r.witness.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(box[i].contains(r.witness[i]));
  EXPECT_GT(r.witness_lower_bound, thresholds[k]);
  EXPECT_GT(sampledMinimum(u, r.witness, k, rng), thresholds[k]) << where(r.witness);
  ASSERT_EQ(r.witness_error_lower.size(), 6);
  for (int j = 0; j < 6; ++j) {
    EXPECT_LE(r.witness_error_lower[j], sampledMinimum(u, r.witness, j, rng) * (1 + 1e-9)) << j;
  }
}

}  // namespace

/// The reference evidence on a corner of the paper workspace (see the TESTs below), with the combined geometry form
/// or the decomposed one (SearchTuning::decompose_geometry).
void checkReferenceAnswers(bool decomposed) {
  SCOPED_TRACE(decomposed ? "decomposed" : "combined");
  const io::RobotFile rf = test::ref6File();
  const IVec box = cornerBox(1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  int cases = 0;
  for (const double h : rf.anchor_uncertainty_cases) {
    if (!(h > 0.0)) continue;
    ++cases;
    SCOPED_TRACE("h = " + std::to_string(h));
    const Uncertain u(withUncertainty(h));
    const model::GoughPlatform robot(u.geometry);
    const Sampled s = sample(u, box, 600, 707);
    std::mt19937_64 rng(708);

    // ---- max-error mode: brackets, and the lower bound attained at (argmax, argmax geometry) ----
    // alpha: 2% at h = 0.5 mm. At h = 1 mm the bound of a single pose exceeds the worst geometry by up to ~6%
    // (second-order remainder, see SecondOrderBoundsEveryAdmissibleGeometryOnRandomBoxes) and 2% (or 5%) does not
    // converge within 15 s even with strategy (b) (reported), so 10% there.
    verify::VerifierOptions o;
    o.tuning.decompose_geometry = decomposed;
    o.mode = verify::Mode::MaxError;
    o.alpha = h <= 0.0005 ? 0.02 : 0.1;
    o.time_limit_s = 30.0;  // a safety net: both converge in < 0.2 s
    checkMaxError(verify::Verifier::run(robot, ws, o), u, box, s, o.alpha, rng);

    // ---- verify mode: 10% above the sampled maxima (over poses and geometries) is SAFE ----
    verify::VerifierOptions v;
    v.tuning.decompose_geometry = decomposed;
    v.thresholds = s.max * 1.10;
    const auto safe = verify::Verifier::run(robot, ws, v);
    EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
    EXPECT_EQ(safe.undecided_box_count, 0u);
    EXPECT_EQ(safe.sensitive_count, 0u);
    EXPECT_NEAR(safe.stats.safe_fraction, 1.0, 1e-9);

    // ---- 5% below: UNSAFE (witness for every geometry) or UNDECIDED (uncertainty_sensitive) ----
    v.thresholds = s.max * 0.95;
    const auto below = verify::Verifier::run(robot, ws, v);
    ASSERT_NE(below.verdict, Verdict::Safe) << below.message;
    if (below.verdict == Verdict::Unsafe) {
      checkWitness(below, u, box, v.thresholds, rng);
    } else {
      ASSERT_EQ(below.reason, UndecidedReason::UncertaintySensitive) << below.message;
      EXPECT_EQ(toString(below.reason), "uncertainty_sensitive");
      ASSERT_GE(below.sensitive_count, 1u);
      ASSERT_FALSE(below.sensitive.empty());
      checkSensitivePose(below.sensitive.front(), u, box, v.thresholds);
    }
    // Which one our own sampling says. UNSAFE needs a pose where f_k exceeds for every geometry, certified by
    // errorAtPose whose lower end is below the true minimum over the geometries by a second-order amount (measured
    // <= 1.5% at h = 0.5 mm, <= 8% at 1 mm). So: a box corner (the pre-sampling grid holds every corner) exceeding
    // for every sampled geometry by more than 100 h (5%, 10%) makes UNSAFE certain; no sampled pose (all corners,
    // with vertex searches for the extremes, and 600 random poses) within 2% of exceeding for every sampled geometry
    // makes it impossible in practice, so the answer must be uncertainty_sensitive.
    bool cornerWitness = false, noWitness = true;
    for (int k = 0; k < 6; ++k) {
      const DVec& q = s.argmaxOfMin[k];
      bool corner = true;
      for (int i = 0; i < 6; ++i) corner = corner && (q[i] == box[i].lower() || q[i] == box[i].upper());
      if (corner && s.maxOfMin[k] > (1.0 + 100.0 * h) * v.thresholds[k]) cornerWitness = true;
      if (s.maxOfMin[k] > 0.98 * v.thresholds[k]) noWitness = false;
    }
    std::cout << "[ info     ] h=" << h << ": 5% below -> " << toString(below.verdict) << " (" << toString(below.reason)
              << "); sampled (max over poses of min over geometries) / (max over both):";
    for (int k = 0; k < 6; ++k) std::cout << " " << s.maxOfMin[k] / s.max[k];
    std::cout << "\n";
    EXPECT_TRUE(cornerWitness || noWitness) << "the sampling does not make the expected answer clear";
    if (cornerWitness) {
      EXPECT_EQ(below.verdict, Verdict::Unsafe) << below.message;
    }
    if (noWitness) {
      EXPECT_EQ(below.reason, UndecidedReason::UncertaintySensitive) << below.message;
    }

    // ---- clearly lower thresholds (30% below): UNSAFE with a witness checked for every sampled geometry ----
    v.thresholds = s.max * 0.70;
    checkWitness(verify::Verifier::run(robot, ws, v), u, box, v.thresholds, rng);

    // ---- the same without stopping at the first evidence (a box budget): every recorded sensitive pose checked,
    // whole boxes certified unsafe for every geometry, volume fractions adding up ----
    v.stop_at_first_witness = false;
    v.max_boxes = 2000;
    const auto all = verify::Verifier::run(robot, ws, v);
    checkWitness(all, u, box, v.thresholds, rng);
    EXPECT_GT(all.stats.unsafe_fraction, 0.0);
    EXPECT_NEAR(all.stats.safe_fraction + all.stats.unsafe_fraction + all.stats.undecided_fraction, 1.0, 1e-9);
    v.thresholds = s.max * 0.95;
    const auto sensitive = verify::Verifier::run(robot, ws, v);
    EXPECT_EQ(sensitive.reason, UndecidedReason::UncertaintySensitive) << sensitive.message;
    EXPECT_GE(sensitive.sensitive_count, sensitive.sensitive.size());
    EXPECT_GT(sensitive.sensitive.size(), 1u);
    for (std::size_t i = 0; i < sensitive.sensitive.size() && i < 25; ++i) {
      checkSensitivePose(sensitive.sensitive[i], u, box, v.thresholds);
    }
    EXPECT_NEAR(sensitive.stats.safe_fraction + sensitive.stats.unsafe_fraction + sensitive.stats.undecided_fraction,
                1.0, 1e-9);
  }
  EXPECT_EQ(cases, 2);
}

TEST(UncertaintyVerifier, MaxErrorAndVerdictsOnTheReferenceRobot) { checkReferenceAnswers(false); }

// SearchTuning::decompose_geometry: the same answers (brackets that hold and close, SAFE 10% above the sampled
// maxima, UNSAFE or uncertainty_sensitive as the sampling says 5% below, witnesses for every geometry 30% below).
TEST(UncertaintyVerifier, DecomposedGeometryFormKeepsTheReferenceAnswers) { checkReferenceAnswers(true); }

// Verify mode without stopping at the first witness and without pre-sampling, on a box where every pose exceeds every
// threshold for every admissible geometry (half the smallest nominal error at its corners and centre): the root box's
// enclosure certifies that at once (ErrorBounds::lower). The verdict must be UNSAFE with a witness in the box that
// exceeds for every sampled geometry, not SAFE with the volume counted as unsafe.
TEST(UncertaintyVerifier, BoxCertifiedUnsafeWithoutPresamplingGivesAWitness) {
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 256.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  DVec smallest = DVec::Constant(6, std::numeric_limits<double>::infinity());
  for (int corner = 0; corner <= 64; ++corner) {
    DVec q(6);
    for (int i = 0; i < 6; ++i)
      q[i] = corner == 64 ? box[i].mid() : ((corner >> i) & 1 ? box[i].upper() : box[i].lower());
    smallest = smallest.cwiseMin(u.error(u.nominal, q));
  }
  std::mt19937_64 rng(1201);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    verify::VerifierOptions o;
    o.thresholds = 0.5 * smallest;
    o.presample_points = 0;
    o.stop_at_first_witness = false;
    o.threads = threads;
    const auto r = verify::Verifier::run(robot, ws, o);
    checkWitness(r, u, box, o.thresholds, rng);
    EXPECT_GT(r.stats.unsafe_fraction, 0.0);
    EXPECT_NEAR(r.stats.safe_fraction + r.stats.unsafe_fraction + r.stats.undecided_fraction, 1.0, 1e-9);
  }
}

// The geometries a result reports (max-error argmax geometries; sensitive poses' failing and passing geometries) lie
// in the admissible set as given, nominal +- h as real numbers (the model's ranges are rounded outward, their ends an
// ulp outside), and each max-error lower bound is attained there: a plain double evaluation at (argmax, geometry)
// reproduces it to round-off.
TEST(UncertaintyVerifier, ReportedGeometriesAreAdmissibleExactlyAndAttainTheirBounds) {
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.02;
  o.time_limit_s = 30.0;  // a safety net
  const auto r = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(r.max_argmax_geometry.size(), 6u);
  int named = 0;
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE("component " + std::to_string(k));
    const std::vector<double>& g = r.max_argmax_geometry[k];
    if (g.empty()) continue;  // (the bound holds for every geometry)
    ++named;
    ASSERT_EQ(static_cast<int>(g.size()), u.count());
    for (int p = 0; p < u.count(); ++p) {
      EXPECT_TRUE(test::withinHalfWidth(g[p], u.nominal[p], u.coords[p].half))
          << robot.geometryParameterName(p) << " = " << g[p] << " outside " << u.nominal[p] << " +- "
          << u.coords[p].half;
    }
    const double value = u.error(g, r.max_argmax[k])[k];
    EXPECT_GE(value, r.max_lower[k] * (1.0 - 1e-12));
    EXPECT_LE(value, r.max_lower[k] * (1.0 + 1e-9));
  }
  EXPECT_GE(named, 1);

  verify::VerifierOptions v;
  v.thresholds = 0.95 * r.max_lower;
  v.stop_at_first_witness = false;
  v.max_boxes = 300;
  const auto sensitive = verify::Verifier::run(robot, ws, v);
  ASSERT_GE(sensitive.sensitive.size(), 1u) << sensitive.message;
  for (const verify::SensitivePose& s : sensitive.sensitive) {
    EXPECT_TRUE(admissible(u, s.failing_geometry));
    EXPECT_TRUE(s.passing_geometry.empty() || admissible(u, s.passing_geometry));
  }
}

// =====================================================================================================================
// Strategy (b): bisecting the geometry
// =====================================================================================================================

TEST(UncertaintyVerifier, StrategyBSwitchesOnStallsAndKeepsTheVerdict) {
  // h = 1 mm on the 1/32 corner box. At +0.4% of the sampled maxima strategy (a) alone does not conclude within 3 000
  // boxes (the plain bound stays above the worst geometry by its second-order geometry remainder), while stalled paths
  // (stall_levels = 1) that switch to bisecting the geometry prove SAFE (measured: 81 boxes, 18 geometry splits; at
  // +0.75% strategy (a) settles the box in 5 boxes, at +0.2% neither within 2e4). 1% below the maxima every mode must
  // find the same uncertainty-sensitive answer. The faces step, which stalled paths take first, is off here (its own
  // tests are in section 7).
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 32.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 808);
  for (const double factor : {1.004, 0.99}) {
    SCOPED_TRACE("thresholds x " + std::to_string(factor));
    verify::VerifierOptions o;
    o.thresholds = s.max * factor;
    o.threads = 1;
    o.max_boxes = 3000;
    o.tuning.faces = false;
    o.geometry_splitting = verify::GeometrySplitting::Never;
    const auto never = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(never.stats.geometry_switches, 0u);
    EXPECT_EQ(never.stats.geometry_splits, 0u);
    o.max_boxes = 20000;  // a safety net
    o.geometry_splitting = verify::GeometrySplitting::Auto;
    o.tuning.stall_levels = 1;
    const auto autoRun = verify::Verifier::run(robot, ws, o);
    std::cout << "[ info     ] x" << factor << ": strategy (a) " << never.stats.boxes << " boxes, auto "
              << autoRun.stats.boxes << " boxes, " << autoRun.stats.geometry_switches << " switches, "
              << autoRun.stats.geometry_splits << " geometry splits\n";
    EXPECT_GE(autoRun.stats.geometry_splits, autoRun.stats.geometry_switches);
    // Threads: same verdict.
    o.threads = 2;
    const auto two = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(two.verdict, autoRun.verdict) << two.message;
    EXPECT_EQ(two.reason, autoRun.reason);
    EXPECT_EQ(two.stats.threads, 2);
    if (factor > 1.0) {
      EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
      EXPECT_EQ(never.reason, UndecidedReason::BoxBudget) << never.message;
      EXPECT_EQ(autoRun.verdict, Verdict::Safe) << autoRun.message;
      EXPECT_GT(autoRun.stats.geometry_switches, 0u);
      EXPECT_EQ(autoRun.undecided_box_count, 0u);
      EXPECT_NEAR(autoRun.stats.safe_fraction, 1.0, 1e-9);  // the geometry halves' volumes add up
    } else {
      // The sampled maximum is a real error value (a pose and an admissible geometry) above the thresholds: no
      // mode may prove SAFE, and no pose exceeds for every sampled geometry (max-of-min is ~85% of the max).
      EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
      EXPECT_EQ(never.reason, UndecidedReason::UncertaintySensitive) << never.message;
      EXPECT_EQ(autoRun.verdict, never.verdict) << autoRun.message;
      EXPECT_EQ(autoRun.reason, never.reason);
      o.threads = 1;
      o.geometry_splitting = verify::GeometrySplitting::Always;
      o.tuning.stall_levels = 0;
      const auto always = verify::Verifier::run(robot, ws, o);
      EXPECT_EQ(always.verdict, never.verdict) << always.message;
      EXPECT_EQ(always.reason, never.reason);
    }
  }

  // A tiny box budget: the undecided records searched on a geometry sub-box carry sub-intervals of the ranges (at
  // +0.4% with 60 boxes, where the run above needs 81).
  verify::VerifierOptions o;
  o.thresholds = s.max * 1.004;
  o.geometry_splitting = verify::GeometrySplitting::Auto;
  o.tuning.faces = false;
  o.tuning.stall_levels = 1;
  o.threads = 1;
  o.max_boxes = 60;
  o.presample_points = 0;
  const auto partial = verify::Verifier::run(robot, ws, o);
  std::cout << "[ info     ] x1.004, 60 boxes: " << partial.stats.geometry_switches << " switches, "
            << partial.undecided_boxes.size() << " undecided boxes listed\n";
  EXPECT_EQ(partial.verdict, Verdict::Undecided);
  EXPECT_EQ(partial.reason, UndecidedReason::BoxBudget);
  EXPECT_NEAR(partial.stats.safe_fraction + partial.stats.undecided_fraction + partial.stats.outside_fraction, 1.0,
              1e-9);
  EXPECT_GT(partial.stats.geometry_switches, 0u);
  int withGeometry = 0;
  for (const verify::BoxRecord& b : partial.undecided_boxes) {
    if (b.geometry.empty()) continue;
    ++withGeometry;
    ASSERT_EQ(static_cast<int>(b.geometry.size()), robot.geometryParameterCount());
    bool narrower = false;
    for (int p = 0; p < robot.geometryParameterCount(); ++p) {
      const Interval full = robot.geometryParameterRange(p);
      EXPECT_TRUE(b.geometry[p].isSubsetOf(full)) << p;
      EXPECT_FALSE(b.geometry[p].isEmpty()) << p;
      narrower = narrower || b.geometry[p].width() < full.width();
    }
    EXPECT_TRUE(narrower);
  }
  EXPECT_GT(withGeometry, 0);
}

TEST(UncertaintyVerifier, PresamplingCertifiesTheGridsWorstPointsOverEveryGeometry) {
  // +-0.5 mm on the whole paper workspace, thresholds 1% below the sampled maxima over poses and geometries (at
  // workspace corners, which the sampling grid contains). At the centre geometry the errors stay 5-8% below those
  // maxima, so the grid's double screening alone certifies no point; the grid's worst point of each component,
  // certified over every geometry, shows an uncertainty-sensitive pose before any box is enclosed (without it the
  // search ran out of a 60 s budget).
  const Uncertain u(withUncertainty(0.0005));
  const model::GoughPlatform robot(u.geometry);
  const io::RobotFile rf = test::ref6File();
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const Sampled s = sample(u, ws.initialBox(), 20, 909);
  verify::VerifierOptions o;
  o.thresholds = s.max * 0.99;
  o.threads = 1;
  o.time_limit_s = 20.0;  // a safety net
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(r.verdict, Verdict::Undecided) << r.message;
  EXPECT_EQ(r.reason, UndecidedReason::UncertaintySensitive) << r.message;
  EXPECT_EQ(r.stats.boxes, 0u);
  ASSERT_GE(r.sensitive_count, 1u);
  ASSERT_FALSE(r.sensitive.empty());
  checkSensitivePose(r.sensitive.front(), u, ws.initialBox(), o.thresholds);
}

TEST(UncertaintyVerifier, StrategyBProvesWhatIntervalCoefficientsCannot) {
  // h = 1 mm on the 1/128 corner box at +0.4% of the sampled maxima: the single-pose bound exceeds the worst
  // geometry by more than that at the corner (second-order remainder), so strategy (a) alone cannot conclude;
  // bisecting the geometry does (the faces off), and so do the faces. (At +0.75% strategy (a) settles the box at
  // once.)
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = cornerBox(1.0 / 128.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 809);
  std::mt19937_64 rng(810);
  verify::VerifierOptions o;
  o.thresholds = s.max * 1.004;
  o.threads = 1;
  o.tuning.faces = false;
  o.geometry_splitting = verify::GeometrySplitting::Never;
  o.max_boxes = 3000;
  const auto never = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(never.verdict, Verdict::Undecided) << never.message;
  EXPECT_EQ(never.reason, UndecidedReason::BoxBudget);
  // The faces alone (no geometry bisection, stalled paths after 1 level): SAFE.
  o.tuning.faces = true;
  o.tuning.stall_levels = 1;
  const auto faced = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(faced.verdict, Verdict::Safe) << faced.message;
  EXPECT_GT(faced.stats.face_switches, 0u);
  EXPECT_EQ(faced.stats.geometry_splits, 0u);
  std::cout << "[ info     ] faces, no geometry bisection: " << faced.stats.boxes << " boxes\n";
  o.tuning.faces = false;
  o.tuning.stall_levels = 0;
  o.max_boxes = 20000;  // a safety net: a few hundred boxes are measured (Always) and a few dozen (Auto)
  for (const auto mode : {verify::GeometrySplitting::Always, verify::GeometrySplitting::Auto}) {
    o.geometry_splitting = mode;
    o.tuning.stall_levels = mode == verify::GeometrySplitting::Auto ? 1 : 0;
    for (const int threads : {1, 2}) {
      o.threads = threads;
      const auto r = verify::Verifier::run(robot, ws, o);
      EXPECT_EQ(r.verdict, Verdict::Safe) << r.message;
      EXPECT_GT(r.stats.geometry_splits, 0u);
      EXPECT_NEAR(r.stats.safe_fraction, 1.0, 1e-9);
    }
  }
  // Max-error mode with geometry bisection: brackets checked independently (alpha 0.5%: at 1% the bounds converge
  // without any geometry split; at 0.3% not within 20 s).
  verify::VerifierOptions m;
  m.mode = verify::Mode::MaxError;
  m.alpha = 0.005;
  m.geometry_splitting = verify::GeometrySplitting::Always;
  m.tuning.faces = false;
  m.time_limit_s = 20.0;
  const auto r = verify::Verifier::run(robot, ws, m);
  EXPECT_GT(r.stats.geometry_splits, 0u);
  checkMaxError(r, u, box, s, m.alpha, rng);
}

// =====================================================================================================================
// Nominal robot: the geometry options change nothing
// =====================================================================================================================

TEST(UncertaintyVerifier, NominalRobotIgnoresTheGeometryOptionsBitForBit) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform robot(withUncertainty(0.0));
  ASSERT_EQ(robot.geometryParameterCount(), 0);
  const IVec box = test::centredSubBox(rf.workspaces.at("paper").initialBox(), 1.0 / 32.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Uncertain nominal(withUncertainty(0.0));
  const Sampled s = sample(nominal, box, 200, 909);
  auto same = [](const verify::VerifierResult& a, const verify::VerifierResult& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(a.verdict, b.verdict);
    EXPECT_EQ(a.reason, b.reason);
    EXPECT_EQ(a.message, b.message);
    EXPECT_EQ(a.stats.boxes, b.stats.boxes);
    EXPECT_EQ(a.stats.max_depth, b.stats.max_depth);
    EXPECT_EQ(a.stats.safe_fraction, b.stats.safe_fraction);
    EXPECT_EQ(a.stats.undecided_fraction, b.stats.undecided_fraction);
    EXPECT_EQ(a.stats.geometry_switches, 0u);
    EXPECT_EQ(b.stats.geometry_switches, 0u);
    EXPECT_EQ(a.stats.geometry_splits, 0u);
    EXPECT_EQ(b.stats.geometry_splits, 0u);
    EXPECT_EQ(a.sensitive_count, 0u);
    EXPECT_EQ(b.sensitive_count, 0u);
    EXPECT_EQ(a.undecided_box_count, b.undecided_box_count);
    ASSERT_EQ(a.witness.size(), b.witness.size());
    for (int i = 0; i < a.witness.size(); ++i) EXPECT_EQ(a.witness[i], b.witness[i]);
    EXPECT_EQ(a.witness_component, b.witness_component);
    EXPECT_EQ(a.witness_lower_bound, b.witness_lower_bound);
    ASSERT_EQ(a.max_lower.size(), b.max_lower.size());
    for (int k = 0; k < a.max_lower.size(); ++k) {
      EXPECT_EQ(a.max_lower[k], b.max_lower[k]);
      EXPECT_EQ(a.max_upper[k], b.max_upper[k]);
      EXPECT_EQ(a.max_argmax[k], b.max_argmax[k]);
    }
    EXPECT_TRUE(a.max_argmax_geometry.empty() || a.max_argmax_geometry == b.max_argmax_geometry);
    ASSERT_EQ(a.undecided_boxes.size(), b.undecided_boxes.size());
    for (std::size_t i = 0; i < a.undecided_boxes.size(); ++i) {
      EXPECT_TRUE(a.undecided_boxes[i].geometry.empty());
      EXPECT_TRUE(b.undecided_boxes[i].geometry.empty());
    }
  };
  for (const double factor : {1.10, 0.95, 0.0}) {
    verify::VerifierOptions plain;
    plain.threads = 1;
    if (factor > 0.0) {
      plain.thresholds = s.max * factor;
    } else {
      plain.mode = verify::Mode::MaxError;
      plain.alpha = 0.05;
    }
    const auto reference = verify::Verifier::run(robot, ws, plain);
    if (factor > 1.0) {
      EXPECT_EQ(reference.verdict, Verdict::Safe);
    }
    if (factor > 0.0 && factor < 1.0) {
      EXPECT_EQ(reference.verdict, Verdict::Unsafe);
    }
    for (const auto mode :
         {verify::GeometrySplitting::Never, verify::GeometrySplitting::Always, verify::GeometrySplitting::Auto}) {
      for (const int stall : {0, 1, 5}) {
        verify::VerifierOptions o = plain;
        o.geometry_splitting = mode;
        o.tuning.stall_levels = stall;
        same(reference, verify::Verifier::run(robot, ws, o),
             "factor " + std::to_string(factor) + " mode " + std::to_string(static_cast<int>(mode)) + " stall " +
                 std::to_string(stall));
      }
    }
  }
}

TEST(UncertaintyRegression, SmearBisectionProvesSafeWhereItOnceStalled) {
  // h = 1 mm, centred 1/16 paper sub-box, thresholds 1.10 x sampled maxima: Smear bisection is still UNDECIDED
  // after thousands of boxes (depth 36+) while LargestScaledWidth proves SAFE in 167 boxes, and thresholds 1.08 x
  // (tighter!) are proven SAFE in 31 boxes. The stuck boxes are ones where the geometry form falls back to interval
  // coefficients (UncertaintyRegression.ApplySuccessDoesNotDependOnTheRightHandSide): a bound ~10% looser, zero
  // geometry smear, and a pose smear that misses the variable (pitch) whose bisection removes 11% of the bound.
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = test::centredSubBox(test::ref6File().workspaces.at("paper").initialBox(), 1.0 / 16.0);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 100, 808);
  verify::VerifierOptions o;
  o.threads = 1;
  o.max_boxes = 5000;
  o.thresholds = s.max * 1.08;
  EXPECT_EQ(verify::Verifier::run(robot, ws, o).verdict, Verdict::Safe);
  o.tuning.bisection = verify::Bisection::LargestScaledWidth;
  o.thresholds = s.max * 1.10;
  EXPECT_EQ(verify::Verifier::run(robot, ws, o).verdict, Verdict::Safe);
  o.tuning.bisection = verify::Bisection::Smear;
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(r.verdict, Verdict::Safe) << r.message;
}

TEST(UncertaintyVerifier, FacesCertifyMarginsBelowTheFirstOrderRemainder) {
  // h = 1 mm on a small box at the pitch corner, thresholds 0.2% above the sampled maximum of pitch (the others
  // out of reach): the plain geometry-aware bound stays ~0.4% above the maximum there whatever the pose box (its
  // second-order geometry remainder); stalled paths switch to the faces, whose bounds reach the worst vertex: SAFE.
  // 0.5% below the sampled maximum it must not be SAFE (the sampled maximum is attained at an admissible geometry).
  // Both geometry forms (the decomposed default switches stalled paths to the combined form for the faces). Measured
  // (+0.2%): see the info line; (+0.5%): 31 boxes each (255 with 6 stall levels instead of the default 3); with a 10%
  // progress step in the stall test the decomposed default's paths reach the faces only at the precision limit
  // (UNDECIDED after 200 001 boxes) and the combined form needs 2 439.
  const Uncertain u(withUncertainty(0.001));
  const model::GoughPlatform robot(u.geometry);
  const IVec box = pitchCorner(0.0001, 0.00015);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  const Sampled s = sample(u, box, 50, 711);
  for (const bool decomposed : {true, false}) {
    SCOPED_TRACE(decomposed ? "decomposed" : "combined");
    verify::VerifierOptions o;
    o.threads = 2;
    o.max_boxes = 20000;
    o.tuning.decompose_geometry = decomposed;
    o.thresholds = DVec::Constant(6, 1.0);
    o.thresholds[4] = s.max[4] * 1.002;
    const auto safe = verify::Verifier::run(robot, ws, o);
    EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
    EXPECT_GT(safe.stats.face_switches, 0u);
    EXPECT_GT(safe.stats.face_boxes, 0u);
    std::cout << "[ info     ] " << (decomposed ? "decomposed" : "combined") << ", SAFE at +0.2%: " << safe.stats.boxes
              << " boxes, " << safe.stats.face_switches << " face switches\n";
    o.thresholds[4] = s.max[4] * 0.995;
    const auto below = verify::Verifier::run(robot, ws, o);
    EXPECT_NE(below.verdict, Verdict::Safe) << below.message;
  }
}

// The tool point's box at +-5 mm on a 2 cm box: max-error to 2% converges in a few boxes (with the tool point as a
// first-order parameter: not within 57 000 boxes and 10 s, every component's bracket 2-5% wide), and the bracket
// holds against the exact-tool robots at the tool vertices (3^6 poses each) and at the argmax geometries.
TEST(UncertaintyVerifier, ToolPointUncertaintyConvergesAtItsVertices) {
  model::GoughGeometry g = test::ref6File().geometry;
  g.tool_point_halfwidth = Eigen::Vector3d::Constant(0.005);
  const Uncertain u(g);
  ASSERT_EQ(u.count(), 3);
  const model::GoughPlatform robot(u.geometry);
  const double ranges[12] = {-0.01, 0.01, -0.01, 0.01, 0.47, 0.48, -0.01, 0.01, -0.01, 0.01, -0.01, 0.01};
  IVec box(6);
  for (int i = 0; i < 6; ++i) box[i] = Interval(ranges[2 * i], ranges[2 * i + 1]);
  const domain::Workspace ws = domain::Workspace::fromRanges(test::toRanges(box));
  verify::VerifierOptions o;
  o.threads = 2;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.02;
  o.max_boxes = 5000;
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_LE(r.stats.boxes, 16u);
  DVec sampled = DVec::Zero(6);
  for (int v = 0; v < 8; ++v) {
    Geometry tool(3);
    for (int a = 0; a < 3; ++a) tool[a] = ((v >> a) & 1) ? u.hi[a] : u.lo[a];
    const model::GoughPlatform at(u.at(tool));
    for (int idx = 0; idx < 729; ++idx) {
      DVec q(6);
      for (int i = 0, rest = idx; i < 6; ++i, rest /= 3) q[i] = box[i].lower() + 0.5 * (rest % 3) * box[i].width();
      sampled = sampled.cwiseMax(at.worstErrorAt(q));
    }
  }
  ASSERT_EQ(r.max_upper.size(), 6);
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE("k=" + std::to_string(k));
    EXPECT_GE(r.max_upper[k], sampled[k]);
    // (An empty argmax geometry: the lower bound holds for every geometry, the nominal one and the vertices too.)
    std::vector<Geometry> geometries = {r.max_argmax_geometry[k]};
    if (geometries[0].empty()) geometries = {u.nominal, u.lo, u.hi};
    for (const Geometry& geo : geometries) EXPECT_GE(u.error(geo, r.max_argmax[k])[k], r.max_lower[k] * (1 - 1e-12));
  }
}

TEST(UncertaintyVerify, SingularWorkspaceThroughTheNominalGeometry) {
  // paper_40deg at +-1 mm: det J^-1 changes sign over the workspace for the nominal geometry (not certifiably for
  // every admissible one at the corner where it is positive), which is enough for the maximum over poses and
  // geometries to be unbounded. The signs are checked in MPFR with the nominal geometry.
  const model::GoughPlatform robot(withUncertainty(0.001));
  const model::GoughGeometry nominal = test::ref6File().geometry;
  const domain::Workspace& ws = test::ref6File().workspaces.at("paper_40deg");
  verify::VerifierOptions o;
  o.threads = 2;
  o.mode = verify::Mode::MaxError;
  o.time_limit_s = 20.0;
  const auto r = verify::Verifier::run(robot, ws, o);
  ASSERT_TRUE(r.singular) << r.message;
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.stats.boxes, 1000u);
  std::vector<double> gc, gh;
  centresAndHalfWidths(robot, gc, gh);
  EXPECT_EQ(r.singular_geometry, gc);
  const int a = test::mpDeterminantSign(test::mpInverseJacobian(nominal, r.singular_from));
  const int b = test::mpDeterminantSign(test::mpInverseJacobian(nominal, r.singular_to));
  EXPECT_NE(a, 0);
  EXPECT_EQ(a, -b);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(r.max_upper[k], std::numeric_limits<double>::infinity()) << k;

  // Verify mode: not UNSAFE (not shown for every geometry), but SAFE is ruled out at once by an uncertainty-sensitive
  // pose next to the nominal geometry's singular pose, whose error exceeds thresholds of 1 km (checked in MPFR).
  o.mode = verify::Mode::Verify;
  o.thresholds = DVec::Constant(6, 1e3);
  const auto v = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(v.verdict, verify::Verdict::Undecided) << v.message;
  EXPECT_EQ(v.reason, verify::UndecidedReason::UncertaintySensitive) << v.message;
  EXPECT_LT(v.stats.boxes, 1000u);
  ASSERT_FALSE(v.sensitive.empty());
  const verify::SensitivePose& s = v.sensitive.front();
  EXPECT_EQ(s.failing_geometry, gc);
  ASSERT_GE(s.component, 0);
  EXPECT_GT(s.failing_lower, 1e3);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(s.region[i].contains(s.point[i])) << i;
  EXPECT_TRUE(mpGreaterEqual(mpfrWorstError(nominal, s.point)[s.component], s.failing_lower));
}
