// Trajectories and motion varieties (domain/WaypointTrajectory, PolynomialTrajectory, ParametricVariety):
//   * poseView enclosures contain the point poses and the point derivatives of the Dual<double> evaluation at
//     random points of random boxes (also boxes across segment boundaries), and the mean-value data hold:
//     pose(u) in centrePose + d pose/du (box) * deviation;
//   * slerp is the geodesic (against Eigen's quaternion slerp) and meets every waypoint;
//   * the verifier against dense sampling (10^5 samples in t) on the reference robot: SAFE at 10% above the sampled
//     maximum, UNSAFE at 5% below with a witness time whose nominal pose really exceeds the threshold, for a helix
//     of quintic segments, a straight line into the near-singular region yaw -> pi/2, a slerp between two tilted
//     orientations and a 2-parameter variety; a descent through the coplanar singularity z = 0 is UNSAFE; waypoints
//     that are all accurate with an inaccurate middle are caught.
// The YAML reader's tests are in test/io/TrajectoryFileTest.cpp, pkm_verify --trajectory's in
// test/tools/TrajectoryCliTest.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "TrajectorySampling.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using domain::PiecewiseTrajectory;
using domain::PolynomialTrajectory;
using domain::WaypointTrajectory;
using test::ref6;
using test::rotation;
using test::sample;
using test::Sampled;
using test::worstError;
using verify::Verdict;

