// io::TrajectoryFile, the YAML reader of trajectories and motion varieties: waypoints, polynomial segments, varieties
// and regions are read as written; every error names the file, the key and the row; a `frame` key gives the poses in
// the base frame (against an independent mapping, and through the verifier against dense sampling).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../core/TrajectorySampling.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/ParametricVariety.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;
using domain::WaypointTrajectory;
using test::ref6;
using test::rotation;
using test::worstError;

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
      {"interpolation: cubic\nwaypoints:\n" + two, {"traj.yaml: interpolation", "slerp or linear_rpy", "cubic"}},
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
