// Trajectories and motion varieties (domain/WaypointTrajectory, PolynomialTrajectory, ParametricVariety, the YAML
// reader io/TrajectoryFile and pkm_verify --trajectory):
//   * poseView enclosures contain the point poses and the point derivatives of the Dual<double> evaluation at
//     random points of random boxes (also boxes across segment boundaries), and the mean-value data hold:
//     pose(u) in centrePose + d pose/du (box) * deviation;
//   * slerp is the geodesic (against Eigen's quaternion slerp) and meets every waypoint;
//   * the verifier against dense sampling (10^5 samples in t) on the reference robot: SAFE at 10% above the sampled
//     maximum, UNSAFE at 5% below with a witness time whose nominal pose really exceeds the threshold, for a helix
//     of quintic segments, a straight line into the near-singular region yaw -> pi/2, a slerp between two tilted
//     orientations and a 2-parameter variety; a descent through the coplanar singularity z = 0 is UNSAFE; waypoints
//     that are all accurate with an inaccurate middle are caught;
//   * YAML errors name the file, key and row; the command-line tool reports witness_t and undecided time intervals.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;
using domain::PiecewiseTrajectory;
using domain::PolynomialTrajectory;
using domain::WaypointTrajectory;
using verify::Verdict;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

const model::GoughPlatform& ref6() {
  static const model::GoughPlatform robot(test::ref6File().geometry);
  return robot;
}

DVec worstError(const DVec& pose) {
  try {
    return ref6().worstErrorAt(pose);
  } catch (const SingularMatrix&) {
    return DVec::Constant(6, kInf);
  }
}

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