namespace {

constexpr double kPi = 3.14159265358979323846;

WaypointTrajectory waypoints(const std::vector<std::array<double, 7>>& rows, WaypointTrajectory::Interpolation i) {
  std::vector<WaypointTrajectory::Waypoint> w;
  for (const auto& r : rows) {
    WaypointTrajectory::Waypoint p;
    p.t = r[0];
    for (int k = 0; k < 6; ++k) p.pose[k] = r[k + 1];
    w.push_back(p);
  }
  return WaypointTrajectory(w, i);
}

/// Coefficients of the quintic with position, velocity and acceleration (p, v, a) at tau = 0 and tau = T.
std::vector<double> quintic(double p0, double v0, double a0, double p1, double v1, double a1, double T) {
  const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
  return {p0,
          v0,
          a0 / 2.0,
          (20.0 * (p1 - p0) - (8.0 * v1 + 12.0 * v0) * T - (3.0 * a0 - a1) * T2) / (2.0 * T3),
          (30.0 * (p0 - p1) + (14.0 * v1 + 16.0 * v0) * T + (3.0 * a0 - 2.0 * a1) * T2) / (2.0 * T4),
          (12.0 * (p1 - p0) - 6.0 * (v1 + v0) * T + (a1 - a0) * T2) / (2.0 * T5)};
}

/// A helix of `segments` quintic segments over [0, 4] s: one turn of radius 0.1 m around the z axis while rising
/// 2 cm, the platform tilting along (roll, pitch follow the turn) and turning 0.3 rad in yaw.
PolynomialTrajectory helix(int segments) {
  const double w = kPi / 2.0, T = 4.0 / segments;
  // Per coordinate: value, first and second derivative at time t.
  auto state = [&](int i, double t, int d) {
    const double c = std::cos(w * t), s = std::sin(w * t);
    const double wd = std::pow(w, d);
    const double cosD[3] = {c, -s, -c}, sinD[3] = {s, c, -s};
    switch (i) {
      case 0:
        return 0.1 * wd * cosD[d];
      case 1:
        return 0.1 * wd * sinD[d];
      case 2:
        return d == 0 ? 0.46 + 0.005 * t : d == 1 ? 0.005 : 0.0;
      case 3:
        return 0.15 * wd * cosD[d];
      case 4:
        return 0.15 * wd * sinD[d];
      default:
        return d == 0 ? -0.15 + 0.075 * t : d == 1 ? 0.075 : 0.0;
    }
  };
  std::vector<PolynomialTrajectory::Segment> segs;
  for (int k = 0; k < segments; ++k) {
    PolynomialTrajectory::Segment g;
    g.start = k * T;
    g.end = k + 1 == segments ? 4.0 : (k + 1) * T;
    for (int i = 0; i < 6; ++i) {
      g.coefficients[i] = quintic(state(i, g.start, 0), state(i, g.start, 1), state(i, g.start, 2), state(i, g.end, 0),
                                  state(i, g.end, 1), state(i, g.end, 2), g.end - g.start);
    }
    segs.push_back(g);
  }
  return PolynomialTrajectory(segs);
}

/// Checks the poseView of random boxes (some across segment boundaries) against the point evaluation.
void checkPoseViews(const PiecewiseTrajectory& traj, std::uint64_t seed, int boxes) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double span = traj.endTime() - traj.startTime();
  int spanning = 0;
  for (int b = 0; b < boxes; ++b) {
    const double width = std::pow(10.0, -4.0 * uni(rng));  // 1e-4 .. 1
    double lo = uni(rng) * (1.0 - width);
    if (b % 5 == 0) {  // centred on a random segment boundary
      const int k = 1 + static_cast<int>(uni(rng) * (traj.segments() - 1));
      lo = std::max(0.0, std::min(1.0 - width, (traj.times()[k] - traj.startTime()) / span - 0.5 * width));
    }
    IVec box(1);
    box[0] = Interval(lo, lo + width);
    enclosure::BoxInput in;
    traj.poseView(box, true, in);
    ASSERT_EQ(in.variables, 1);
    ASSERT_TRUE(in.hasGradient);
    ASSERT_EQ(in.pose.size(), 6);
    ASSERT_EQ(in.deviation.size(), 1);
    const Interval T = traj.timeEnclosure(box[0]);
    if (traj.times().end() !=
        std::find_if(traj.times().begin() + 1, traj.times().end() - 1, [&](double t) { return T.contains(t); })) {
      ++spanning;
    }
    for (int p = 0; p < 20; ++p) {
      const double u = lo + width * (0.001 + 0.998 * uni(rng));
      const auto pt = traj.pointAt(u);
      for (int i = 0; i < 6; ++i) {
        ASSERT_TRUE(in.pose[i].contains(pt.pose[i]))
            << "box " << box[0] << " u " << u << " coordinate " << i << ": " << in.pose[i] << " vs " << pt.pose[i];
        ASSERT_TRUE(in.dualPose[i].value().contains(pt.pose[i]));
        const Interval& d = in.dualPose[i].d(0);
        ASSERT_TRUE(d.contains(pt.velocity[i]))
            << "box " << box[0] << " u " << u << " coordinate " << i << ": d/du " << d << " vs " << pt.velocity[i];
        for (int v = 1; v < kMaxDof; ++v) ASSERT_EQ(in.dualPose[i].d(v), Interval(0.0));
        // The mean-value data: pose(u) in centrePose + d/du (box) * deviation (in RPY space only where the
        // principal angles do not wrap around inside the box; the model sees a continuous rotation there).
        if (in.pose[i].width() > 3.0) continue;
        const Interval mv = in.centrePose[i] + d * in.deviation[0];
        ASSERT_TRUE(mv.contains(pt.pose[i]))
            << "box " << box[0] << " u " << u << " coordinate " << i << ": " << mv << " vs " << pt.pose[i];
      }
    }
    // poseAt encloses the point pose.
    const double u = lo + 0.5 * width;
    const IVec at = traj.poseAt(DVec::Constant(1, u));
    const auto pt = traj.pointAt(u);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(at[i].mid(), pt.pose[i], 1e-12 + 1e-3 * at[i].width());
    for (int i = 0; i < 6; ++i) EXPECT_LT(at[i].width(), 1e-9) << at[i];
  }
  EXPECT_GT(spanning, boxes / 10) << "too few boxes across segment boundaries were tested";
}

verify::VerifierResult verifyAt(const domain::Domain& d, const DVec& thresholds) {
  verify::VerifierOptions o;
  o.thresholds = thresholds;
  o.time_limit_s = 20.0;
  return verify::Verifier::run(ref6(), d, o);
}

