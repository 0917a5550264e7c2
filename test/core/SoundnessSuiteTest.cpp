// Randomized soundness suite (docs/soundness.md, "The randomized soundness suite"): a fixed-seed slice of the random
// problems of bench/soundness_campaign, every answer of the verifier checked against the plain oracle
// (test/support/PlainOracle.hpp, written independently of the core). What is checked per case
// (test/support/SoundnessCases.hpp, runCase):
//   * max-error mode: certified upper >= the oracle's maximum over poses and geometries, every component; the certified
//     lower bound reproduced by the oracle at the reported argmax (and geometry, or every geometry tried when none is
//     reported); a reported singularity has opposite signs of det J^-1 at its two ends;
//   * verify mode with thresholds 0.999 x max(oracle maximum, certified lower bound), and clearly below in some
//     components: never SAFE; every UNSAFE witness above its certified bound (so above its threshold) for every
//     geometry tried; every uncertainty-sensitive pose's failing geometry above its threshold;
//   * verify mode just above the oracle's maxima: SAFE only if no certified lower bound exceeds the thresholds;
//   * the upper bounds recorded with safe and undecided boxes hold at the oracle's maxima in those boxes.
// UNDECIDED is always acceptable (budgets are small); a wrong SAFE never is.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../support/SoundnessCases.hpp"
#include "TestRobots.hpp"

using namespace pkm_accuracy;
namespace sn = pkm_accuracy::test::soundness;
namespace oracle = pkm_accuracy::test::oracle;

namespace {

/// The slice: seed, cases, budgets (small: the suite checks answers, not how far the search gets).
constexpr std::uint64_t kSeed = 1;
constexpr int kCases = 400;

}  // namespace

