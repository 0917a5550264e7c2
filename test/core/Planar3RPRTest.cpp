// The planar 3-RPR model and its workspace, and the generic enclosures and verifier on a robot with
// three degrees of freedom: against an independent implementation of the inverse kinematics (leg lengths from
// Eigen's Rotation2D), central finite differences and dense double-precision sampling. (Its robot file's reader:
// test/io/PlanarRobotFileTest.cpp.)
#include <gtest/gtest.h>
#include <Eigen/LU>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PlanarWorkspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/robots/Planar3RPRKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/PlanarRobotFile.hpp"

using namespace pkm_accuracy;
using verify::Verdict;

namespace {

io::PlanarRobotFile planarFile() { return io::loadPlanarRobotFile(test::configPath("planar3rpr.yaml")); }

// Leg lengths with the tool point t (base frame) and orientation theta: B_i = t + R(theta) (b_i - c).
Eigen::Vector3d lengths(const model::Planar3RPRGeometry& g, const Eigen::Vector2d& t, double theta) {
  const Eigen::Rotation2Dd r(theta);
  Eigen::Vector3d l;
  for (int i = 0; i < 3; ++i) l[i] = (t + r * (g.platform_anchors[i] - g.tool_point) - g.base_anchors[i]).norm();
  return l;
}

DVec pose3(double x, double y, double theta) {
  DVec v(3);
  v << x, y, theta;
  return v;
}

IVec thinBox(const DVec& q) {
  IVec b(q.size());
  for (int i = 0; i < q.size(); ++i) b[i] = Interval(q[i]);
  return b;
}

/// Maximum of every component over random points and the corners of a box (a lower estimate of the true maxima),
/// restricted to the points the domain contains.
DVec sampledMaxima(const model::RobotModel& robot, const domain::Domain& dom, int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const IVec& box = dom.initialBox();
  DVec best = DVec::Zero(robot.dof());
  auto account = [&](const DVec& q) {
    if (dom.classify(thinBox(q)) != domain::Containment::Inside) return;
    const DVec f = robot.worstErrorAt(q);
    for (int k = 0; k < robot.dof(); ++k) best[k] = std::max(best[k], f[k]);
  };
  for (int s = 0; s < samples; ++s) account(test::randomPoint(box, rng));
  for (int corner = 0; corner < (1 << box.size()); ++corner) {
    DVec q(box.size());
    for (int i = 0; i < box.size(); ++i) q[i] = (corner >> i) & 1 ? box[i].upper() : box[i].lower();
    account(q);
  }
  return best;
}

/// Similar triangles (b_i = A_i / 4, exactly representable): at (0, 0, 0) the three legs meet at the origin.
model::Planar3RPRGeometry concurrentLegsGeometry() {
  model::Planar3RPRGeometry g;
  g.base_anchors = {Eigen::Vector2d(0.0, 0.5), Eigen::Vector2d(-0.5, -0.25), Eigen::Vector2d(0.5, -0.25)};
  for (const auto& a : g.base_anchors) g.platform_anchors.push_back(a / 4.0);
  g.sensor_error = {1e-5, 1e-5, 1e-5};
  return g;
}

}  // namespace

// ---- model ---------------------------------------------------------------------------------------------------------

TEST(Planar3RPR, InterfaceDescribesThreeComponents) {
  const auto robotPtr = model::makePlanar3RPR(planarFile().geometry);
  const auto& robot = *robotPtr;
  EXPECT_EQ(robot.dof(), 3);
  EXPECT_EQ(robot.name(), "planar3rpr");
  EXPECT_EQ(robot.componentName(0), "dx [m]");
  EXPECT_EQ(robot.componentName(1), "dy [m]");
  EXPECT_EQ(robot.componentName(2), "dtheta [rad]");
  EXPECT_EQ(robot.componentName(3), "?");
  EXPECT_FALSE(robot.isAngular(0));
  EXPECT_FALSE(robot.isAngular(1));
  EXPECT_TRUE(robot.isAngular(2));
  EXPECT_EQ(robot.sensorError().size(), 3u);
  EXPECT_FALSE(robot.hasGeometryUncertainty());
}