/// An UNSAFE result with a witness time whose nominal pose really exceeds the threshold.
void checkWitness(const PiecewiseTrajectory& traj, const verify::VerifierResult& unsafe, const DVec& thresholds,
                  const std::string& what) {
  ASSERT_EQ(unsafe.verdict, Verdict::Unsafe) << unsafe.message;
  const int k = unsafe.witness_component;
  ASSERT_GE(k, 0);
  ASSERT_EQ(unsafe.witness.size(), 1);
  const double u = unsafe.witness[0], t = traj.timeOf(u);
  EXPECT_GE(u, 0.0);
  EXPECT_LE(u, 1.0);
  const DVec pose = traj.pointAtTime(t).pose;
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(unsafe.witness_pose[i].mid(), pose[i], 1e-9);
  EXPECT_GT(worstError(pose)[k], thresholds[k]) << "witness t = " << t << " s";
  EXPECT_GT(unsafe.witness_lower_bound, thresholds[k]);
  EXPECT_LE(unsafe.witness_lower_bound, worstError(pose)[k] * (1 + 1e-9));
  std::printf("[ figures  ] %s: UNSAFE in %zu boxes, witness t = %.9g s (%s)\n", what.c_str(), unsafe.stats.boxes, t,
              ref6().componentName(k).c_str());
}

/// SAFE at 10% above the sampled maximum, UNSAFE at 5% below with a real witness time.
void safeAboveUnsafeBelow(const PiecewiseTrajectory& traj, const std::string& what) {
  SCOPED_TRACE(what);
  const auto start = std::chrono::steady_clock::now();
  const Sampled s = sample(traj, 100000);
  ASSERT_TRUE(s.max.allFinite());
  const auto safe = verifyAt(traj, s.max * 1.10);
  EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
  EXPECT_EQ(safe.undecided_box_count, 0u);
  EXPECT_EQ(safe.stats.unenclosed_boxes, 0u);  // (SearchTuning::skip_hopeless: domains of 3 or more variables)
  // Also without the pre-sampling grid (u = 0, 1/2, 1): the branch-and-bound has to find the witness itself.
  for (int presample : {3, 0}) {
    SCOPED_TRACE("presample_points " + std::to_string(presample));
    verify::VerifierOptions o;
    o.thresholds = s.max * 0.95;
    o.presample_points = presample;
    o.time_limit_s = 20.0;
    checkWitness(traj, verify::Verifier::run(ref6(), traj, o), o.thresholds, what);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ figures  ] %s: SAFE at +10%% in %zu boxes (%.3f s); test %.2f s\n", what.c_str(), safe.stats.boxes,
              safe.stats.seconds, seconds);
}

}  // namespace

// ---- pose maps ----------------------------------------------------------------------------------------------------
TEST(TrajectoryDomain, WaypointPoseViewsEncloseThePointPosesAndDerivatives) {
  const std::vector<std::array<double, 7>> rows = {{0.0, -0.10, 0.05, 0.46, 0.25, -0.20, 0.15},
                                                   {1.5, 0.00, 0.10, 0.48, -0.20, 0.30, -0.25},
                                                   {2.0, 0.08, -0.05, 0.47, -0.20, 0.30, -0.25},  // same orientation
                                                   {3.7, 0.12, -0.10, 0.49, 0.40, 0.10, 2.80},
                                                   {4.0, 0.00, 0.00, 0.47, 0.00, -0.35, -3.00}};  // across yaw = pi
  for (auto i : {WaypointTrajectory::Interpolation::Slerp, WaypointTrajectory::Interpolation::LinearRpy}) {
    SCOPED_TRACE(WaypointTrajectory::interpolationName(i));
    const WaypointTrajectory traj = waypoints(rows, i);
    EXPECT_EQ(traj.variables(), 1);
    EXPECT_EQ(traj.segments(), 4);
    EXPECT_EQ(traj.initialBox()[0], Interval(0.0, 1.0));
    checkPoseViews(traj, 1, 400);
    // Every waypoint is met (as a rotation for slerp, whose RPY is principal), with its time.
    for (std::size_t w = 0; w < rows.size(); ++w) {
      const auto p = traj.pointAtTime(rows[w][0]);
      DVec expected(6);
      for (int k = 0; k < 6; ++k) expected[k] = rows[w][k + 1];
      EXPECT_LT((p.pose.head(3) - expected.head(3)).norm(), 1e-15);
      EXPECT_LT((rotation(p.pose) - rotation(expected)).norm(), 1e-12) << "waypoint " << w;
      const IVec cert = traj.poseAtTime(rows[w][0]);
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(cert[k].contains(expected[k]));
    }
  }
  // Slerp is the geodesic: against Eigen's quaternion slerp at random times.
  const WaypointTrajectory traj = waypoints(rows, WaypointTrajectory::Interpolation::Slerp);
  std::mt19937_64 rng(3);
  for (int n = 0; n < 2000; ++n) {
    const int k = n % 4;
    const double s = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const double t = rows[k][0] + s * (rows[k + 1][0] - rows[k][0]);
    DVec a(6), b(6);
    for (int c = 0; c < 6; ++c) {
      a[c] = rows[k][c + 1];
      b[c] = rows[k + 1][c + 1];
    }
    const Eigen::Quaterniond qa(rotation(a)), qb(rotation(b));
    const auto p = traj.pointAtTime(t);
    EXPECT_LT((rotation(p.pose) - qa.slerp(s, qb).toRotationMatrix()).norm(), 1e-12) << "t " << t;
    EXPECT_LT(std::fabs(p.pose[0] - (a[0] + s * (b[0] - a[0]))), 1e-15);
  }
}

