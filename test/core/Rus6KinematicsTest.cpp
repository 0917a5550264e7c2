// The 6-RUS hexapod (type rus6, Rus6Kinematics through KinematicModel): its reference file, its inverse kinematics
// against an independent implementation (Eigen rotations, the crank angle from atan2 / acos and the branch from its
// defining property), J^-1 against central differences of that implementation under the Gough error convention, and
// every enclosure KinematicModel derives from the templated J^-1 against double values and differences.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "KinematicModelChecks.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/core/model/robots/Rus6Kinematics.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"

using namespace pkm_accuracy;
using model::Rus6Kinematics;

namespace {

using Model = model::KinematicModel<Rus6Kinematics>;

/// The reference robot file as pkm_verify and the node read it.
const io::ModelFile& rus6File() {
  static const io::ModelFile file = io::loadModelFile(test::configPath("rus6.yaml"));
  return file;
}

IVec referenceBox() { return rus6File().workspaces.at("reference")->initialBox(); }

Model referenceModel() { return Model(Rus6Kinematics(), rus6File().description); }

/// The geometry of a description as the independent implementation reads it.
struct Geometry {
  Eigen::Vector3d a[6], b[6], c;
  double beta[6], r[6], l[6];
  explicit Geometry(const model::RobotDescription& d) {
    auto value = [&d](const std::string& name) {
      return d.geometry[static_cast<std::size_t>(d.geometryIndex(name))].nominal;
    };
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 6; ++i) {
      const std::string leg = "[" + std::to_string(i) + "]";
      for (int k = 0; k < 3; ++k) {
        a[i][k] = value("base_pivots" + leg + "." + axis[k]);
        b[i][k] = value("platform_anchors" + leg + "." + axis[k]);
      }
      beta[i] = value("crank_axis_angle" + leg);
      r[i] = value("crank_radius" + leg);
      l[i] = value("rod_length" + leg);
    }
    for (int k = 0; k < 3; ++k) c[k] = value(std::string("tool_point.") + axis[k]);
  }
  Eigen::Vector3d e1(int i) const { return Eigen::Vector3d(-std::sin(beta[i]), std::cos(beta[i]), 0.0); }
  Eigen::Vector3d crankEnd(int i, double theta) const {
    return a[i] + r[i] * (std::cos(theta) * e1(i) + std::sin(theta) * Eigen::Vector3d::UnitZ());
  }
  Eigen::Vector3d crankVelocity(int i, double theta) const {
    return -std::sin(theta) * e1(i) + std::cos(theta) * Eigen::Vector3d::UnitZ();
  }
};

Eigen::Matrix3d rotation(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// Independent inverse kinematics: the crank angle theta with |B - C(theta)| = l, a cos + b sin = rho cos(theta -
/// atan2(b, a)) = K, theta = atan2(b, a) +- acos(K / rho); the solution whose rod points along the crank end's
/// velocity ((B - C) . C'(theta) > 0). NaN where unreachable.
Eigen::Matrix<double, 6, 1> crankAngles(const Geometry& g, const Eigen::Vector3d& p, const Eigen::Matrix3d& rot) {
  Eigen::Matrix<double, 6, 1> theta;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d bi = p + rot * g.b[i], d = bi - g.a[i];
    const double a = d.dot(g.e1(i)), b = d.z();
    const double k = (d.squaredNorm() + g.r[i] * g.r[i] - g.l[i] * g.l[i]) / (2 * g.r[i]);
    const double phi = std::atan2(b, a), delta = std::acos(k / std::hypot(a, b));
    theta[i] = std::nan("");
    for (const double t : {phi + delta, phi - delta}) {
      if ((bi - g.crankEnd(i, t)).dot(g.crankVelocity(i, t)) > 0) theta[i] = std::remainder(t, 2 * M_PI);
    }
  }
  return theta;
}

Eigen::Matrix<double, 6, 1> crankAngles(const Geometry& g, const DVec& pose) {
  return crankAngles(g, pose.head<3>(), rotation(pose[3], pose[4], pose[5]));
}

/// The pose coordinates of a platform frame given by p and R (R = Rz(yaw) Ry(pitch) Rx(roll), |pitch| < pi / 2).
DVec poseOf(const Eigen::Vector3d& p, const Eigen::Matrix3d& rot) {
  DVec q(6);
  q << p, std::atan2(rot(2, 1), rot(2, 2)), std::asin(-rot(2, 0)), std::atan2(rot(1, 0), rot(0, 0));
  return q;
}

