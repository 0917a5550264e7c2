// The 3-PRS robot (type prs3, Prs3Kinematics through KinematicModel): its reference file, its parasitic motion and
// inverse kinematics against an independent implementation (Eigen: the zero-torsion rotation from
// Quaternion::FromTwoVectors, the platform centre by least squares from the three leg-plane constraints), J^-1 against
// central differences of that implementation, and every enclosure KinematicModel derives from the templated J^-1.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "KinematicModelChecks.hpp"
#include "TestRobots.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/core/model/robots/Prs3Kinematics.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"

using namespace pkm_accuracy;
using model::Prs3Kinematics;

namespace {

using Model = model::KinematicModel<Prs3Kinematics>;

/// The reference robot file as pkm_verify and the node read it.
const io::ModelFile& prs3File() {
  static const io::ModelFile file = io::loadModelFile(test::configPath("prs3.yaml"));
  return file;
}

IVec referenceBox() { return prs3File().workspaces.at("reference")->initialBox(); }

/// The description with different values per leg (so that a mixed-up index would show).
model::RobotDescription perturbed(model::RobotDescription d) {
  d.geometry[Prs3Kinematics::baseRadius(1)].nominal = 0.21;
  d.geometry[Prs3Kinematics::baseRadius(2)].nominal = 0.195;
  d.geometry[Prs3Kinematics::rodLength(0)].nominal = 0.31;
  d.geometry[Prs3Kinematics::rodLength(2)].nominal = 0.29;
  return d;
}

/// The independent implementation.
struct Reference {
  double base[3], rod[3], rp;
  explicit Reference(const model::RobotDescription& d) {
    for (int i = 0; i < 3; ++i) {
      base[i] = d.geometry[Prs3Kinematics::baseRadius(i)].nominal;
      rod[i] = d.geometry[Prs3Kinematics::rodLength(i)].nominal;
    }
    rp = d.geometry[Prs3Kinematics::kPlatformRadius].nominal;
  }
  static Eigen::Vector3d u(int i) {
    const double phi = (90.0 + 120.0 * i) * M_PI / 180.0;
    return Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
  }
  static Eigen::Vector3d t(int i) { return Eigen::Vector3d::UnitZ().cross(u(i)); }
  static Eigen::Matrix3d rotation(double tiltX, double tiltY) {
    const Eigen::Vector3d n = Eigen::AngleAxisd(tiltY, Eigen::Vector3d::UnitY()) *
                              (Eigen::AngleAxisd(tiltX, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ());
    return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n).toRotationMatrix();
  }
  /// The platform centre: p_z = z, (p_x, p_y) solving B_i . t_i = 0 in the least-squares sense; `residual` is
  /// what remains of the three constraints.
  Eigen::Vector3d centre(const DVec& pose, double* residual = nullptr) const {
    const Eigen::Matrix3d r = rotation(pose[1], pose[2]);
    Eigen::Matrix<double, 3, 2> m;
    Eigen::Vector3d rhs;
    for (int i = 0; i < 3; ++i) {
      m.row(i) = t(i).head<2>().transpose();
      rhs[i] = -rp * (r * u(i)).dot(t(i));
    }
    const Eigen::Vector2d xy = m.colPivHouseholderQr().solve(rhs);
    if (residual) *residual = (m * xy - rhs).norm();
    return Eigen::Vector3d(xy.x(), xy.y(), pose[0]);
  }
  Eigen::Vector3d anchor(const DVec& pose, int i) const {
    return centre(pose) + rp * (rotation(pose[1], pose[2]) * u(i));
  }
  Eigen::Vector3d sliders(const DVec& pose) const {
    Eigen::Vector3d q;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d b = anchor(pose, i);
      const double rho = b.dot(u(i)) - base[i];
      q[i] = b.z() - std::sqrt(rod[i] * rod[i] - rho * rho);
    }
    return q;
  }
};

DVec pose3(double z, double a, double b) {
  DVec q(3);
  q << z, a, b;
  return q;
}

}  // namespace