TEST(TrajectoryDomain, PolynomialPoseViewsEncloseThePointPosesAndDerivatives) {
  const PolynomialTrajectory traj = helix(8);
  EXPECT_EQ(traj.segments(), 8);
  EXPECT_EQ(traj.startTime(), 0.0);
  EXPECT_EQ(traj.endTime(), 4.0);
  checkPoseViews(traj, 2, 400);
  // The quintics interpolate the helix at the segment boundaries (value and velocity).
  for (double t : {0.0, 0.5, 1.0, 2.5, 4.0}) {
    const auto p = traj.pointAtTime(t);
    EXPECT_NEAR(p.pose[0], 0.1 * std::cos(kPi / 2 * t), 1e-12);
    EXPECT_NEAR(p.velocity[1], 0.1 * kPi / 2 * std::cos(kPi / 2 * t), 1e-10);
    EXPECT_NEAR(p.pose[5], -0.15 + 0.075 * t, 1e-12);
  }
  // Horner's scheme with Dual<double>: velocity of p(tau) = 1 + 2 tau + 3 tau^2 at tau = 0.5 is 2 + 6 tau = 5.
  PolynomialTrajectory::Segment g;
  g.start = 1.0;
  g.end = 2.0;
  for (int i = 0; i < 6; ++i) g.coefficients[i] = {1.0, 2.0, 3.0};
  const PolynomialTrajectory simple({g});
  const auto p = simple.pointAtTime(1.5);
  EXPECT_DOUBLE_EQ(p.pose[2], 1.0 + 1.0 + 0.75);
  EXPECT_DOUBLE_EQ(p.velocity[2], 5.0);
}

