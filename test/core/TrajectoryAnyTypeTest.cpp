// Trajectories and motion varieties of robots whose pose is not the rigid-body pose: delta3 (x, y, z), planar3rpr
// (x, y, theta), prs3 (z, tilt_x, tilt_y), each built as the default pipeline composes it (io::loadModelFile, the
// trajectory file read with the type's pose coordinates, verify::Verifier with default options):
//   * the max-error bracket contains the maximum of a plain double sampler along the motion: dense sampling of the
//     parameter, the pose from the motion's definition evaluated here (linear interpolation of the rows, Horner,
//     monomial sums), the worst error sum_j |J_kj| e_j with J the inverse of the model's J^-1 in double;
//   * thresholds at 1.05 x the sampled maxima are SAFE, at 0.95 x UNSAFE with a witness whose sampled error exceeds
//     the threshold;
//   * refusals name what is wrong: slerp / linear_rpy for a type without orientation coordinates, a wrong number of
//     columns or polynomials, a region or frame the pose coordinates do not allow, a domain of other pose coordinates
//     than the model's.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;
using domain::PoseCoordinates;
using domain::WaypointTrajectory;
using verify::Verdict;

namespace {

const io::ModelFile& robot(const std::string& type) {
  static const io::ModelFile delta3 = io::loadModelFile(test::configPath("delta3.yaml"));
  static const io::ModelFile planar = io::loadModelFile(test::configPath("planar3rpr.yaml"));
  static const io::ModelFile prs3 = io::loadModelFile(test::configPath("prs3.yaml"));
  return type == "delta3" ? delta3 : type == "planar3rpr" ? planar : prs3;
}

PoseCoordinates coordinatesOf(const std::string& type) { return PoseCoordinates::of(robot(type).description); }

/// The plain worst error sum_j |J_kj| e_j at a pose, J = (J^-1)^-1 in double (+inf where J^-1 is singular).
DVec plainWorstError(const model::RobotModel& m, const DVec& pose) {
  const DMat jinv = m.inverseJacobian(pose);
  Eigen::FullPivLU<DMat> lu(jinv);
  if (!lu.isInvertible()) return DVec::Constant(m.dof(), std::numeric_limits<double>::infinity());
  const DMat j = lu.inverse();
  DVec f = DVec::Zero(m.dof());
  for (int k = 0; k < m.dof(); ++k)
    for (int i = 0; i < m.dof(); ++i) f[k] += std::abs(j(k, i)) * m.sensorError()[static_cast<std::size_t>(i)];
  return f;
}

/// A motion as its definition gives it: the pose at a point of the parameters, evaluated here in double.
using PlainPose = std::function<DVec(const DVec& u)>;

/// Linear interpolation of rows [t, q_1 .. q_n] at the parameter u of t = t_0 + u (t_N - t_0).
PlainPose linearRows(const std::vector<std::vector<double>>& rows) {
  return [rows](const DVec& u) {
    const double t = rows.front()[0] + u[0] * (rows.back()[0] - rows.front()[0]);
    std::size_t k = 0;
    while (k + 2 < rows.size() && t > rows[k + 1][0]) ++k;
    const double s = std::min(1.0, std::max(0.0, (t - rows[k][0]) / (rows[k + 1][0] - rows[k][0])));
    DVec q(static_cast<int>(rows[k].size()) - 1);
    for (int i = 0; i < q.size(); ++i) q[i] = rows[k][i + 1] + s * (rows[k + 1][i + 1] - rows[k][i + 1]);
    return q;
  };
}

/// Polynomial segments {start, end, coefficients per coordinate} at the parameter u.
struct PlainSegment {
  double start = 0.0, end = 0.0;
  std::vector<std::vector<double>> coefficients;
};
PlainPose polynomialSegments(const std::vector<PlainSegment>& segs) {
  return [segs](const DVec& u) {
    const double t = segs.front().start + u[0] * (segs.back().end - segs.front().start);
    std::size_t k = 0;
    while (k + 1 < segs.size() && t > segs[k].end) ++k;
    const double tau = t - segs[k].start;
    DVec q(static_cast<int>(segs[k].coefficients.size()));
    for (int i = 0; i < q.size(); ++i) {
      const auto& c = segs[k].coefficients[static_cast<std::size_t>(i)];
      double v = 0.0;
      for (std::size_t j = c.size(); j-- > 0;) v = v * tau + c[j];
      q[i] = v;
    }
    return q;
  };
}

/// Per coordinate, monomials [coefficient, exponent of u, exponent of v].
PlainPose monomialSums(const std::vector<std::vector<std::array<double, 3>>>& coords) {
  return [coords](const DVec& u) {
    DVec q = DVec::Zero(static_cast<int>(coords.size()));
    for (int i = 0; i < q.size(); ++i)
      for (const auto& m : coords[static_cast<std::size_t>(i)])
        q[i] += m[0] * std::pow(u[0], m[1]) * std::pow(u[1], m[2]);
    return q;
  };
}

struct Sampled {
  DVec max;
};

/// The largest plain worst errors over a dense grid of the parameters (m = 1: `n` points; m = 2: n x n).
Sampled sampleMotion(const model::RobotModel& m, const PlainPose& pose, int parameters, int n) {
  Sampled s;
  s.max = DVec::Zero(m.dof());
  const int total = parameters == 1 ? n : n * n;
  for (int idx = 0; idx < total; ++idx) {
    DVec u(parameters);
    u[0] = static_cast<double>(idx % n) / (n - 1);
    if (parameters == 2) u[1] = static_cast<double>(idx / n) / (n - 1);
    s.max = s.max.cwiseMax(plainWorstError(m, pose(u)));
  }
  return s;
}

/// The bracket, SAFE at 1.05 x and UNSAFE at 0.95 x the sampled maxima, on the motion of a trajectory file.
void checkAgainstSampling(const std::string& type, const io::TrajectoryFile& file, const PlainPose& pose,
                          const std::string& what) {
  SCOPED_TRACE(type + ": " + what);
  const model::RobotModel& m = *robot(type).model;
  const domain::Domain& d = *file.domain;
  ASSERT_EQ(d.poseDimension(), m.dof());
  const int parameters = d.variables();
  const Sampled s = sampleMotion(m, pose, parameters, parameters == 1 ? 20001 : 201);
  ASSERT_TRUE(s.max.allFinite());

  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = 0.005;
  o.time_limit_s = 30.0;
  const verify::VerifierResult r = verify::Verifier::run(m, d, o);
  ASSERT_TRUE(r.converged) << r.message;
  ASSERT_EQ(r.max_upper.size(), m.dof());
  for (int k = 0; k < m.dof(); ++k) {
    EXPECT_GE(r.max_upper[k], s.max[k]) << m.componentName(k);
    EXPECT_LE(r.max_lower[k], s.max[k] * (1.0 + 1e-6)) << m.componentName(k);  // attained, up to the sampling
  }

  verify::VerifierOptions safe;
  safe.thresholds = s.max * 1.05;
  safe.time_limit_s = 30.0;
  const verify::VerifierResult above = verify::Verifier::run(m, d, safe);
  EXPECT_EQ(above.verdict, Verdict::Safe) << above.message;
  EXPECT_EQ(above.undecided_box_count, 0u);

  // Also without the pre-sampling grid: the branch-and-bound has to find the witness itself.
  std::size_t belowBoxes = 0;
  for (int presample : {3, 0}) {
    SCOPED_TRACE("presample_points " + std::to_string(presample));
    verify::VerifierOptions unsafe = safe;
    unsafe.thresholds = s.max * 0.95;
    unsafe.presample_points = presample;
    const verify::VerifierResult below = verify::Verifier::run(m, d, unsafe);
    ASSERT_EQ(below.verdict, Verdict::Unsafe) << below.message;
    const int k = below.witness_component;
    ASSERT_GE(k, 0);
    ASSERT_EQ(below.witness.size(), parameters);
    const DVec at = pose(below.witness);
    ASSERT_EQ(below.witness_pose.size(), m.dof());
    for (int i = 0; i < m.dof(); ++i) EXPECT_NEAR(below.witness_pose[i].mid(), at[i], 1e-9) << i;
    EXPECT_GT(plainWorstError(m, at)[k], unsafe.thresholds[k]);
    belowBoxes = below.stats.boxes;
  }
  std::printf(
      "[ figures  ] %s %s: max-error %zu boxes, SAFE at +5%% in %zu boxes, UNSAFE at -5%% in %zu boxes "
      "(without pre-sampling)\n",
      type.c_str(), what.c_str(), r.stats.boxes, above.stats.boxes, belowBoxes);
}

std::string parseError(const std::string& yaml, const std::string& type) {
  try {
    io::parseTrajectory(yaml, "traj.yaml", coordinatesOf(type));
  } catch (const ParseError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

// ---- sampled truth ------------------------------------------------------------------------------------------------
TEST(TrajectoryAnyType, Delta3WaypointsOfTheExampleFile) {
  const std::string path = test::configPath("delta3_trajectory.yaml");
  const io::TrajectoryFile file = io::loadTrajectoryFile(path, coordinatesOf("delta3"));
  EXPECT_EQ(file.description, "waypoints (linear), 4 waypoints");
  // The rows read by yaml-cpp directly (the plain definition of the motion).
  std::vector<std::vector<double>> rows;
  for (const auto& row : YAML::LoadFile(path)["waypoints"]) rows.push_back(row.as<std::vector<double>>());
  ASSERT_EQ(rows.size(), 4u);
  checkAgainstSampling("delta3", file, linearRows(rows), "example waypoints");
}

TEST(TrajectoryAnyType, Delta3PolynomialSegmentsAndVariety) {
  // Two cubic segments, continuous at t = 1.5 s (up to the rounding of the first segment's end values).
  const std::vector<PlainSegment> segs = {
      {0.0, 1.5, {{-0.08, 0.06, 0.02, -0.01}, {0.05, -0.04, 0.0, 0.005}, {-0.42, 0.0, 0.03, -0.012}}},
      {1.5, 3.0, {{0.02125, 0.01, -0.03}, {0.006875, 0.03}, {-0.393, -0.02, 0.0, 0.004}}}};
  const io::TrajectoryFile poly = io::parseTrajectory(
      "polynomial_segments:\n"
      "  - {t: [0.0, 1.5], x: [-0.08, 0.06, 0.02, -0.01], y: [0.05, -0.04, 0.0, 0.005], z: [-0.42, 0.0, 0.03, "
      "-0.012]}\n"
      "  - {t: [1.5, 3.0], x: [0.02125, 0.01, -0.03], y: [0.006875, 0.03], z: [-0.393, -0.02, 0.0, 0.004]}\n",
      "poly.yaml", coordinatesOf("delta3"));
  EXPECT_EQ(poly.description, "polynomial, 2 segments, degree <= 3");
  checkAgainstSampling("delta3", poly, polynomialSegments(segs), "cubic segments");

  const io::TrajectoryFile variety = io::parseTrajectory(
      "variety:\n"
      "  parameters: 2\n"
      "  x: [[-0.08, 0, 0], [0.16, 1, 0]]\n"
      "  y: [[-0.08, 0, 0], [0.16, 0, 1], [0.02, 1, 1]]\n"
      "  z: [[-0.43, 0, 0], [0.06, 1, 1]]\n",
      "variety.yaml", coordinatesOf("delta3"));
  checkAgainstSampling(
      "delta3", variety,
      monomialSums(
          {{{-0.08, 0, 0}, {0.16, 1, 0}}, {{-0.08, 0, 0}, {0.16, 0, 1}, {0.02, 1, 1}}, {{-0.43, 0, 0}, {0.06, 1, 1}}}),
      "surface (m = 2)");
}

TEST(TrajectoryAnyType, Planar3rprWaypointsAndPolynomialSegments) {
  const std::vector<std::vector<double>> rows = {
      {0.0, -0.08, 0.06, 0.25}, {0.7, 0.0, -0.02, -0.1}, {2.0, 0.09, 0.08, 0.2}, {2.6, 0.05, -0.09, -0.28}};
  const io::TrajectoryFile w = io::parseTrajectory(
      "waypoints:\n"
      "  - [0.0, -0.08, 0.06, 0.25]\n"
      "  - [0.7, 0.0, -0.02, -0.1]\n"
      "  - [2.0, 0.09, 0.08, 0.2]\n"
      "  - [2.6, 0.05, -0.09, -0.28]\n",
      "w.yaml", coordinatesOf("planar3rpr"));
  EXPECT_EQ(w.description, "waypoints (linear), 4 waypoints");  // linear: the default without orientation angles
  checkAgainstSampling("planar3rpr", w, linearRows(rows), "waypoints");

  const std::vector<PlainSegment> segs = {
      {1.0, 3.0, {{-0.09, 0.08, 0.0, -0.01}, {0.07, -0.1, 0.03}, {-0.2, 0.3, -0.08}}}};
  const io::TrajectoryFile p = io::parseTrajectory(
      "polynomial_segments:\n"
      "  - {t: [1.0, 3.0], x: [-0.09, 0.08, 0.0, -0.01], y: [0.07, -0.1, 0.03], theta: [-0.2, 0.3, -0.08]}\n",
      "p.yaml", coordinatesOf("planar3rpr"));
  checkAgainstSampling("planar3rpr", p, polynomialSegments(segs), "one cubic segment");
}

TEST(TrajectoryAnyType, Prs3WaypointsWithTilts) {
  const std::vector<std::vector<double>> rows = {
      {0.0, 0.31, -0.08, 0.05}, {1.0, 0.33, 0.06, -0.07}, {1.8, 0.30, 0.0, 0.09}};
  const io::TrajectoryFile w = io::parseTrajectory(
      "interpolation: linear\n"
      "waypoints:\n"
      "  - [0.0, 0.31, -0.08, 0.05]\n"
      "  - [1.0, 0.33, 0.06, -0.07]\n"
      "  - [1.8, 0.30, 0.0, 0.09]\n",
      "w.yaml", coordinatesOf("prs3"));
  checkAgainstSampling("prs3", w, linearRows(rows), "waypoints");
}

// ---- the domains know their pose coordinates ----------------------------------------------------------------------
TEST(TrajectoryAnyType, PoseViewsHaveTheModelsCoordinates) {
  const PoseCoordinates delta3 = coordinatesOf("delta3");
  EXPECT_EQ(delta3.size(), 3);
  EXPECT_FALSE(delta3.rigidBody());
  EXPECT_TRUE(PoseCoordinates().rigidBody());
  std::vector<WaypointTrajectory::Waypoint> w(3);
  w[0] = {0.0, {-0.05, 0.02, -0.4}};
  w[1] = {1.0, {0.03, -0.04, -0.37}};
  w[2] = {2.5, {0.08, 0.06, -0.44}};
  const WaypointTrajectory traj(w, WaypointTrajectory::Interpolation::Linear, delta3);
  EXPECT_EQ(traj.poseDimension(), 3);
  const PlainPose plain = linearRows({{0.0, -0.05, 0.02, -0.4}, {1.0, 0.03, -0.04, -0.37}, {2.5, 0.08, 0.06, -0.44}});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int b = 0; b < 200; ++b) {
    const double lo = 0.9 * uni(rng), width = 0.1 * uni(rng);
    IVec box(1);
    box[0] = Interval(lo, lo + width);
    enclosure::BoxInput in;
    traj.poseView(box, true, in);
    ASSERT_EQ(in.pose.size(), 3);
    ASSERT_EQ(in.centrePose.size(), 3);
    for (int i = 3; i < kMaxDof; ++i) ASSERT_EQ(in.dualPose[i].value(), Interval(0.0));
    const DVec u = DVec::Constant(1, lo + width * uni(rng));
    const DVec q = plain(u);
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(in.pose[i].contains(q[i])) << in.pose[i] << " vs " << q[i];
      ASSERT_TRUE((in.centrePose[i] + in.dualPose[i].d(0) * in.deviation[0]).contains(q[i]));
    }
    EXPECT_EQ(traj.pointAt(u[0]).pose.size(), 3);
    EXPECT_EQ(traj.poseAt(u).size(), 3);
  }
  // A position region applies to types with x, y, z.
  io::TrajectoryFile inside = io::parseTrajectory(
      "waypoints: [[0, -0.05, 0.02, -0.4], [1, 0.03, -0.04, -0.37]]\n"
      "region: {type: box, x: [-0.1, 0.1], y: [-0.1, 0.1], z: [-0.45, -0.35]}\n",
      "r.yaml", delta3);
  EXPECT_EQ(inside.domain->classify(inside.domain->initialBox()), domain::Containment::Inside);
  io::TrajectoryFile outside = io::parseTrajectory(
      "waypoints: [[0, -0.05, 0.02, -0.4], [1, 0.03, -0.04, -0.37]]\n"
      "region: {type: box, x: [-0.1, 0.1], y: [-0.1, 0.1], z: [-0.3, -0.2]}\n",
      "r.yaml", delta3);
  EXPECT_EQ(outside.domain->classify(outside.domain->initialBox()), domain::Containment::Outside);
}

TEST(TrajectoryAnyType, LinearIsLinearRpyForTheRigidBodyPose) {
  const std::string rows = "waypoints:\n  - [0, -0.1, 0, 0.47, 0, 0, 0]\n  - [1.5, 0.1, 0, 0.47, 0.1, 0, 0.2]\n";
  const io::TrajectoryFile linear = io::parseTrajectory("interpolation: linear\n" + rows, "a.yaml");
  const io::TrajectoryFile rpy = io::parseTrajectory("interpolation: linear_rpy\n" + rows, "b.yaml");
  EXPECT_EQ(linear.description, "waypoints (linear_rpy), 2 waypoints");
  EXPECT_EQ(rpy.description, linear.description);
  for (double t : {0.0, 0.4, 1.1, 1.5}) {
    EXPECT_EQ(linear.trajectory->pointAtTime(t).pose, rpy.trajectory->pointAtTime(t).pose) << t;
  }
}

// ---- refusals -----------------------------------------------------------------------------------------------------
TEST(TrajectoryAnyType, FileErrorsNameTheKeyAndTheExpectedCoordinates) {
  const std::string two = "waypoints:\n  - [0, 0, 0, -0.4]\n  - [1, 0.01, 0, -0.4]\n";
  const std::vector<std::tuple<std::string, std::string, std::vector<std::string>>> cases = {
      {"delta3",
       "interpolation: slerp\n" + two,
       {"traj.yaml: interpolation: slerp", "rigid-body pose", "delta3 has the pose coordinates (x, y, z)", "linear"}},
      {"delta3",
       "interpolation: linear_rpy\n" + two,
       {"traj.yaml: interpolation: linear_rpy", "delta3 has the pose coordinates (x, y, z)"}},
      {"delta3", "interpolation: cubic\n" + two, {"traj.yaml: interpolation", "expected linear", "cubic"}},
      {"delta3",
       "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0, 0.47, 0, 0, 0]\n",
       {"traj.yaml: waypoints[0]", "expected 4 numbers [t, x, y, z]", "3 pose coordinates of delta3", "got 7"}},
      {"planar3rpr",
       "waypoints:\n  - [0, 0, 0]\n  - [1, 0, 0]\n",
       {"traj.yaml: waypoints[0]", "expected 4 numbers [t, x, y, theta]", "planar3rpr", "got 3"}},
      {"prs3", "waypoints: 3\n", {"traj.yaml: waypoints", "list of rows [t, z, tilt_x, tilt_y]"}},
      {"delta3",
       "polynomial_segments:\n  - {t: [0, 1], x: [0], y: [0], z: [-0.4], roll: [0]}\n",
       {"traj.yaml: polynomial_segments[0].roll", "unknown key", "3 for delta3 (x, y, z)"}},
      {"delta3",
       "polynomial_segments:\n  - {t: [0, 1], x: [0], y: [0]}\n",
       {"traj.yaml: polynomial_segments[0].z", "missing", "3 for delta3 (x, y, z)"}},
      {"planar3rpr",
       "variety:\n  parameters: 1\n  x: [[0.1, 1]]\n  yaw: [[0.1, 1]]\n",
       {"traj.yaml: variety.yaw", "unknown key", "3 for planar3rpr (x, y, theta)"}},
      {"planar3rpr",
       "waypoints:\n  - [0, 0, 0, 0]\n  - [1, 0.01, 0, 0]\nregion: {type: sphere, centre: [0, 0, 0], "
       "radius: 1}\n",
       {"traj.yaml: region", "x, y, z", "planar3rpr has the pose coordinates (x, y, theta)"}},
      {"delta3",
       two + "frame: {translation: [0, 0, 0.1]}\n",
       {"traj.yaml: frame", "rigid-body pose", "delta3 has the pose coordinates (x, y, z)"}},
  };
  for (const auto& [type, yaml, expected] : cases) {
    SCOPED_TRACE(type + ": " + yaml);
    const std::string e = parseError(yaml, type);
    for (const auto& m : expected) EXPECT_NE(e.find(m), std::string::npos) << "'" << m << "' in: " << e;
  }
}

TEST(TrajectoryAnyType, CoreRefusesWhatThePoseCoordinatesDoNotAllow) {
  const PoseCoordinates delta3 = coordinatesOf("delta3");
  auto message = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const InvalidArgument& e) {
      return e.what();
    }
    return "no error";
  };
  std::vector<WaypointTrajectory::Waypoint> w(2);
  w[0] = {0.0, {0.0, 0.0, -0.4}};
  w[1] = {1.0, {0.01, 0.0, -0.4}};
  std::string e = message([&] { const WaypointTrajectory t(w, WaypointTrajectory::Interpolation::Slerp, delta3); });
  EXPECT_NE(e.find("interpolation: slerp"), std::string::npos) << e;
  EXPECT_NE(e.find("delta3 has the pose coordinates (x, y, z)"), std::string::npos) << e;
  w[1].pose[3] = 0.1;  // a rigid-body waypoint given to a delta3 trajectory
  e = message([&] { const WaypointTrajectory t(w, WaypointTrajectory::Interpolation::Linear, delta3); });
  EXPECT_NE(e.find("waypoints[1]: pose entry 3 is beyond the 3 pose coordinates (x, y, z) of delta3"),
            std::string::npos)
      << e;

  domain::PolynomialTrajectory::Segment seg;
  seg.start = 0.0;
  seg.end = 1.0;
  for (int i = 0; i < 6; ++i) seg.coefficients[i] = {0.0};
  e = message([&] { const domain::PolynomialTrajectory t({seg}, delta3); });
  EXPECT_NE(e.find("polynomial_segments[0]: expected 3 coordinate polynomials (x, y, z) for delta3"), std::string::npos)
      << e;

  std::array<std::vector<domain::ParametricVariety::Monomial>, kMaxDof> coords;
  coords[4].push_back({0.1, {1, 0, 0, 0, 0, 0}});
  e = message([&] { const domain::ParametricVariety v(1, coords, delta3); });
  EXPECT_NE(e.find("variety: expected monomials for 3 pose coordinates (x, y, z) of delta3"), std::string::npos) << e;

  // A trajectory of rigid-body poses is not verified for delta3, and a delta3 trajectory is not placed in a frame.
  w[1].pose[3] = 0.0;
  const auto rigid = std::make_shared<WaypointTrajectory>(w, WaypointTrajectory::Interpolation::Linear);
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  e = message([&] { verify::Verifier::run(*robot("delta3").model, *rigid, o); });
  EXPECT_NE(e.find("domain: expected poses of 3 coordinates (the dof of delta3), got 6"), std::string::npos) << e;
  const auto mine = std::make_shared<WaypointTrajectory>(w, WaypointTrajectory::Interpolation::Linear, delta3);
  e = message([&] { const domain::TransformedDomain framed(mine, domain::RigidTransform()); });
  EXPECT_NE(e.find("rigid-body poses"), std::string::npos) << e;
}