/// Dense sampling of the worst error along a trajectory (n equally spaced times, double precision).
struct Sampled {
  DVec max = DVec::Zero(6);
  std::vector<double> at = std::vector<double>(6, 0.0);
};
Sampled sample(const PiecewiseTrajectory& traj, int n) {
  Sampled s;
  for (int i = 0; i < n; ++i) {
    const double t = traj.startTime() + (traj.endTime() - traj.startTime()) * i / (n - 1);
    const DVec f = worstError(traj.pointAtTime(t).pose);
    for (int k = 0; k < 6; ++k) {
      if (f[k] > s.max[k]) {
        s.max[k] = f[k];
        s.at[k] = t;
      }
    }
  }
  return s;
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

Eigen::Matrix3d rotation(const DVec& pose) {
  return (Eigen::AngleAxisd(pose[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pose[4], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pose[3], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
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
  EXPECT_EQ(safe.stats.unenclosed_boxes, 0u);  // (VerifierOptions::skip_hopeless: domains of 3 or more variables)
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

// ---- YAML files -------------------------------------------------------------------------------------------------
namespace {

std::string parseError(const std::string& yaml) {
  try {
    io::parseTrajectory(yaml, "traj.yaml");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(TrajectoryFile, ReadsWaypointsPolynomialsVarietiesAndRegions) {
  const auto w = io::parseTrajectory(
      "interpolation: linear_rpy\n"
      "waypoints:\n"
      "  - [0.0, -0.1, 0.0, 0.47, 0.0, 0.0, 0.0]\n"
      "  - [1.5,  0.1, 0.0, 0.47, 0.1, 0.0, 0.2]\n"
      "region: {type: cylinder, centre: [0, 0], radius: 0.2, z: [0.4, 0.5]}\n",
      "w.yaml");
  ASSERT_EQ(w.kind, io::TrajectoryFile::Kind::Waypoints);
  ASSERT_TRUE(w.trajectory);
  EXPECT_EQ(w.trajectory->endTime(), 1.5);
  EXPECT_EQ(w.region, "cylinder");
  EXPECT_EQ(w.description, "waypoints (linear_rpy), 2 waypoints");
  EXPECT_NEAR(w.trajectory->pointAtTime(0.75).pose[5], 0.1, 1e-15);
  EXPECT_EQ(dynamic_cast<const WaypointTrajectory&>(*w.trajectory).interpolation(),
            WaypointTrajectory::Interpolation::LinearRpy);

  const auto p = io::parseTrajectory(
      "polynomial_segments:\n"
      "  - {t: [0, 1], x: [0, 0.1], y: [0], z: [0.47], roll: [0], pitch: [0], yaw: [0, 0, 0.3]}\n"
      "  - {t: [1, 3], x: [0.1], y: [0, 0.01], z: [0.47], roll: [0], pitch: [0], yaw: [0.3, 0.6, -0.1]}\n",
      "p.yaml");
  ASSERT_EQ(p.kind, io::TrajectoryFile::Kind::Polynomial);
  EXPECT_EQ(p.trajectory->segments(), 2);
  EXPECT_NEAR(p.trajectory->pointAtTime(2.0).pose[5], 0.3 + 0.6 - 0.1, 1e-15);
  EXPECT_EQ(p.region, "none");

  const auto v = io::parseTrajectory(
      "variety:\n"
      "  parameters: 2\n"
      "  x: [[-0.1, 0, 0], [0.2, 1, 0]]\n"
      "  y: [[0.2, 0, 1]]\n"
      "  z: [[0.47, 0, 0]]\n"
      "region: {type: box, x: [-0.2, 0.2], y: [-0.2, 0.2], z: [0.4, 0.5]}\n",
      "v.yaml");
  ASSERT_EQ(v.kind, io::TrajectoryFile::Kind::Variety);
  EXPECT_FALSE(v.trajectory);
  ASSERT_TRUE(v.variety);
  EXPECT_EQ(v.domain->variables(), 2);
  DVec pose;
  DMat jac;
  v.variety->pointAt((DVec(2) << 0.5, 0.25).finished(), pose, jac);
  EXPECT_DOUBLE_EQ(pose[0], 0.0);
  EXPECT_DOUBLE_EQ(pose[1], 0.05);
  EXPECT_DOUBLE_EQ(pose[5], 0.0);
}

TEST(TrajectoryFile, ErrorsNameTheFileKeyAndRow) {
  const std::string two = "  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0, 0.47, 0, 0, 0]\n";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0, 0.47, 0, 0, 0]\n",
       {"traj.yaml: waypoints[2][0]", "not greater", "1 s"}},
      {"waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0, 0.47, 0, 0]\n",
       {"traj.yaml: waypoints[1]", "expected 7 numbers", "got 6"}},
      {"waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, .nan, 0.47, 0, 0, 0]\n",
       {"traj.yaml: waypoints[1][2]", "finite", ".nan"}},
      {"waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, abc, 0.47, 0, 0, 0]\n",
       {"traj.yaml: waypoints[1][2]", "'abc'"}},
      {"waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n", {"traj.yaml: waypoints", "at least 2"}},
      {"waypoints: 3\n", {"traj.yaml: waypoints", "list of rows"}},
      {"interpolation: cubic\nwaypoints:\n" + two,
       {"traj.yaml: interpolation", "slerp, linear_rpy or linear", "cubic"}},
      {"waypoint:\n" + two, {"traj.yaml: waypoint", "unknown key"}},
      {"waypoints:\n" + two + "polynomial_segments: []\n", {"traj.yaml", "exactly one of"}},
      {"region: {type: box, x: [0, 1], y: [0, 1], z: [0, 1]}\n", {"traj.yaml", "expected one of"}},
      {"waypoints:\n" + two + "region: {type: cone}\n", {"traj.yaml: region.type", "cone"}},
      {"waypoints:\n" + two + "region: {type: box, x: [1, 0], y: [0, 1], z: [0, 1]}\n", {"traj.yaml: region.x"}},
      {"waypoints:\n" + two + "region: {type: sphere, centre: [0, 0, 0], radius: -1}\n",
       {"traj.yaml: region", "radius"}},
      {"polynomial_segments:\n  - {t: [0, 1], x: [0], y: [0], z: [0.47], roll: [0], pitch: [0], yaw: [0]}\n"
       "  - {t: [2, 3], x: [0], y: [0], z: [0.47], roll: [0], pitch: [0], yaw: [0]}\n",
       {"traj.yaml: polynomial_segments[1].t[0]", "previous one ends"}},
      {"polynomial_segments:\n  - {t: [0, 1], x: [0], y: [0], z: [0.47], roll: [0], pitch: [0]}\n",
       {"traj.yaml: polynomial_segments[0].yaw", "missing"}},
      {"polynomial_segments:\n  - {t: [1, 1], x: [0], y: [0], z: [0.47], roll: [0], pitch: [0], yaw: [0]}\n",
       {"traj.yaml: polynomial_segments[0].t", "start < end"}},
      {"polynomial_segments:\n  - {t: [0, 1], x: [0, .inf], y: [0], z: [0.47], roll: [0], pitch: [0], yaw: [0]}\n",
       {"traj.yaml: polynomial_segments[0].x[1]", "finite"}},
      {"variety:\n  parameters: 2\n  x: [[1.0, 0.5, 0]]\n", {"traj.yaml: variety.x[0][1]", "integer exponent"}},
      {"variety:\n  parameters: 7\n", {"traj.yaml: variety.parameters", "1 to 6"}},
      {"variety:\n  parameters: 2\n  x: [[1.0, 1]]\n", {"traj.yaml: variety.x[0]", "expected 3 numbers"}},
      {"waypoints: [\n", {"traj.yaml: invalid YAML"}},
      {"waypoints:\n" + two + "frame: 3\n", {"traj.yaml: frame", "expected a map", "3"}},
      {"waypoints:\n" + two + "frame: {rotation: [0, 0, 0]}\n", {"traj.yaml: frame", "rotation", "unknown key"}},
      {"waypoints:\n" + two + "frame: {rpy: [0, 0]}\n", {"traj.yaml: frame.rpy"}},
      {"waypoints:\n" + two + "frame: {translation: [0, .nan, 0]}\n", {"traj.yaml: frame.translation", "finite"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.first);
    const std::string e = parseError(c.first);
    for (const auto& m : c.second) EXPECT_NE(e.find(m), std::string::npos) << "'" << m << "' in: " << e;
  }
  try {
    io::loadTrajectoryFile("/nonexistent/traj.yaml");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/traj.yaml: cannot open file"), std::string::npos);
  }
}

TEST(TrajectoryFile, FrameKeyVerifiesThePosesInTheBaseFrame) {
  // A waypoint trajectory and a variety given in a frame F at translation t, rotation Rz(0.4) Ry(-0.03) Rx(0.02).
  const Eigen::Vector3d t(0.01, -0.02, 0.05);
  const Eigen::Matrix3d F = rotation((DVec(6) << 0, 0, 0, 0.02, -0.03, 0.4).finished());
  const std::string frame = "frame: {translation: [0.01, -0.02, 0.05], rpy: [0.02, -0.03, 0.4]}\n";
  const auto w = io::parseTrajectory(
      "waypoints:\n"
      "  - [0.0, -0.03, 0.02, 0.42, 0.02, -0.01, 0.1]\n"
      "  - [2.0,  0.04, -0.01, 0.43, -0.03, 0.02, -0.2]\n" +
          frame,
      "w.yaml");
  const auto v = io::parseTrajectory(
      "variety:\n  parameters: 2\n  x: [[-0.03, 0, 0], [0.06, 1, 0]]\n  y: [[0.04, 0, 1]]\n  z: [[0.42, 0, 0]]\n"
      "  yaw: [[0.1, 1, 1]]\n" +
          frame,
      "v.yaml");
  EXPECT_NE(w.description.find("in frame (translation [0.01, -0.02, 0.05] m, rpy [0.02, -0.03, 0.4] rad)"),
            std::string::npos)
      << w.description;
  // The independent mapping: p_base = t + F p, R_base = F R (principal RPY).
  auto toBase = [&](const DVec& p) {
    const Eigen::Matrix3d R = F * rotation(p);
    const Eigen::Vector3d x = t + F * p.head<3>();
    return (DVec(6) << x, std::atan2(R(2, 1), R(2, 2)), std::asin(-R(2, 0)), std::atan2(R(1, 0), R(0, 0))).finished();
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 50; ++i) {
    // The trajectory itself stays in F; the domain's poses are its base-frame images.
    const double u = unit(rng);
    const DVec inF = w.trajectory->pointAtTime(2.0 * u).pose;
    const IVec base = w.domain->poseAt(DVec::Constant(1, u));
    const DVec want = toBase(inF);
    for (int k = 0; k < 6; ++k) {
      EXPECT_TRUE(base[k].contains(want[k]) || std::abs(base[k].mid() - want[k]) < 1e-14) << k;
      EXPECT_LT(base[k].width(), 1e-12) << k;
    }
    const DVec uv = (DVec(2) << unit(rng), unit(rng)).finished();
    DVec pose;
    DMat jac;
    v.variety->pointAt(uv, pose, jac);
    const IVec vb = v.domain->poseAt(uv);
    const DVec vw = toBase(pose);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(vb[k].mid(), vw[k], 1e-14) << k;
  }
  // The verifier on the framed domain: max-error brackets the maxima of the base-frame poses sampled by the oracle,
  // and they differ from the unframed trajectory's (the frame is not ignored).
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.005;
  o.alpha_relative = true;
  o.time_limit_s = 20.0;
  const verify::VerifierResult r = verify::Verifier::run(ref6(), *w.domain, o);
  const verify::VerifierResult plain = verify::Verifier::run(ref6(), *w.trajectory, o);
  ASSERT_TRUE(r.converged) << r.message;
  DVec sampled = DVec::Zero(6), sampledPlain = DVec::Zero(6);
  for (int i = 0; i <= 2000; ++i) {
    const DVec inF = w.trajectory->pointAtTime(2.0 * i / 2000).pose;
    sampled = sampled.cwiseMax(worstError(toBase(inF)));
    sampledPlain = sampledPlain.cwiseMax(worstError(inF));
  }
  for (int k = 0; k < 6; ++k) {
    EXPECT_LE(r.max_lower[k], sampled[k] * (1 + 1e-9)) << k;  // attained (up to the sampling)
    EXPECT_GE(r.max_upper[k], sampled[k]) << k;
    EXPECT_GE(sampled[k], r.max_upper[k] / 1.01) << k;
  }
  bool differs = false;
  for (int k = 0; k < 6; ++k)
    differs = differs || std::abs(plain.max_upper[k] - r.max_upper[k]) > 0.02 * r.max_upper[k];
  EXPECT_TRUE(differs);
}

// ---- command-line tool ------------------------------------------------------------------------------------------
namespace {

class TrajectoryCli : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/pkm_traj_cli_XXXXXX";
    ASSERT_NE(::mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream f(dir_ + "/" + name);
    f << text;
    return dir_ + "/" + name;
  }
  static std::string read(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  }
  /// Runs pkm_verify; returns the exit code, fills out / err.
  int run(const std::vector<std::string>& args, std::string& out, std::string& err) const {
    std::string cmd = "'" + std::string(PKM_PVERIFY_EXE) + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " > '" + dir_ + "/out.txt' 2> '" + dir_ + "/err.txt' < /dev/null";
    const int status = std::system(cmd.c_str());
    out = read(dir_ + "/out.txt");
    err = read(dir_ + "/err.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  static std::string join(const DVec& v) {
    std::string s;
    char buf[64];
    for (int i = 0; i < v.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g", v[i]);
      s += (i ? "," : "") + std::string(buf);
    }
    return s;
  }
  std::string dir_;
};

const char* kSlerpFile =
    "interpolation: slerp\n"
    "waypoints:\n"
    "  - [0.0, -0.10, 0.05, 0.46, 0.25, -0.20, 0.15]\n"
    "  - [1.0,  0.00, 0.00, 0.47, 0.00,  0.10, 0.00]\n"
    "  - [3.0,  0.12, -0.08, 0.49, -0.20, 0.30, -0.25]\n";

}  // namespace

TEST_F(TrajectoryCli, VerifiesATrajectoryAndReportsTheWitnessTime) {
  const std::string file = write("slerp.yaml", kSlerpFile);
  const io::TrajectoryFile traj = io::loadTrajectoryFile(file);
  const Sampled s = sample(*traj.trajectory, 20000);
  const std::string robot = test::configPath("ref6.yaml");
  std::string out, err;
  // SAFE at +10%: empty list of undecided time intervals.
  ASSERT_EQ(
      run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.1), "--json", dir_ + "/safe.json"},
          out, err),
      0)
      << out << err;
  EXPECT_NE(out.find("trajectory: " + file + " (waypoints (slerp), 3 waypoints), t in [0, 3] s"), std::string::npos)
      << out;
  const YAML::Node safe = YAML::LoadFile(dir_ + "/safe.json");  // JSON is YAML
  EXPECT_EQ(safe["verdict"].as<std::string>(), "SAFE");
  EXPECT_EQ(safe["domain"].as<std::string>(), "trajectory");
  EXPECT_EQ(safe["trajectory"].as<std::string>(), file);
  EXPECT_TRUE(safe["workspace"].IsNull());
  EXPECT_TRUE(safe["witness_t"].IsNull());
  EXPECT_EQ(safe["time_span"][1].as<double>(), 3.0);
  EXPECT_EQ(safe["undecided_t"].size(), 0u);
  EXPECT_EQ(safe["variables"][0].as<std::string>(), "u");

  // UNSAFE at -5%: witness_t is the time of witness_variables[0] and its nominal pose exceeds the threshold.
  const DVec thresholds = s.max * 0.95;
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--thresholds", join(thresholds), "--json",
                 dir_ + "/unsafe.json", "--yaml", dir_ + "/unsafe.yaml"},
                out, err),
            1)
      << out << err;
  EXPECT_NE(out.find("witness:   t = "), std::string::npos) << out;
  const YAML::Node j = YAML::LoadFile(dir_ + "/unsafe.json");
  EXPECT_EQ(j["verdict"].as<std::string>(), "UNSAFE");
  const double t = j["witness_t"].as<double>(), u = j["witness_variables"][0].as<double>();
  EXPECT_NEAR(t, 3.0 * u, 1e-12);
  const int k = j["witness_component"].as<int>();
  EXPECT_GT(worstError(traj.trajectory->pointAtTime(t).pose)[k], thresholds[k]);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(j["witness"][i].as<double>(), traj.trajectory->pointAtTime(t).pose[i], 1e-9);
  }
  EXPECT_TRUE(j["undecided_t"].IsSequence());
  const YAML::Node y = YAML::LoadFile(dir_ + "/unsafe.yaml");
  EXPECT_EQ(y["witness_t"].as<double>(), t);

  // A time limit far too small: UNDECIDED, with the undecided part of the trajectory as time intervals.
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.0001), "--max-boxes", "3",
                 "--json", dir_ + "/undecided.json"},
                out, err),
            2)
      << out << err;
  const YAML::Node und = YAML::LoadFile(dir_ + "/undecided.json");
  ASSERT_GE(und["undecided_t"].size(), 1u);
  for (std::size_t i = 0; i < und["undecided_t"].size(); ++i) {
    const double lo = und["undecided_t"][i][0].as<double>(), hi = und["undecided_t"][i][1].as<double>();
    EXPECT_LE(0.0, lo);
    EXPECT_LE(lo, hi);
    EXPECT_LE(hi, 3.0);
  }
  EXPECT_NE(out.find("in time: ["), std::string::npos) << out;

  // max-error: the argmax of every component as a parameter, a time and a pose (which attains the lower bound).
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--mode", "max-error", "--alpha", "0.02", "--json",
                 dir_ + "/max.json"},
                out, err),
            0)
      << out << err;
  const YAML::Node mx = YAML::LoadFile(dir_ + "/max.json");
  ASSERT_EQ(mx["max_error"]["argmax_t"].size(), 6u);
  for (int c = 0; c < 6; ++c) {
    const double tc = mx["max_error"]["argmax_t"][c].as<double>();
    EXPECT_NEAR(tc, 3.0 * mx["max_error"]["argmax_variables"][c][0].as<double>(), 1e-12);
    EXPECT_GE(mx["max_error"]["upper"][c].as<double>(), s.max[c] * (1 - 1e-9));
    ASSERT_EQ(mx["max_error"]["argmax"][c].size(), 6u);
    DVec pose(6);
    for (int i = 0; i < 6; ++i) pose[i] = mx["max_error"]["argmax"][c][i].as<double>();
    EXPECT_LT((pose - traj.trajectory->pointAtTime(tc).pose).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_GE(worstError(pose)[c], mx["max_error"]["lower"][c].as<double>() * (1 - 1e-9));
  }

  // --min-width takes one value per parameter.
  EXPECT_EQ(
      run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.1), "--min-width", "1e-6"}, out, err),
      0)
      << err;
}