TEST(TrajectoryDomain, VarietyPoseViewsEncloseThePointPosesAndJacobians) {
  using Mono = domain::ParametricVariety::Monomial;
  auto mono = [](double c, int a, int b, int d = 0) {
    Mono m;
    m.coefficient = c;
    m.exponents = {a, b, d, 0, 0, 0};
    return m;
  };
  const domain::ParametricVariety v(3, {{{mono(-0.1, 0, 0), mono(0.2, 1, 0), mono(0.03, 2, 1, 1)},
                                         {mono(-0.1, 0, 0), mono(0.2, 0, 1)},
                                         {mono(0.46, 0, 0), mono(0.02, 1, 1), mono(0.01, 0, 0, 1)},
                                         {mono(-0.1, 0, 0), mono(0.2, 1, 0, 3)},
                                         {mono(0.1, 0, 2)},
                                         {mono(-0.1, 0, 0), mono(0.3, 1, 1), mono(-0.05, 0, 3, 2)}}});
  EXPECT_EQ(v.variables(), 3);
  EXPECT_EQ(v.variableName(1), "v");
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int b = 0; b < 300; ++b) {
    IVec box(3);
    for (int i = 0; i < 3; ++i) {
      const double w = std::pow(10.0, -3.0 * uni(rng)), lo = uni(rng) * (1.0 - w);
      box[i] = Interval(lo, lo + w);
    }
    enclosure::BoxInput in;
    v.poseView(box, true, in);
    ASSERT_EQ(in.variables, 3);
    for (int p = 0; p < 10; ++p) {
      DVec t(3);
      for (int i = 0; i < 3; ++i) t[i] = box[i].lower() + uni(rng) * (box[i].upper() - box[i].lower());
      DVec pose;
      DMat jac;
      v.pointAt(t, pose, jac);
      for (int k = 0; k < 6; ++k) {
        ASSERT_TRUE(in.pose[k].contains(pose[k]));
        Interval mv = in.centrePose[k];
        for (int i = 0; i < 3; ++i) {
          ASSERT_TRUE(in.dualPose[k].d(i).contains(jac(k, i))) << in.dualPose[k].d(i) << " " << jac(k, i);
          mv = mv + in.dualPose[k].d(i) * in.deviation[i];
        }
        ASSERT_TRUE(mv.contains(pose[k]));
      }
    }
  }
  // Bad input names the coordinate and monomial.
  try {
    domain::ParametricVariety(2, {{{mono(1.0, 0, 0, 1)}, {}, {}, {}, {}, {}}});
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("variety.x[0]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(domain::ParametricVariety(0, {}), InvalidArgument);
}

TEST(TrajectoryDomain, RejectsBadWaypointsAndSegments) {
  using I = WaypointTrajectory::Interpolation;
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message([] { waypoints({{0, 0, 0, 0.47, 0, 0, 0}}, I::Slerp); }).find("at least 2"), std::string::npos);
  EXPECT_NE(message([] {
              waypoints({{0, 0, 0, 0.47, 0, 0, 0}, {0, 0, 0, 0.47, 0, 0, 0}}, I::Slerp);
            }).find("waypoints[1]: time 0 s is not greater"),
            std::string::npos);
  EXPECT_NE(message([] {
              waypoints({{0, 0, 0, 0.47, 0, 0, 0}, {1, 0, NAN, 0.47, 0, 0, 0}}, I::LinearRpy);
            }).find("waypoints[1][2] (y)"),
            std::string::npos);
  PolynomialTrajectory::Segment a, b;
  a.start = 0.0;
  a.end = 1.0;
  b.start = 1.5;
  b.end = 2.0;
  for (int i = 0; i < 6; ++i) a.coefficients[i] = b.coefficients[i] = {0.0};
  EXPECT_NE(message([&] { PolynomialTrajectory({a, b}); }).find("polynomial_segments[1].t"), std::string::npos);
  b.start = 1.0;
  b.coefficients[4].clear();
  EXPECT_NE(message([&] { PolynomialTrajectory({a, b}); }).find("polynomial_segments[1].pitch"), std::string::npos);
  EXPECT_THROW(PolynomialTrajectory({}), InvalidArgument);
}

TEST(TrajectoryDomain, RegionClassifiesTheVisitedPositions) {
  WaypointTrajectory traj =
      waypoints({{0, 0, 0, 0.30, 0, 0, 0}, {1, 0, 0, -0.05, 0, 0, 0}}, WaypointTrajectory::Interpolation::LinearRpy);
  traj.setRegion(domain::PositionRegion::box(Eigen::Vector3d(-1, -1, 0.1), Eigen::Vector3d(1, 1, 1)));
  IVec box(1);
  box[0] = Interval(0.0, 0.1);  // z in [0.265, 0.30]
  EXPECT_EQ(traj.classify(box), domain::Containment::Inside);
  box[0] = Interval(0.9, 1.0);  // z in [-0.05, -0.015]
  EXPECT_EQ(traj.classify(box), domain::Containment::Outside);
  box[0] = Interval(0.0, 1.0);
  EXPECT_EQ(traj.classify(box), domain::Containment::Partial);
}

// ---- verification against dense sampling ----------------------------------------------------------------------
TEST(TrajectoryVerify, HelixOfQuinticSegments) { safeAboveUnsafeBelow(helix(8), "helix, 8 quintic segments"); }

TEST(TrajectoryVerify, StraightLineIntoTheNearSingularRegion) {
  // yaw -> pi/2 is a singularity of this geometry (the worst rz error grows from 1.1e-3 to ~5e-2 rad here).
  const WaypointTrajectory traj =
      waypoints({{0.0, -0.10, 0.00, 0.46, 0.00, 0.00, 1.20}, {2.0, 0.10, 0.05, 0.48, 0.10, 0.05, 1.55}},
                WaypointTrajectory::Interpolation::LinearRpy);
  safeAboveUnsafeBelow(traj, "straight line to yaw 1.55");
}

TEST(TrajectoryVerify, SlerpBetweenTiltedOrientations) {
  const WaypointTrajectory traj =
      waypoints({{0.0, -0.10, 0.05, 0.46, 0.25, -0.20, 0.15}, {3.0, 0.12, -0.08, 0.49, -0.20, 0.30, -0.25}},
                WaypointTrajectory::Interpolation::Slerp);
  safeAboveUnsafeBelow(traj, "slerp between tilted orientations");
}