TEST(Prs3Kinematics, ReferenceFileDescriptionAndRegistryAgree) {
  const io::ModelFile& file = prs3File();
  EXPECT_EQ(file.type, "prs3");
  EXPECT_TRUE(file.unknown_keys.empty());
  EXPECT_NE(dynamic_cast<const Model*>(file.model.get()), nullptr);
  ASSERT_EQ(file.workspaces.count("reference"), 1u);
  // The file with an uncertainty block: the group's values become the geometry parameters.
  {
    std::ifstream in(test::configPath("prs3.yaml"));
    std::stringstream text;
    text << in.rdbuf() << "uncertainty:\n  platform_radius: 2.0e-4\n";
    const io::ModelFile uncertain = io::parseModelDocument(text.str(), "prs3.yaml + uncertainty");
    EXPECT_EQ(uncertain.model->geometryParameterCount(), 1);
    EXPECT_EQ(uncertain.model->geometryParameterName(0).rfind("platform_radius", 0), 0u);
    const Interval range = uncertain.model->geometryParameterRange(0);
    EXPECT_NEAR(range.upper() - range.lower(), 4.0e-4, 1e-12);
  }
  const model::RobotDescription d = Prs3Kinematics::description();
  ASSERT_EQ(file.description.geometry.size(), static_cast<std::size_t>(Prs3Kinematics::kGeometryValues));
  for (std::size_t v = 0; v < d.geometry.size(); ++v)
    EXPECT_EQ(file.description.geometry[v].nominal, d.geometry[v].nominal) << d.geometry[v].name;
  EXPECT_EQ(file.description.sensor_error, std::vector<double>(3, 1e-5));
  EXPECT_EQ(d.geometry[Prs3Kinematics::baseRadius(2)].name, "base_radius[2]");
  EXPECT_EQ(d.geometry[Prs3Kinematics::rodLength(1)].name, "rod_length[1]");
  EXPECT_EQ(d.geometry[Prs3Kinematics::kPlatformRadius].name, "platform_radius");
  const model::ModelType* type = model::ModelRegistry::global().find("prs3");
  ASSERT_NE(type, nullptr);
  const auto robot = type->make(file.description);
  EXPECT_EQ(robot->dof(), 3);
  EXPECT_EQ(robot->name(), "prs3");
  EXPECT_EQ(robot->componentName(0), "dz [m]");
  EXPECT_EQ(robot->componentName(1), "dtilt_x [rad]");
  EXPECT_EQ(robot->componentName(2), "dtilt_y [rad]");
  EXPECT_EQ(robot->jointName(2), "slider_2 [m]");
  EXPECT_FALSE(robot->isAngular(0));
  EXPECT_TRUE(robot->isAngular(1));
}

TEST(Prs3Kinematics, ParasiticMotionKeepsEveryLegInItsPlaneAndTheLoopsClose) {
  const model::RobotDescription d = perturbed(prs3File().description);
  const Reference ref(d);
  const Model robot(Prs3Kinematics(), d);
  std::mt19937_64 rng(1);
  IVec box = referenceBox();
  box[1] = Interval(-0.4, 0.4);
  box[2] = Interval(-0.4, 0.4);
  std::vector<double> nominal;
  for (const model::GeometryValue& v : d.geometry) nominal.push_back(v.nominal);
  double largestParasitic = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const DVec pose = trial == 0 ? pose3(0.32, 0.0, 0.0) : test::randomPoint(box, rng);
    // Zero torsion is consistent: the three leg-plane constraints hold with two unknowns.
    double residual = 0.0;
    const Eigen::Vector3d p = ref.centre(pose, &residual);
    EXPECT_LT(residual, 1e-15);
    const model::kin::Vec3<double> c = Prs3Kinematics::platformCentre(pose.data(), nominal.data());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], p[k], 1e-15) << k;
    largestParasitic = std::max(largestParasitic, p.head<2>().norm());
    const DVec q = robot.legLengths(pose);
    const Eigen::Vector3d qr = ref.sliders(pose);
    const IVec qi = robot.jointCoordinates(test::thinBox(pose));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(q[i], qr[i], 1e-14) << i;
      EXPECT_TRUE(test::encloses(qi[i], q[i], 0.0)) << i;
      const Eigen::Vector3d b = ref.anchor(pose, i);
      EXPECT_NEAR(b.dot(Reference::t(i)), 0.0, 1e-15) << i;
      const Eigen::Vector3d slider = ref.base[i] * Reference::u(i) + q[i] * Eigen::Vector3d::UnitZ();
      EXPECT_NEAR((b - slider).norm(), ref.rod[i], 1e-14) << i;
      EXPECT_GT(b.z(), slider.z()) << i;  // the slider below the platform joint
    }
  }
  EXPECT_GT(largestParasitic, 1e-3);  // the test sees the parasitic motion, not only zeros
  // At small tilts, tilt_x and tilt_y are the rotation vector's x and y (to second order), its z is 0.
  for (const DVec& pose : {pose3(0.3, 1e-3, 0.0), pose3(0.3, 0.0, -1e-3), pose3(0.3, 7e-4, 6e-4)}) {
    const Eigen::AngleAxisd aa(Reference::rotation(pose[1], pose[2]));
    const Eigen::Vector3d v = aa.angle() * aa.axis();
    EXPECT_NEAR(v.x(), pose[1], 1e-6);
    EXPECT_NEAR(v.y(), pose[2], 1e-6);
    EXPECT_NEAR(v.z(), 0.0, 1e-15);
  }
}