TEST(Planar3RPR, InverseJacobianMatchesFiniteDifferencesOfLegLengths) {
  for (const bool withTool : {false, true}) {
    io::PlanarRobotFile rf = planarFile();
    if (withTool) rf.geometry.tool_point = Eigen::Vector2d(0.02, -0.03);
    const auto robotPtr = model::makePlanar3RPR(rf.geometry);
    const auto& robot = *robotPtr;
    std::mt19937_64 rng(7);
    const IVec box = rf.workspaces.at("reference").initialBox();
    for (int trial = 0; trial < 500; ++trial) {
      const DVec q = test::randomPoint(box, rng);
      const Eigen::Vector2d t = q.head<2>() + Eigen::Rotation2Dd(q[2]) * rf.geometry.tool_point;  // base frame
      const DMat m = robot.inverseJacobian(q);
      ASSERT_EQ(m.rows(), 3);
      ASSERT_EQ(m.cols(), 3);
      const double h = 1e-6;
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d e = Eigen::Vector2d::Unit(k) * h;
        const Eigen::Vector3d d = (lengths(rf.geometry, t + e, q[2]) - lengths(rf.geometry, t - e, q[2])) / (2 * h);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(m(i, k), d[i], 1e-8) << "leg " << i << " translation " << k;
      }
      // Rotation about the tool point (the tool point stays where it is).
      const Eigen::Vector3d dr = (lengths(rf.geometry, t, q[2] + h) - lengths(rf.geometry, t, q[2] - h)) / (2 * h);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(m(i, 2), dr[i], 1e-8) << "leg " << i << " rotation";
      // Leg lengths agree with the independent formula, and their enclosures contain them.
      const DVec l = robot.legLengths(q);
      const IVec li = robot.jointCoordinates(thinBox(q));
      const Eigen::Vector3d ref = lengths(rf.geometry, t, q[2]);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(l[i], ref[i], 1e-14);
        EXPECT_TRUE(li[i].contains(l[i])) << li[i] << " " << l[i];
      }
    }
  }
}