TEST_F(TrajectoryCli, BadTrajectoryInputExitsThree) {
  const std::string robot = test::configPath("ref6.yaml");
  const std::string good = write("good.yaml", kSlerpFile);
  const std::string t6 = "1e-4,1e-4,1e-4,1e-3,1e-3,1e-3";
  const std::string decreasing = write("decreasing.yaml",
                                       "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [2, 0, 0, 0.47, 0, 0, 0]\n"
                                       "  - [1, 0, 0, 0.47, 0, 0, 0]\n");
  const std::string shortRow = write("short.yaml", "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0]\n");
  const std::string nan =
      write("nan.yaml", "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, .nan, 0, 0.47, 0, 0, 0]\n");
  const std::vector<std::pair<std::vector<std::string>, std::vector<std::string>>> cases = {
      {{"--robot", robot, "--workspace", "paper", "--trajectory", good, "--thresholds", t6},
       {"--trajectory", "--workspace"}},
      {{"--robot", robot, "--trajectory", decreasing, "--thresholds", t6},
       {"--trajectory", "decreasing.yaml: waypoints[2][0]", "not greater"}},
      {{"--robot", robot, "--trajectory", shortRow, "--thresholds", t6},
       {"--trajectory", "short.yaml: waypoints[1]", "expected 7 numbers"}},
      {{"--robot", robot, "--trajectory", nan, "--thresholds", t6}, {"nan.yaml: waypoints[1][1]", "finite"}},
      {{"--robot", robot, "--trajectory", dir_ + "/missing.yaml", "--thresholds", t6},
       {"--trajectory", "missing.yaml"}},
      {{"--robot", robot, "--trajectory", dir_, "--thresholds", t6}, {"--trajectory", "not a regular file"}},
      {{"--robot", robot, "--trajectory", good, "--thresholds", t6, "--min-width", "1,2"},
       {"--min-width", "expected 1 comma-separated value", "got 2"}},
      {{"--robot", robot, "--trajectory", good, "--thresholds", t6, "--min-width", "-1"}, {"--min-width[0] (u)"}},
      {{"--robot", robot, "--trajectory", "", "--thresholds", t6}, {"--trajectory", "empty"}},
  };
  for (const auto& c : cases) {
    std::string line;
    for (const auto& a : c.first) line += a + " ";
    SCOPED_TRACE(line);
    std::string out, err;
    EXPECT_EQ(run(c.first, out, err), 3) << out << err;
    EXPECT_TRUE(out.empty()) << out;
    EXPECT_EQ(err.rfind("pkm_verify: error: ", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    for (const auto& m : c.second) EXPECT_NE(err.find(m), std::string::npos) << "'" << m << "' in: " << err;
  }
}

TEST_F(TrajectoryCli, VarietyFromTheCommandLine) {
  const std::string file = write("variety.yaml",
                                 "variety:\n"
                                 "  parameters: 2\n"
                                 "  x: [[-0.05, 0, 0], [0.1, 1, 0]]\n"
                                 "  y: [[-0.05, 0, 0], [0.1, 0, 1]]\n"
                                 "  z: [[0.47, 0, 0]]\n"
                                 "  yaw: [[0.2, 1, 1]]\n");
  std::string out, err;
  ASSERT_EQ(run({"--robot", test::configPath("ref6.yaml"), "--trajectory", file, "--thresholds",
                 "1e-3,1e-3,1e-3,1e-2,1e-2,1e-2", "--json", dir_ + "/v.json"},
                out, err),
            0)
      << out << err;
  const YAML::Node j = YAML::LoadFile(dir_ + "/v.json");
  EXPECT_EQ(j["domain"].as<std::string>(), "variety");
  EXPECT_TRUE(j["witness_t"].IsNull());
  EXPECT_TRUE(j["time_span"].IsNull());
  EXPECT_EQ(j["variables"].size(), 2u);
  EXPECT_NE(out.find("variety:   " + file), std::string::npos) << out;
}