TEST(Prs3Kinematics, InverseJacobianIsTheDerivativeOfTheSliderPositions) {
  const model::RobotDescription d = perturbed(prs3File().description);
  const Reference ref(d);
  const Model robot(Prs3Kinematics(), d);
  std::mt19937_64 rng(2);
  IVec box = referenceBox();
  box[1] = box[1] * Interval(3.0);
  box[2] = box[2] * Interval(3.0);
  for (int trial = 0; trial < 500; ++trial) {
    const DVec pose = trial == 0 ? pose3(0.32, 0.0, 0.0) : test::randomPoint(box, rng);
    const DMat m = robot.inverseJacobian(pose);
    ASSERT_TRUE(m.allFinite());
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a) {
      DVec qp = pose, qm = pose;
      qp[a] += h;
      qm[a] -= h;
      const Eigen::Vector3d fd = (ref.sliders(qp) - ref.sliders(qm)) / (2 * h);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(m(i, a), fd[i], 1e-8) << "leg " << i << " coordinate " << a;
    }
    for (int i = 0; i < 3; ++i) EXPECT_EQ(m(i, 0), 1.0);  // the platform's height moves every slider alike
    EXPECT_LT((m * robot.jacobian(pose) - DMat::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(Prs3Kinematics, IntervalEnclosuresContainSampledInverseJacobiansIncludingNearTheReachLimit) {
  const Model robot(Prs3Kinematics(), perturbed(prs3File().description));
  std::mt19937_64 rng(3);
  const IVec ws = referenceBox();
  const double scales[4] = {0.0, 0.01, 0.1, 0.5};
  int bounded = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const IVec box = test::randomSubBox(ws, scales[trial % 4], rng);
    if (test::checkInverseJacobianEnclosures(robot, box, 20, rng)) ++bounded;
  }
  EXPECT_EQ(bounded, 200);
  // Short rods: tilting about x, rod 0 ends up horizontal (|rho| = l, J^-1 unbounded).
  model::RobotDescription d = prs3File().description;
  d.geometry[Prs3Kinematics::rodLength(0)].nominal = 0.12;
  const Model shortRods(Prs3Kinematics(), d);
  const DVec from = pose3(0.32, 0.0, 0.0);
  const DVec dir = pose3(0.0, 1.0, 0.0);
  const double limit = test::reachLimit(shortRods, from, dir, 1.5);
  EXPECT_GT(limit, 0.2);
  for (const double gap : {1e-2, 1e-3, 1e-4}) {
    IVec box = test::thinBox(from);
    box[1] = Interval(limit - gap - 1e-5, limit - gap);
    box[2] = Interval(-1e-4, 1e-4);
    box[0] = Interval(0.31, 0.33);
    EXPECT_TRUE(test::checkInverseJacobianEnclosures(shortRods, box, 20, rng)) << gap;
    box[1] = Interval(limit - gap, limit + gap);
    const IMat m = shortRods.inverseJacobian(box);
    bool unbounded = false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        unbounded = unbounded || !m(i, j).isBounded();
        EXPECT_FALSE(m(i, j).isEmpty());
      }
    EXPECT_TRUE(unbounded) << gap;
    test::checkInverseJacobianEnclosures(shortRods, box, 20, rng);
  }
}

TEST(Prs3Kinematics, HessianEnclosuresContainCentralDifferencesAndBoundPreconditionedHessians) {
  const Model robot(Prs3Kinematics(), perturbed(prs3File().description));
  std::mt19937_64 rng(4);
  const IVec ws = referenceBox();
  for (int trial = 0; trial < 60; ++trial) {
    const IVec box = test::randomSubBox(ws, trial % 3 == 0 ? 0.0 : 0.1 * (trial % 3), rng);
    EXPECT_TRUE(test::checkHessianEnclosures(robot, box, 5, rng));
    test::checkPreconditionedHessian(robot, box, 5, rng);
  }
}

TEST(Prs3Kinematics, GeometryDerivativesContainFiniteDifferences) {
  model::RobotDescription d = perturbed(prs3File().description);
  d.geometry[Prs3Kinematics::baseRadius(0)].lo = -1e-3;
  d.geometry[Prs3Kinematics::baseRadius(0)].hi = 5e-4;
  d.geometry[Prs3Kinematics::rodLength(1)].lo = -5e-4;
  d.geometry[Prs3Kinematics::rodLength(1)].hi = 5e-4;
  d.geometry[Prs3Kinematics::kPlatformRadius].lo = -1e-3;
  d.geometry[Prs3Kinematics::kPlatformRadius].hi = 1e-3;
  const Model robot(Prs3Kinematics(), d);
  ASSERT_EQ(robot.geometryParameterCount(), 3);
  std::mt19937_64 rng(5);
  const IVec ws = referenceBox();
  for (int trial = 0; trial < 30; ++trial) {
    const IVec box = test::randomSubBox(ws, trial % 2 ? 0.05 : 0.0, rng);
    test::checkGeometryDerivatives(robot, box, 10, rng);
    GeometryDerivatives out;
    ASSERT_TRUE(robot.geometryDerivatives(box, out));
    int rows[3] = {0, 0, 0};
    for (int e = 0; e < out.count; ++e) {
      const GeometryRowDerivative& r = out.entries[static_cast<std::size_t>(e)];
      rows[r.parameter] |= 1 << r.row;
    }
    EXPECT_EQ(rows[0], 1 << 0);  // base_radius[0]: leg 0 only
    EXPECT_EQ(rows[1], 1 << 1);  // rod_length[1]: leg 1 only
    EXPECT_EQ(rows[2], 7);       // platform_radius: every leg
  }
}

TEST(Prs3Kinematics, VerifierBracketsTheSampledMaximaOfTheReferenceWorkspace) {
  const Model robot(Prs3Kinematics(), prs3File().description);
  test::checkVerifier(robot, referenceBox(), 40000);
}