/// The description with a tool point off the platform origin (the error convention then matters).
model::RobotDescription withToolPoint(model::RobotDescription d) {
  d.geometry[Rus6Kinematics::tool(0)].nominal = 0.01;
  d.geometry[Rus6Kinematics::tool(1)].nominal = -0.02;
  d.geometry[Rus6Kinematics::tool(2)].nominal = 0.05;
  return d;
}

}  // namespace

TEST(Rus6Kinematics, ReferenceFileDescriptionAndRegistryAgree) {
  const io::ModelFile& file = rus6File();
  EXPECT_EQ(file.type, "rus6");
  EXPECT_TRUE(file.unknown_keys.empty());
  EXPECT_NE(dynamic_cast<const Model*>(file.model.get()), nullptr);
  ASSERT_EQ(file.workspaces.count("reference"), 1u);
  // The file with an uncertainty block: the group's values become the geometry parameters.
  {
    std::ifstream in(test::configPath("rus6.yaml"));
    std::stringstream text;
    text << in.rdbuf() << "uncertainty:\n  rod_length: 2.0e-4\n";
    const io::ModelFile uncertain = io::parseModelDocument(text.str(), "rus6.yaml + uncertainty");
    EXPECT_EQ(uncertain.model->geometryParameterCount(), 6);
    EXPECT_EQ(uncertain.model->geometryParameterName(0).rfind("rod_length", 0), 0u);
    const Interval range = uncertain.model->geometryParameterRange(0);
    EXPECT_NEAR(range.upper() - range.lower(), 4.0e-4, 1e-12);
  }
  const model::RobotDescription d = Rus6Kinematics::description();
  ASSERT_EQ(file.description.geometry.size(), static_cast<std::size_t>(Rus6Kinematics::kGeometryValues));
  for (std::size_t v = 0; v < d.geometry.size(); ++v)
    EXPECT_EQ(file.description.geometry[v].nominal, d.geometry[v].nominal) << d.geometry[v].name;
  EXPECT_EQ(file.description.sensor_error, std::vector<double>(6, 1e-4));
  // Index functions and names agree.
  EXPECT_EQ(d.geometry[Rus6Kinematics::basePivot(3, 1)].name, "base_pivots[3].y");
  EXPECT_EQ(d.geometry[Rus6Kinematics::crankAxisAngle(2)].name, "crank_axis_angle[2]");
  EXPECT_EQ(d.geometry[Rus6Kinematics::crankAxisAngle(2)].unit, "rad");
  EXPECT_EQ(d.geometry[Rus6Kinematics::crankRadius(5)].name, "crank_radius[5]");
  EXPECT_EQ(d.geometry[Rus6Kinematics::rodLength(0)].name, "rod_length[0]");
  EXPECT_EQ(d.geometry[Rus6Kinematics::platformAnchor(4, 2)].name, "platform_anchors[4].z");
  EXPECT_EQ(d.geometry[Rus6Kinematics::tool(1)].name, "tool_point.y");
  EXPECT_EQ(d.geometry[Rus6Kinematics::tool(1)].tool_point_coordinate, 1);
  const model::ModelType* type = model::ModelRegistry::global().find("rus6");
  ASSERT_NE(type, nullptr);
  EXPECT_EQ(type->description.geometry.size(), d.geometry.size());
  const auto robot = type->make(file.description);
  EXPECT_EQ(robot->dof(), 6);
  EXPECT_EQ(robot->name(), "rus6");
  EXPECT_EQ(robot->componentName(3), "drx [rad]");
  EXPECT_EQ(robot->jointName(4), "crank_4 [rad]");
  EXPECT_TRUE(robot->isAngular(5));
  EXPECT_FALSE(robot->isAngular(2));
  EXPECT_FALSE(robot->hasGeometryUncertainty());
  // Unset sensor errors are named.
  try {
    type->make(Rus6Kinematics::description());
    FAIL() << "expected InvalidGeometry";
  } catch (const InvalidGeometry& e) {
    EXPECT_NE(std::string(e.what()).find("sensor_error"), std::string::npos) << e.what();
  }
}