TEST(SoundnessOracle, AgreesWithTheModelsPointEvaluationOnRandomRobots) {
  // Two independent implementations of f_k (the oracle here, GoughPlatform::worstErrorAt in the core) agree at random
  // poses of random cases: a check of the oracle as much as of the model.
  const model::GoughGeometry ref6 = test::ref6File().geometry;
  std::mt19937_64 rng(11);
  int compared = 0;
  for (int index = 0; index < 40; ++index) {
    const sn::Case c = sn::makeCase(99, index, ref6);
    model::GoughGeometry nominal = c.geometry;
    nominal.base_anchor_halfwidth.clear();
    nominal.platform_anchor_halfwidth.clear();
    nominal.tool_point_halfwidth.setZero();
    const model::GoughPlatform robot(nominal);
    std::vector<oracle::Placement> poses;
    for (int n = 0; n < 20; ++n) {
      bool ok = false;
      const oracle::Point t = oracle::randomInside(*c.map, rng, ok);
      if (!ok) continue;
      c.map->poses(t, poses);
      for (const oracle::Placement& x : poses) {
        const auto rpy = oracle::rpyOf(x.r);
        DVec q(6);
        q << static_cast<double>(x.p[0]), static_cast<double>(x.p[1]), static_cast<double>(x.p[2]),
            static_cast<double>(rpy[0]), static_cast<double>(rpy[1]), static_cast<double>(rpy[2]);
        const oracle::Placement back = oracle::Placement::fromPose({q[0], q[1], q[2], q[3], q[4], q[5]});
        const DVec core = robot.worstErrorAt(q);
        for (int k = 0; k < 6; ++k) {
          const oracle::Precise p = oracle::precise(c.uncertainty.nominal, back, k);
          if (!p.reliable || p.tolerance > 1e-6) continue;
          EXPECT_NEAR(core[k], p.value, 1e-8 * p.value) << c.description() << "\ncomponent " << k;
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 3000);
}

TEST(SoundnessOracle, PoseMapsAgreeWithTheDomainsPoses) {
  // The oracle's poses (from the definitions of workspaces, regions, frames, trajectories and varieties) and the
  // core's domains (Domain::poseAt: certified enclosures) describe the same motions, at random points of random cases.
  const model::GoughGeometry ref6 = test::ref6File().geometry;
  std::mt19937_64 rng(12);
  int compared = 0;
  for (int index = 0; index < 60; ++index) {
    const sn::Case c = sn::makeCase(98, index, ref6);
    std::vector<oracle::Placement> poses;
    for (int n = 0; n < 10; ++n) {
      bool ok = false;
      const oracle::Point t = oracle::randomInside(*c.map, rng, ok);
      if (!ok) continue;
      DVec v(t.size());
      for (int i = 0; i < t.size(); ++i) v[i] = t[i];
      const IVec core = c.domain->poseAt(v);
      c.map->poses(t, poses);
      ASSERT_EQ(poses.size(), 1u) << c.description();
      const oracle::Placement& x = poses.front();
      const oracle::Mat3L33 r = oracle::rotation(core[3].mid(), core[4].mid(), core[5].mid());
      for (int i = 0; i < 3; ++i) {
        const double scale = 1.0 + std::abs(core[i].mid());
        EXPECT_NEAR(core[i].mid(), static_cast<double>(x.p[i]), 1e-12 * scale + core[i].rad()) << c.description();
      }
      double angleRadius = 0.0;
      for (int i = 3; i < 6; ++i) angleRadius += core[i].rad();
      EXPECT_LT(static_cast<double>((r - x.r).norm()), 1e-12 + 2.0 * angleRadius) << c.description();
      ++compared;
    }
  }
  EXPECT_GT(compared, 500);
}

TEST(SoundnessOracle, ChecksRejectAnswersTheOracleContradicts) {
  // The checks can fail: a witness bound just above the oracle's value at the witness, a lower bound just above the
  // value at its argmax, and a singularity whose ends have the same sign of det J^-1 are all reported.
  const model::GoughGeometry ref6 = test::ref6File().geometry;
  for (int index = 0; index < 20; ++index) {
    const sn::Case c = sn::makeCase(5, index, ref6);
    std::mt19937_64 rng(3);
    bool ok = false;
    const oracle::Point t = oracle::randomInside(*c.map, rng, ok);
    if (!ok) continue;
    // The smallest value over the geometries at t (what a witness must beat for every geometry), found as the
    // checker finds it (the same search from the same seed).
    std::mt19937_64 same(1);
    const oracle::Candidate low = oracle::minimumOverGeometries(*c.map, c.uncertainty, t, 0, same);
    const double value = sn::detail::preciseAt(c, t, low.g, 0, true).value;
    ASSERT_TRUE(std::isfinite(value));
    DVec w(t.size());
    for (int i = 0; i < t.size(); ++i) w[i] = t[i];
    verify::VerifierResult r;
    r.verdict = verify::Verdict::Unsafe;
    r.witness = w;
    r.witness_component = 0;
    const DVec thresholds = DVec::Constant(6, 0.5 * value);
    for (const double factor : {0.999, 1.001}) {
      sn::Counts counts;
      std::vector<std::string> failures;
      sn::detail::Checker chk{c, counts, failures, std::mt19937_64(1)};
      r.witness_lower_bound = factor * value;
      chk.unsafe(r, thresholds, "fabricated");
      EXPECT_EQ(failures.empty(), factor < 1.0) << c.description() << "\nfactor " << factor;
    }
    // Same sign at both ends: not a singularity.
    verify::VerifierResult s;
    s.singular = true;
    s.singular_from = w;
    s.singular_to = w;
    sn::Counts counts;
    std::vector<std::string> failures;
    sn::detail::Checker chk{c, counts, failures, std::mt19937_64(1)};
    chk.singular(s, "fabricated");
    EXPECT_TRUE(!failures.empty() || counts.skipped > 0) << c.description();
  }
}

TEST(SoundnessSuite, FixedSeedSliceOfRandomProblems) {
  const model::GoughGeometry ref6 = test::ref6File().geometry;
  const sn::RunSettings settings = sn::sliceSettings();
  struct Outcome {
    sn::Counts counts;
    std::vector<std::string> failures;
    std::string description;
  };
  std::vector<Outcome> outcomes(kCases);
  std::atomic<int> next{0};
  const auto start = std::chrono::steady_clock::now();
  // Two workers over the cases (each verifier run single-threaded: the answers do not depend on the scheduling).
  auto work = [&]() {
    for (int i = next++; i < kCases; i = next++) {
      Outcome& o = outcomes[i];
      try {
        const sn::Case c = sn::makeCase(kSeed, i, ref6);
        o.description = c.description();
        o.failures = sn::runCase(c, settings, o.counts);
      } catch (const std::exception& e) {
        o.failures.push_back(std::string("exception: ") + e.what());
      }
    }
  };
  std::thread helper(work);
  work();
  helper.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  sn::Counts total;
  for (int i = 0; i < kCases; ++i) {
    total.add(outcomes[i].counts);
    if (outcomes[i].failures.empty()) continue;
    std::string text = outcomes[i].description + "\n";
    for (const std::string& f : outcomes[i].failures) text += "  failure: " + f + "\n";
    text +=
        "  reproduce: soundness_campaign " + std::to_string(kSeed) + " 1 " + std::to_string(i) + " --slice --verbose";
    ADD_FAILURE() << text;
  }
  std::cout << "[ info     ] soundness slice (seed " << kSeed << "): " << total.summary() << "; " << seconds << " s\n";
  // Not vacuous: the slice reaches every kind of answer and checks many assertions.
  EXPECT_EQ(total.cases, kCases);
  EXPECT_GT(total.safe, kCases / 10);
  EXPECT_GT(total.unsafe, kCases / 2);
  EXPECT_GT(total.maxConverged, kCases / 3);
  EXPECT_GT(total.assertions, 40L * kCases);
}