TEST(TrajectoryVerify, VarietyOfTwoParameters) {
  using Mono = domain::ParametricVariety::Monomial;
  auto mono = [](double c, int a, int b) {
    Mono m;
    m.coefficient = c;
    m.exponents = {a, b, 0, 0, 0, 0};
    return m;
  };
  const domain::ParametricVariety v(2, {{{mono(-0.1, 0, 0), mono(0.2, 1, 0)},
                                         {mono(-0.1, 0, 0), mono(0.2, 0, 1)},
                                         {mono(0.46, 0, 0), mono(0.02, 1, 1)},
                                         {mono(-0.1, 0, 0), mono(0.2, 1, 0)},
                                         {mono(0.1, 0, 2)},
                                         {mono(-0.1, 0, 0), mono(0.3, 1, 1)}}});
  DVec max = DVec::Zero(6);
  for (int i = 0; i <= 316; ++i) {
    for (int j = 0; j <= 316; ++j) {
      DVec t(2), pose;
      t << i / 316.0, j / 316.0;
      DMat jac;
      v.pointAt(t, pose, jac);
      max = max.cwiseMax(worstError(pose));
    }
  }
  const auto safe = verifyAt(v, max * 1.10);
  EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
  const auto unsafe = verifyAt(v, max * 0.95);
  ASSERT_EQ(unsafe.verdict, Verdict::Unsafe) << unsafe.message;
  DVec pose;
  DMat jac;
  v.pointAt(unsafe.witness, pose, jac);
  const int k = unsafe.witness_component;
  EXPECT_GT(worstError(pose)[k], max[k] * 0.95);
  std::printf("[ figures  ] 2-parameter variety: SAFE at +10%% in %zu boxes (%.3f s), UNSAFE at -5%% in %zu boxes\n",
              safe.stats.boxes, safe.stats.seconds, unsafe.stats.boxes);
}

TEST(TrajectoryVerify, DescentThroughTheCoplanarSingularityIsUnsafe) {
  // At z = 0 the platform lies in the plane of the base: J^-1 is singular, the error unbounded.
  const WaypointTrajectory traj =
      waypoints({{0.0, 0.0, 0.0, 0.30, 0.0, 0.0, 0.0}, {5.0, 0.0, 0.0, -0.05, 0.0, 0.0, 0.0}},
                WaypointTrajectory::Interpolation::LinearRpy);
  // Thresholds 10x above the errors at the start (z = 0.3): only the neighbourhood of z = 0 violates them.
  const DVec start = worstError(traj.pointAtTime(0.0).pose);
  const auto r = verifyAt(traj, start * 10.0);
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  const double t = traj.timeOf(r.witness[0]);
  const DVec pose = traj.pointAtTime(t).pose;
  EXPECT_LT(std::fabs(pose[2]), 0.05) << "witness z " << pose[2] << " at t = " << t;
  EXPECT_GT(worstError(pose)[r.witness_component], start[r.witness_component] * 10.0);
  // Restricted to z >= 0.1 by a position region, the same trajectory is SAFE.
  WaypointTrajectory above = traj;
  above.setRegion(domain::PositionRegion::box(Eigen::Vector3d(-1, -1, 0.1), Eigen::Vector3d(1, 1, 1)));
  Sampled s;
  for (int i = 0; i <= 20000; ++i) {
    const double ti = 5.0 * i / 20000.0;
    const DVec p = traj.pointAtTime(ti).pose;
    if (p[2] >= 0.1) s.max = s.max.cwiseMax(worstError(p));
  }
  const auto inside = verifyAt(above, s.max * 1.10);
  EXPECT_EQ(inside.verdict, Verdict::Safe) << inside.message;
  EXPECT_GT(inside.stats.outside_fraction, 0.3);
}