TEST(Rus6Kinematics, CrankAnglesCloseEveryLoopOnTheReferenceAssembly) {
  const model::RobotDescription d = withToolPoint(rus6File().description);
  const Geometry g(d);
  const Model robot(Rus6Kinematics(), d);
  // Where every crank is horizontal: all crank angles 0 (the claim of config/rus6.yaml).
  {
    const Eigen::Vector3d c0 = g.crankEnd(0, 0.0);
    const double h = std::sqrt(g.l[0] * g.l[0] - (g.b[0] - c0).head<2>().squaredNorm());
    EXPECT_NEAR(h, 0.3098, 1e-4);
    DVec home(6);
    home << 0, 0, h, 0, 0, 0;
    const DVec q = robot.legLengths(home);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(q[i], 0.0, 1e-12) << i;
  }
  std::mt19937_64 rng(1);
  const IVec box = referenceBox();
  double minSine = 1.0, maxAngle = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const DVec pose = trial % 2 ? test::randomPoint(box, rng) : test::randomFacePoint(box, rng);
    const DVec q = robot.legLengths(pose);
    const Eigen::Matrix<double, 6, 1> ref = crankAngles(g, pose);
    const IVec qi = robot.jointCoordinates(test::thinBox(pose));
    const Eigen::Matrix3d rot = rotation(pose[3], pose[4], pose[5]);
    for (int i = 0; i < 6; ++i) {
      ASSERT_TRUE(std::isfinite(q[i])) << i;
      EXPECT_NEAR(q[i], ref[i], 1e-12) << i;
      EXPECT_TRUE(test::encloses(qi[i], q[i], 0.0)) << i;
      // The loop closes: |B - C| = l, and the rod points along the crank end's velocity.
      const Eigen::Vector3d rod = pose.head<3>() + rot * g.b[i] - g.crankEnd(i, q[i]);
      EXPECT_NEAR(rod.norm(), g.l[i], 1e-12) << i;
      const double sine = rod.dot(g.crankVelocity(i, q[i])) / g.l[i];  // sine of the rod-crank angle
      EXPECT_GT(sine, 0.0) << i;
      minSine = std::min(minSine, sine);
      maxAngle = std::max(maxAngle, std::abs(q[i]));
    }
  }
  // The reference workspace's margins stated in config/rus6.yaml.
  EXPECT_GT(minSine, std::sin(40.0 * M_PI / 180.0));
  EXPECT_LT(maxAngle, 30.0 * M_PI / 180.0);
}

TEST(Rus6Kinematics, InverseJacobianIsTheDerivativeOfTheCrankAnglesInTheGoughConvention) {
  // Row i of J^-1 = d theta_i / d(t, omega): t the tool point (base frame), omega a small rotation about it.
  const model::RobotDescription d = withToolPoint(rus6File().description);
  const Geometry g(d);
  const Model robot(Rus6Kinematics(), d);
  std::mt19937_64 rng(2);
  IVec box = referenceBox();
  for (int i = 3; i < 6; ++i) box[i] = box[i] * Interval(4.0);  // wider orientations too
  for (int trial = 0; trial < 300; ++trial) {
    const DVec pose = test::randomPoint(box, rng);
    const Eigen::Matrix3d rot = rotation(pose[3], pose[4], pose[5]);
    const Eigen::Vector3d tool = pose.head<3>() + rot * g.c;
    const DMat m = robot.inverseJacobian(pose);
    ASSERT_TRUE(m.allFinite());
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(k) * h;
      const Eigen::Matrix<double, 6, 1> fd =
          (crankAngles(g, pose.head<3>() + e, rot) - crankAngles(g, pose.head<3>() - e, rot)) / (2 * h);
      for (int i = 0; i < 6; ++i)
        EXPECT_NEAR(m(i, k), fd[i], 1e-7 * (1 + std::abs(fd[i]))) << i << " translation " << k;
      const Eigen::Matrix3d rp = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k)) * rot;
      const Eigen::Matrix3d rm = Eigen::AngleAxisd(-h, Eigen::Vector3d::Unit(k)) * rot;
      const Eigen::Matrix<double, 6, 1> fr =
          (crankAngles(g, tool - rp * g.c, rp) - crankAngles(g, tool - rm * g.c, rm)) / (2 * h);
      for (int i = 0; i < 6; ++i)
        EXPECT_NEAR(m(i, 3 + k), fr[i], 1e-7 * (1 + std::abs(fr[i]))) << i << " rotation " << k;
      // The same rotation through the model's own inverse kinematics and pose coordinates.
      const DVec qp = robot.legLengths(poseOf(tool - rp * g.c, rp)), qm = robot.legLengths(poseOf(tool - rm * g.c, rm));
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(m(i, 3 + k), (qp[i] - qm[i]) / (2 * h), 1e-7 * (1 + std::abs(fr[i])));
    }
    EXPECT_LT((robot.inverseJacobian(pose) * robot.jacobian(pose) - DMat::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(Rus6Kinematics, IntervalEnclosuresContainSampledInverseJacobiansIncludingNearTheReachLimit) {
  const Model robot(Rus6Kinematics(), withToolPoint(rus6File().description));
  std::mt19937_64 rng(3);
  const IVec ws = referenceBox();
  const double scales[4] = {0.0, 0.01, 0.1, 0.5};
  int bounded = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const IVec box = test::randomSubBox(ws, scales[trial % 4], rng);
    if (test::checkInverseJacobianEnclosures(robot, box, 10, rng)) ++bounded;
  }
  EXPECT_EQ(bounded, 120);  // the reference workspace is reachable: every sub-box has bounded enclosures
  // Straight up from the workspace centre the rods end up aligned with their cranks (D -> 0, J^-1 unbounded).
  const DVec centre = domain::centreOf(ws);
  const DVec up = DVec::Unit(6, 2);
  const double t = test::reachLimit(robot, centre, up, 0.5);
  const double zmax = centre[2] + t;
  EXPECT_GT(zmax, 0.4);
  for (const double gap : {1e-2, 1e-3, 1e-4}) {
    IVec box = test::thinBox(centre);
    box[2] = Interval(zmax - gap - 1e-5, zmax - gap);  // reachable, close to the limit
    box[5] = Interval(-1e-4, 1e-4);
    EXPECT_TRUE(test::checkInverseJacobianEnclosures(robot, box, 10, rng)) << gap;
    box[2] = Interval(zmax - gap, zmax + gap);  // straddles it: unbounded, never NaN
    const IMat m = robot.inverseJacobian(box);
    bool unbounded = false;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        unbounded = unbounded || !m(i, j).isBounded();
        EXPECT_FALSE(m(i, j).isEmpty());
      }
    EXPECT_TRUE(unbounded) << gap;
    test::checkInverseJacobianEnclosures(robot, box, 10, rng);
  }
}