TEST(Planar3RPR, JacobianTimesInverseIsIdentity) {
  const io::PlanarRobotFile rf = planarFile();
  const auto robotPtr = model::makePlanar3RPR(rf.geometry);
  const auto& robot = *robotPtr;
  std::mt19937_64 rng(11);
  const IVec box = rf.workspaces.at("reference").initialBox();
  for (int trial = 0; trial < 500; ++trial) {
    const DVec q = test::randomPoint(box, rng);
    const DMat j = robot.jacobian(q);
    EXPECT_LT((robot.inverseJacobian(q) * j - DMat::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((j * robot.inverseJacobian(q) - DMat::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(Planar3RPR, SingularPoseIsReportedNotNaN) {
  const auto robotPtr = model::makePlanar3RPR(concurrentLegsGeometry());
  const auto& robot = *robotPtr;
  const DVec q = pose3(0.0, 0.0, 0.0);
  // The three legs meet at the origin: no moment about it, the theta column of J^-1 vanishes.
  const DMat m = robot.inverseJacobian(q);
  EXPECT_TRUE(m.allFinite());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(m(i, 2), 0.0) << i;
  EXPECT_THROW(robot.jacobian(q), SingularMatrix);
  EXPECT_THROW(robot.worstErrorAt(q), SingularMatrix);
  const DVec f = enclosure::errorAtPoseDouble(robot, q);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isinf(f[k])) << k;
  IVec fi;
  EXPECT_FALSE(enclosure::errorAtPose(robot, thinBox(q), fi));
  // Every enclosure method gives +inf (never NaN, never a finite bound) on boxes around the singular pose.
  const domain::PlanarWorkspace ws =
      domain::PlanarWorkspace::fromRanges({Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.02, 0.02)});
  for (const std::string& name : enclosure::enclosureNames()) {
    const auto method = enclosure::makeEnclosure(name);
    for (const double scale : {1.0, 1e-3}) {
      IVec box(3);
      for (int i = 0; i < 3; ++i) box[i] = ws.initialBox()[i] * Interval(scale);
      enclosure::BoxInput in;
      ws.poseView(box, method->needsGradient(), in);
      enclosure::ErrorBounds b;
      method->enclose(robot, in, b);
      ASSERT_EQ(b.upper.size(), 3) << name;
      EXPECT_FALSE(b.bounded()) << name;
      for (int k = 0; k < 3; ++k) EXPECT_FALSE(std::isnan(b.upper[k])) << name << " " << k;
    }
  }
  // A workspace containing the singular pose is never SAFE.
  verify::VerifierOptions o;
  o.thresholds = DVec::Constant(3, 1.0);
  o.max_boxes = 20000;
  o.time_limit_s = 2.0;
  const auto r = verify::Verifier::run(robot, ws, o);
  EXPECT_NE(r.verdict, Verdict::Safe) << r.message;
}

TEST(Planar3RPR, IntervalEnclosuresContainPointValuesAndDerivatives) {
  const io::PlanarRobotFile rf = planarFile();
  model::Planar3RPRGeometry g = rf.geometry;
  g.tool_point = Eigen::Vector2d(0.01, 0.02);
  const auto robotPtr = model::makePlanar3RPR(g);
  const auto& robot = *robotPtr;
  std::mt19937_64 rng(3);
  const IVec ws = rf.workspaces.at("reference").initialBox();
  std::uniform_real_distribution<double> frac(0.0, 0.3);
  for (int trial = 0; trial < 300; ++trial) {
    // Random sub-box, some dimensions of zero width.
    const DVec c = test::randomPoint(ws, rng);
    IVec box(3);
    for (int i = 0; i < 3; ++i) {
      const double h = (trial % 5 == i) ? 0.0 : frac(rng) * 0.5 * (ws[i].upper() - ws[i].lower());
      box[i] = Interval(c[i] - h, c[i] + h);
    }
    const IMat mi = robot.inverseJacobian(box);
    MatrixWithGradient mg;
    DualPose dp;
    for (int i = 0; i < 3; ++i) dp[i] = DualI::variable(box[i], i);
    robot.inverseJacobian(dp, mg);
    ASSERT_EQ(mg.value.rows(), 3);
    ASSERT_EQ(mg.value.cols(), 3);
    // Derivatives with respect to box variables the pose does not depend on are zero.
    for (int v = 0; v < kMaxDof; ++v) {
      ASSERT_EQ(mg.d[v].rows(), 3);
      ASSERT_EQ(mg.d[v].cols(), 3);
      if (v < 3) continue;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_EQ(mg.d[v](i, j), Interval(0.0));
    }
    for (int s = 0; s < 20; ++s) {
      const DVec q = test::randomPoint(box, rng);
      const DMat m = robot.inverseJacobian(q);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const double slack = 1e-13 * (1.0 + std::abs(m(i, j)));
          EXPECT_LE(mi(i, j).lower() - slack, m(i, j));
          EXPECT_GE(mi(i, j).upper() + slack, m(i, j));
          EXPECT_LE(mg.value(i, j).lower() - slack, m(i, j));
          EXPECT_GE(mg.value(i, j).upper() + slack, m(i, j));
        }
      }
      // Central differences of J^-1 lie in the derivative enclosures (up to the difference error).
      const double h = 1e-6;
      for (int v = 0; v < 3; ++v) {
        if (box[v].isPoint()) continue;
        DVec qp = q, qm = q;
        qp[v] += h;
        qm[v] -= h;
        const DMat d = (robot.inverseJacobian(qp) - robot.inverseJacobian(qm)) / (2 * h);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            EXPECT_LE(mg.d[v](i, j).lower() - 1e-6, d(i, j));
            EXPECT_GE(mg.d[v](i, j).upper() + 1e-6, d(i, j));
          }
      }
    }
  }
}

TEST(Planar3RPR, RejectsInvalidGeometry) {
  const model::Planar3RPRGeometry ok = planarFile().geometry;
  auto expectThrowNaming = [](const model::Planar3RPRGeometry& g, const std::string& field) {
    try {
      model::makePlanar3RPR(g);
      FAIL() << "expected InvalidGeometry naming " << field;
    } catch (const InvalidGeometry& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  model::Planar3RPRGeometry g = ok;
  g.base_anchors[2] = g.base_anchors[1];
  expectThrowNaming(g, "base_anchors[2]");
  g = ok;
  g.platform_anchors.pop_back();
  expectThrowNaming(g, "platform_anchors");
  g = ok;
  g.base_anchors.push_back(Eigen::Vector2d(1.0, 1.0));
  expectThrowNaming(g, "base_anchors");
  g = ok;
  g.sensor_error[1] = 0.0;
  expectThrowNaming(g, "sensor_error[1]");
  g = ok;
  g.sensor_error[2] = std::nan("");
  expectThrowNaming(g, "sensor_error[2]");
  g = ok;
  g.sensor_error.pop_back();
  expectThrowNaming(g, "sensor_error");
  g = ok;
  g.platform_anchors[0].y() = std::numeric_limits<double>::infinity();
  expectThrowNaming(g, "platform_anchors[0]");
  g = ok;
  g.tool_point.x() = std::nan("");
  expectThrowNaming(g, "tool_point");
}

// ---- workspace -------------------------------------------------------------------------------------------------

TEST(PlanarWorkspace, BoxRangesPoseViewAndValidation) {
  const auto ws = domain::PlanarWorkspace::fromRanges({Interval(-0.1, 0.1), Interval(0.0, 0.2), Interval(-0.3, 0.3)});
  EXPECT_EQ(ws.variables(), 3);
  EXPECT_EQ(ws.variableName(2), "theta [rad]");
  EXPECT_FALSE(ws.isDisc());
  ASSERT_EQ(ws.initialBox().size(), 3);
  EXPECT_EQ(ws.initialBox()[1], Interval(0.0, 0.2));
  EXPECT_EQ(ws.classify(ws.initialBox()), domain::Containment::Inside);
  EXPECT_EQ(ws.classify(thinBox(pose3(0.0, 0.1, 0.0))), domain::Containment::Inside);
  EXPECT_EQ(ws.classify(thinBox(pose3(0.0, 0.3, 0.0))), domain::Containment::Outside);

  const IVec box = test::centredSubBox(ws.initialBox(), 0.5);
  enclosure::BoxInput in;
  ws.poseView(box, true, in);
  EXPECT_EQ(in.variables, 3);
  EXPECT_TRUE(in.hasGradient);
  ASSERT_EQ(in.pose.size(), 3);
  ASSERT_EQ(in.centrePose.size(), 3);
  ASSERT_EQ(in.deviation.size(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(in.pose[i], box[i]);
    EXPECT_TRUE(in.centrePose[i].isPoint());
    EXPECT_TRUE(box[i].contains(in.centrePose[i].lower()));
    EXPECT_TRUE(in.deviation[i].contains(box[i].lower() - in.centrePose[i].lower()));
    EXPECT_EQ(in.dualPose[i].value(), box[i]);
    for (int v = 0; v < kMaxDof; ++v) EXPECT_EQ(in.dualPose[i].d(v), Interval(v == i ? 1.0 : 0.0));
  }
  const IVec p = ws.poseAt(pose3(0.01, 0.02, 0.03));
  ASSERT_EQ(p.size(), 3);
  EXPECT_EQ(p[2], Interval(0.03));

  try {
    domain::PlanarWorkspace::fromRanges({Interval(-0.1, 0.1), Interval(0.0, 0.2), Interval::entire()});
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("theta"), std::string::npos) << e.what();
  }
  EXPECT_THROW(domain::PlanarWorkspace::fromRanges({Interval::empty(), Interval(0.0, 0.2), Interval(0.0)}),
               InvalidArgument);
  EXPECT_THROW(domain::PlanarWorkspace::disc(Eigen::Vector2d(0.0, 0.0), 0.0, Interval(0.0)), InvalidArgument);
}

TEST(PlanarWorkspace, DiscClassification) {
  const auto ws = domain::PlanarWorkspace::disc(Eigen::Vector2d(0.1, -0.1), 0.1, Interval(-0.2, 0.2));
  EXPECT_TRUE(ws.isDisc());
  EXPECT_TRUE(ws.initialBox()[0].contains(0.0) && ws.initialBox()[0].contains(0.2));
  EXPECT_TRUE(ws.initialBox()[1].contains(-0.2) && ws.initialBox()[1].contains(0.0));
  auto box = [](double x0, double x1, double y0, double y1) {
    IVec b(3);
    b << Interval(x0, x1), Interval(y0, y1), Interval(-0.1, 0.1);
    return b;
  };
  EXPECT_EQ(ws.classify(box(0.09, 0.11, -0.11, -0.09)), domain::Containment::Inside);
  EXPECT_EQ(ws.classify(ws.initialBox()), domain::Containment::Partial);
  EXPECT_EQ(ws.classify(box(0.0, 0.01, -0.01, 0.0)), domain::Containment::Outside);  // bounding-box corner
  EXPECT_EQ(ws.classify(box(0.3, 0.4, -0.1, 0.0)), domain::Containment::Outside);    // beyond the bounds
  EXPECT_EQ(ws.classify(box(0.15, 0.2, -0.1, -0.05)), domain::Containment::Partial);
  // Random points: the classification of thin boxes agrees with the disc inequality (away from the circle).
  std::mt19937_64 rng(5);
  for (int s = 0; s < 2000; ++s) {
    const DVec q = test::randomPoint(ws.initialBox(), rng);
    const double r = std::hypot(q[0] - 0.1, q[1] + 0.1);
    if (std::abs(r - 0.1) < 1e-12) continue;
    EXPECT_EQ(ws.classify(thinBox(q)), r < 0.1 ? domain::Containment::Inside : domain::Containment::Outside);
  }
}

// ---- enclosures and verifier on a 3-dof robot ------------------------------------------------------------------

TEST(PlanarEnclosure, EveryMethodIsSoundOnRandomBoxes) {
  const io::PlanarRobotFile rf = planarFile();
  model::Planar3RPRGeometry g = rf.geometry;
  g.tool_point = Eigen::Vector2d(0.01, -0.02);
  g.sensor_error = {1e-5, 2e-5, 1.5e-5};
  const auto robotPtr = model::makePlanar3RPR(g);
  const auto& robot = *robotPtr;
  const domain::PlanarWorkspace& ws = rf.workspaces.at("reference");
  const IVec& full = ws.initialBox();
  for (const std::string& name : enclosure::enclosureNames()) {
    const auto method = enclosure::makeEnclosure(name);
    std::mt19937_64 rng(17);
    int bounded = 0, boundedSmall = 0, small = 0;
    std::uniform_int_distribution<int> pickScale(0, 3);
    const double scales[4] = {1e-3, 1e-2, 0.1, 0.5};
    for (int trial = 0; trial < 200; ++trial) {
      const int si = pickScale(rng);
      const DVec c = test::randomPoint(full, rng);
      IVec box(3);
      for (int i = 0; i < 3; ++i) {
        const double h = (trial % 7 == i) ? 0.0 : scales[si] * 0.5 * (full[i].upper() - full[i].lower());
        box[i] = Interval(c[i] - h, c[i] + h);
      }
      enclosure::BoxInput in;
      ws.poseView(box, method->needsGradient(), in);
      enclosure::ErrorBounds b;
      method->enclose(robot, in, b);
      ASSERT_EQ(b.upper.size(), 3) << name;
      if (si == 0) ++small;
      if (!b.bounded()) continue;
      ++bounded;
      if (si == 0) ++boundedSmall;
      for (int s = 0; s < 20; ++s) {
        const DVec q = s == 0 ? domain::centreOf(box) : test::randomPoint(box, rng);
        IVec f;
        ASSERT_TRUE(enclosure::errorAtPose(robot, thinBox(q), f)) << name;
        const DVec fd = robot.worstErrorAt(q);
        for (int k = 0; k < 3; ++k) {
          // Certified lower bound at a point <= certified upper bound over the box; the point value in between.
          EXPECT_LE(f[k].lower(), b.upper[k]) << name << " component " << k;
          EXPECT_TRUE(f[k].contains(fd[k]) || std::abs(fd[k] - f[k].mid()) <= 1e-12 * fd[k]) << name;
          EXPECT_LE(fd[k], b.upper[k]) << name << " component " << k;
          if (b.lower.size() == 3) {
            EXPECT_LE(b.lower[k], fd[k] * (1 + 1e-12)) << name << " component " << k;
          }
        }
      }
    }
    EXPECT_GT(bounded, 0) << name;
    EXPECT_EQ(boundedSmall, small) << name << ": every box of 1e-3 of the workspace should be bounded";
  }
}

TEST(PlanarVerifier, SafeTenPercentAboveSampledMaximaUnsafeFivePercentBelow) {
  const io::PlanarRobotFile rf = planarFile();
  const auto robotPtr = model::makePlanar3RPR(rf.geometry);
  const auto& robot = *robotPtr;
  const domain::PlanarWorkspace& ws = rf.workspaces.at("reference");
  const DVec maxima = sampledMaxima(robot, ws, 20000, 1);
  verify::VerifierOptions o;
  o.thresholds = maxima * 1.10;
  const auto safe = verify::Verifier::run(robot, ws, o);
  EXPECT_EQ(safe.verdict, Verdict::Safe) << safe.message;
  EXPECT_EQ(safe.undecided_box_count, 0u);
  EXPECT_NEAR(safe.stats.safe_fraction, 1.0, 1e-9);

  o.thresholds = maxima * 0.95;
  const auto unsafe = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(unsafe.verdict, Verdict::Unsafe) << unsafe.message;
  const int k = unsafe.witness_component;
  ASSERT_GE(k, 0);
  ASSERT_LT(k, 3);
  ASSERT_EQ(unsafe.witness.size(), 3);
  ASSERT_EQ(unsafe.witness_pose.size(), 3);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(ws.initialBox()[i].contains(unsafe.witness[i]));
  EXPECT_GT(robot.worstErrorAt(unsafe.witness)[k], o.thresholds[k]);
  EXPECT_GT(unsafe.witness_lower_bound, o.thresholds[k]);
  EXPECT_LE(unsafe.witness_lower_bound, robot.worstErrorAt(unsafe.witness)[k] * (1 + 1e-9));
  EXPECT_NE(unsafe.message.find(robot.componentName(k)), std::string::npos) << unsafe.message;
}

TEST(PlanarVerifier, SingularWorkspaceIsUnsafeForAnyThreshold) {
  // The legs of this geometry meet at the origin at theta = 0: a singular pose inside the workspace, certified
  // through a sign change of det J^-1 (checked here in double at the two ends) whatever the thresholds.
  const auto robotPtr = model::makePlanar3RPR(concurrentLegsGeometry());
  const auto& robot = *robotPtr;
  const domain::PlanarWorkspace ws =
      domain::PlanarWorkspace::fromRanges({Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.02, 0.02)});
  verify::VerifierOptions o;
  o.thresholds = DVec::Constant(3, 1e15);
  o.time_limit_s = 20.0;
  const auto r = verify::Verifier::run(robot, ws, o);
  ASSERT_EQ(r.verdict, Verdict::Unsafe) << r.message;
  ASSERT_TRUE(r.singular) << r.message;
  ASSERT_EQ(r.singular_from.size(), 3);
  ASSERT_EQ(r.singular_to.size(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(ws.initialBox()[i].contains(r.singular_from[i])) << i;
    EXPECT_TRUE(ws.initialBox()[i].contains(r.singular_to[i])) << i;
  }
  const double a = robot.inverseJacobian(DVec(r.singular_from)).determinant();
  const double b = robot.inverseJacobian(DVec(r.singular_to)).determinant();
  EXPECT_LT(a * b, 0.0) << a << " " << b;
  EXPECT_LT(r.stats.boxes, 1000u);
}

TEST(PlanarVerifier, MaxErrorBracketsSampledMaxima) {
  const io::PlanarRobotFile rf = planarFile();
  const auto robotPtr = model::makePlanar3RPR(rf.geometry);
  const auto& robot = *robotPtr;
  for (const std::string wsName : {"reference", "disc"}) {
    const domain::PlanarWorkspace& ws = rf.workspaces.at(wsName);
    const DVec maxima = sampledMaxima(robot, ws, 20000, 2);
    verify::VerifierOptions o;
    o.mode = verify::Mode::MaxError;
    o.alpha = 0.01;
    const auto r = verify::Verifier::run(robot, ws, o);
    ASSERT_TRUE(r.converged) << wsName << ": " << r.message;
    ASSERT_EQ(r.max_upper.size(), 3);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(r.max_upper[k], maxima[k]) << wsName << " " << k;
      EXPECT_GE(r.max_lower[k], maxima[k] * (1 - 0.02)) << wsName << " " << k;  // sampling comes close
      EXPECT_LE(r.max_upper[k] - r.max_lower[k], o.alpha * r.max_lower[k] * (1 + 1e-9)) << wsName << " " << k;
      // The lower bound is attained at the reported point, which belongs to the workspace.
      ASSERT_EQ(r.max_argmax[k].size(), 3);
      EXPECT_EQ(ws.classify(thinBox(r.max_argmax[k])), domain::Containment::Inside) << wsName << " " << k;
      EXPECT_GE(robot.worstErrorAt(r.max_argmax[k])[k], r.max_lower[k] * (1 - 1e-9)) << wsName << " " << k;
    }
  }
}