TEST(TrajectoryVerify, CrossingTheCoplanarSingularityIsUnsafeForAnyThreshold) {
  // Thresholds no double evaluation can certify: UNSAFE through the certified sign change of det J^-1 along the
  // trajectory, whose two times bracket the crossing of z = 0 (where every leg lies in the base plane).
  const WaypointTrajectory traj =
      waypoints({{0.0, 0.0, 0.0, 0.30, 0.0, 0.0, 0.0}, {5.0, 0.0, 0.0, -0.05, 0.0, 0.0, 0.0}},
                WaypointTrajectory::Interpolation::LinearRpy);
  const auto r = verifyAt(traj, DVec::Constant(6, 1e15));
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  ASSERT_TRUE(r.singular) << r.message;
  ASSERT_EQ(r.singular_from.size(), 1);
  ASSERT_EQ(r.singular_to.size(), 1);
  const double za = traj.pointAtTime(traj.timeOf(r.singular_from[0])).pose[2];
  const double zb = traj.pointAtTime(traj.timeOf(r.singular_to[0])).pose[2];
  EXPECT_LT(za * zb, 0.0) << za << " " << zb;
  EXPECT_TRUE(r.singular_pose_from[2].contains(za));
  EXPECT_TRUE(r.singular_pose_to[2].contains(zb));
  // Stopped before it: no singular pose, no certificate.
  const WaypointTrajectory above =
      waypoints({{0.0, 0.0, 0.0, 0.30, 0.0, 0.0, 0.0}, {5.0, 0.0, 0.0, 0.05, 0.0, 0.0, 0.0}},
                WaypointTrajectory::Interpolation::LinearRpy);
  const auto safe = verifyAt(above, DVec::Constant(6, 1e15));
  EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
  EXPECT_FALSE(safe.singular);
}

TEST(TrajectoryVerify, AccurateWaypointsWithAnInaccurateMiddleAreCaught) {
  // (1) A large rotation between two accurate orientations: yaw 1.2 -> 1.94 turns through the singular yaw = pi/2.
  for (auto i : {WaypointTrajectory::Interpolation::Slerp, WaypointTrajectory::Interpolation::LinearRpy}) {
    SCOPED_TRACE(WaypointTrajectory::interpolationName(i));
    const WaypointTrajectory traj =
        waypoints({{0.0, 0.0, 0.0, 0.47, 0.0, 0.0, 1.2}, {1.0, 0.0, 0.0, 0.47, 0.0, 0.0, 1.94}}, i);
    const DVec ends = worstError(traj.pointAtTime(0.0).pose).cwiseMax(worstError(traj.pointAtTime(1.0).pose));
    const DVec thresholds = ends * 2.0;  // both waypoints are accurate with a factor 2 to spare
    const auto r = verifyAt(traj, thresholds);
    ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
    const double t = traj.timeOf(r.witness[0]);
    EXPECT_GT(t, 0.05);
    EXPECT_LT(t, 0.95);
    EXPECT_GT(worstError(traj.pointAtTime(t).pose)[r.witness_component], thresholds[r.witness_component]);
  }
  // (2) No singularity: thresholds between the waypoint errors and the mid-segment maximum found by sampling (the
  //     pitch error peaks inside this segment, ~19% above both ends).
  const WaypointTrajectory traj = waypoints({{0.0, -0.0247, 0.0195, 0.4756, 0.2264, 0.3982, -0.3775},
                                             {2.0, -0.1113, 0.0602, 0.4671, -0.4588, 0.3284, 0.4289}},
                                            WaypointTrajectory::Interpolation::LinearRpy);
  const DVec ends = worstError(traj.pointAtTime(0.0).pose).cwiseMax(worstError(traj.pointAtTime(2.0).pose));
  const Sampled s = sample(traj, 100000);
  ASSERT_GT(s.max[4], ends[4] * 1.15);
  DVec thresholds = s.max * 1.5;  // every other component: generous
  thresholds[4] = std::sqrt(ends[4] * s.max[4]);
  ASSERT_GT(thresholds[4], ends[4]);
  ASSERT_LT(thresholds[4], s.max[4]);
  const auto r = verifyAt(traj, thresholds);
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  EXPECT_EQ(r.witness_component, 4);
  const double t = traj.timeOf(r.witness[0]);
  EXPECT_GT(t, 0.1);
  EXPECT_LT(t, 1.9);
  EXPECT_GT(worstError(traj.pointAtTime(t).pose)[4], thresholds[4]);
  // Just above the sampled maximum it is SAFE.
  thresholds[4] = s.max[4] * 1.05;
  EXPECT_EQ(verifyAt(traj, thresholds).verdict, Verdict::Safe);
}