TEST(Rus6Kinematics, HessianEnclosuresContainCentralDifferencesAndBoundPreconditionedHessians) {
  const Model robot(Rus6Kinematics(), withToolPoint(rus6File().description));
  std::mt19937_64 rng(4);
  const IVec ws = referenceBox();
  for (int trial = 0; trial < 30; ++trial) {
    const IVec box = test::randomSubBox(ws, trial % 3 == 0 ? 0.0 : 0.05 * (trial % 3), rng);
    EXPECT_TRUE(test::checkHessianEnclosures(robot, box, 4, rng));
    test::checkPreconditionedHessian(robot, box, 5, rng);
  }
}

TEST(Rus6Kinematics, GeometryDerivativesContainFiniteDifferencesAndMoveOnlyTheirLegsRows) {
  model::RobotDescription d = withToolPoint(rus6File().description);
  auto uncertain = [&d](int value, double h) {
    d.geometry[static_cast<std::size_t>(value)].lo = -h;
    d.geometry[static_cast<std::size_t>(value)].hi = h;
  };
  uncertain(Rus6Kinematics::basePivot(1, 0), 1e-3);
  uncertain(Rus6Kinematics::basePivot(0, 2), 1e-3);
  uncertain(Rus6Kinematics::crankAxisAngle(2), 2e-3);
  uncertain(Rus6Kinematics::crankRadius(3), 5e-4);
  uncertain(Rus6Kinematics::rodLength(4), 5e-4);
  uncertain(Rus6Kinematics::platformAnchor(5, 1), 1e-3);
  uncertain(Rus6Kinematics::tool(0), 1e-3);
  const Model robot(Rus6Kinematics(), d);
  ASSERT_EQ(robot.geometryParameterCount(), 7);
  EXPECT_TRUE(robot.hasGeometryUncertainty());
  EXPECT_EQ(robot.toolPointCoordinate(6), 0);
  EXPECT_EQ(robot.toolPointCoordinate(0), -1);
  std::mt19937_64 rng(5);
  const IVec ws = referenceBox();
  for (int trial = 0; trial < 20; ++trial) {
    const IVec box = test::randomSubBox(ws, trial % 2 ? 0.02 : 0.0, rng);
    test::checkGeometryDerivatives(robot, box, 5, rng);
    GeometryDerivatives out;
    ASSERT_TRUE(robot.geometryDerivatives(box, out));
    // A leg's values move its row only; the tool point's x moves the rows of every leg.
    int toolRows = 0;
    for (int e = 0; e < out.count; ++e) {
      const GeometryRowDerivative& r = out.entries[static_cast<std::size_t>(e)];
      const std::string name = robot.geometryParameterName(r.parameter);
      if (name == "tool_point.x") {
        ++toolRows;
        continue;
      }
      EXPECT_NE(name.find("[" + std::to_string(r.row) + "]"), std::string::npos) << name << " row " << r.row;
    }
    EXPECT_EQ(toolRows, 6);
    // Enclosures over the box (every admissible geometry) contain J^-1 at sampled geometries: in the helper above.
  }
}

TEST(Rus6Kinematics, VerifierBracketsTheSampledMaximaOfTheReferenceWorkspace) {
  const Model robot = referenceModel();
  test::checkVerifier(robot, referenceBox(), 40000);
}
