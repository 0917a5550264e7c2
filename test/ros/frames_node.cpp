// rostest (frames.test): /verify_workspace requests whose workspace is given in a frame other than the base frame.
// The node looks the frame up in tf2 (static transforms published by the .test file) and the core composes the
// transform exactly (domain::TransformedWorkspace): every verdict equals that of the equivalent base-frame request,
// witnesses lie in the requested frame's workspace and violate the threshold once mapped to the base frame (double
// oracle), max_error brackets overlap those of the base-frame request, ~verdict and ~boxes use the right frames, a
// tilted frame (general rotation) agrees with its equivalent base-frame request; an unknown frame is refused naming
// frame_id. /verify_trajectory likewise: waypoints given in a frame give the verdicts and overlapping brackets of the
// base-frame trajectory through the mapped waypoints (slerp in the tilted frame, linear_rpy in the turned one, where
// both interpolations are frame-independent), with the witness pose in the request's frame.
#include <array>
#include <cmath>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>
#include <Eigen/Geometry>

#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyTrajectory.h"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::VerificationResult;
using pkm_accuracy::VerifyTrajectory;

// The frames of frames.test: the pose of each in base_link.
const Eigen::Vector3d kWork(0.03, -0.02, 0.1);     // work: translated
const Eigen::Vector3d kTurned(0.01, -0.005, 0.1);  // turned (via table): translated and turned by kYaw about z
constexpr double kYaw = 0.7;
const Eigen::Vector3d kTilted(0.02, -0.01, 0.1);  // tilted: translated, roll -0.05, pitch 0.1, yaw 0.3
const Eigen::Vector3d kTiltedRpy(-0.05, 0.1, 0.3);

/// R = Rz(yaw) Ry(pitch) Rx(roll) and the principal roll, pitch, yaw of a rotation (double: the oracle).
Eigen::Matrix3d rotationOf(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d rpyOf(const Eigen::Matrix3d& n) {
  return {std::atan2(n(2, 1), n(2, 2)), std::atan2(-n(2, 0), std::hypot(n(0, 0), n(1, 0))),
          std::atan2(n(1, 0), n(0, 0))};
}

/// The base-frame pose of a pose given in a frame placed at `t` and turned by `yaw` about z (double: the oracle).
std::array<double, 6> toBase(const std::array<double, 6>& p, const Eigen::Vector3d& t, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {t.x() + c * p[0] - s * p[1], t.y() + s * p[0] + c * p[1], t.z() + p[2], p[3], p[4], p[5] + yaw};
}

/// The base-frame box request `base` expressed in a frame translated by t (no rotation).
VerifyWorkspace::Request translated(const VerifyWorkspace::Request& base, const Eigen::Vector3d& t,
                                    const std::string& frame) {
  VerifyWorkspace::Request r = base;
  for (std::size_t k = 0; k < 3; ++k) {
    r.box_min[k] -= t[static_cast<int>(k)];
    r.box_max[k] -= t[static_cast<int>(k)];
  }
  r.frame_id = frame;
  return r;
}

/// A vertical cylinder of radius 5 mm around (cx, cy), z in [z0, z0 + 0.01], roll and pitch in +-0.01 rad, yaw in
/// yaw0 +- 0.01 rad.
VerifyWorkspace::Request cylinder(double cx, double cy, double z0, double yaw0, const std::array<double, 6>& th) {
  VerifyWorkspace::Request r = smallRequest(th);
  r.region_type = "cylinder";
  r.center.x = cx;
  r.center.y = cy;
  r.radius = 0.005;
  r.z_min = z0;
  r.z_max = z0 + 0.01;
  r.yaw_min = yaw0 - 0.01;
  r.yaw_max = yaw0 + 0.01;
  return r;
}

const visualization_msgs::Marker* find(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  for (const auto& m : a.markers)
    if (m.ns == ns) return &m;
  return nullptr;
}

/// Checks a verdict pair and, for UNSAFE, the framed witness against the oracle.
void expectSameVerdict(const VerifyWorkspace::Response& rb, const VerifyWorkspace::Response& rf,
                       const std::string& expected, const std::array<double, 6>& th, const Eigen::Vector3d& t,
                       double yaw) {
  ASSERT_TRUE(rb.success) << rb.message;
  ASSERT_TRUE(rf.success) << rf.message;
  EXPECT_EQ(rb.verdict, expected) << rb.message;
  EXPECT_EQ(rf.verdict, rb.verdict) << rf.message;
  if (rf.verdict != "UNSAFE") return;
  ASSERT_TRUE(rf.has_witness);
  ASSERT_GE(rf.witness_component, 0);
  const auto c = static_cast<std::size_t>(rf.witness_component);
  EXPECT_GT(rf.witness_error[c], th[c]);
  const auto f = worstErrorAt(toBase(to6(rf.witness_pose), t, yaw));
  EXPECT_GT(f[c], th[c]);
  EXPECT_GE(f[c], rf.witness_error[c] * (1.0 - 1e-9));
}

TEST(Frames, TranslatedFrameGivesTheVerdictsOfTheBaseFrame) {
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto base = smallRequest(th);
    const auto framed = translated(base, kWork, "work");
    const auto rb = verify(base);
    const auto rf = verify(framed);
    expectSameVerdict(rb, rf, expected, th, kWork, 0.0);
    if (rf.has_witness) {
      EXPECT_TRUE(poseInWorkspace(to6(rf.witness_pose), framed));  // in the frame's workspace
    }
  }
}

TEST(Frames, TranslatedFrameMaxErrorBracketsOverlapTheBaseFrames) {
  auto base = smallRequest(kNone, "max_error");
  base.alpha = 0.05;
  const auto framed = translated(base, kWork, "work");
  const auto rb = verify(base);
  const auto rf = verify(framed);
  ASSERT_TRUE(rb.success) << rb.message;
  ASSERT_TRUE(rf.success) << rf.message;
  EXPECT_TRUE(rf.converged) << rf.message;
  ASSERT_EQ(rf.lower_bound_poses.size(), 36u);
  for (std::size_t k = 0; k < 6; ++k) {
    // Both brackets enclose the same maxima.
    EXPECT_LE(rf.lower_bound[k], rb.upper_bound[k]) << k;
    EXPECT_LE(rb.lower_bound[k], rf.upper_bound[k]) << k;
    // The lower bound's pose is in the frame's workspace, and attains it once mapped to the base frame.
    std::array<double, 6> pose{};
    for (std::size_t i = 0; i < 6; ++i) pose[i] = rf.lower_bound_poses[6 * k + i];
    EXPECT_TRUE(poseInWorkspace(pose, framed)) << k;
    EXPECT_GE(worstErrorAt(toBase(pose, kWork, 0.0))[k], rf.lower_bound[k] * (1.0 - 1e-9)) << k;
  }
}

TEST(Frames, TurnedFrameThroughAChainGivesTheVerdictsOfTheBaseFrame) {
  Latest<VerificationResult> verdict("/pkm_accuracy/verdict");
  Latest<visualization_msgs::MarkerArray> boxes("/pkm_accuracy/boxes");
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    // A vertical cylinder stays one under a rotation about z: centred on the frame's origin, it is the base-frame
    // cylinder around kTurned's (x, y); yaw ranges differ by kYaw.
    const auto base = cylinder(kTurned.x(), kTurned.y(), 0.47, 0.0, th);
    auto framed = cylinder(0.0, 0.0, 0.47 - kTurned.z(), -kYaw, th);
    framed.frame_id = "turned";
    const auto rb = verify(base);
    const auto rf = verify(framed);
    expectSameVerdict(rb, rf, expected, th, kTurned, kYaw);

    // ~verdict: poses in the request's frame.
    const auto v = verdict.waitFor([&](const VerificationResult& m) { return m.job_id == rf.job_id; });
    ASSERT_TRUE(v) << "no ~verdict for job " << rf.job_id;
    EXPECT_EQ(v->header.frame_id, "turned");
    EXPECT_EQ(v->verdict, rf.verdict);

    // ~boxes: in the base frame, the cylinder around kTurned, turned by kYaw; the witness mapped likewise.
    const std::string label = "job " + std::to_string(rf.job_id) + ": " + rf.verdict;
    const auto a = boxes.waitFor([&](const visualization_msgs::MarkerArray& m) {
      const auto* l = find(m, "label");
      return l && l->text.find(label) == 0;
    });
    ASSERT_TRUE(a) << "no ~boxes for job " << rf.job_id;
    EXPECT_EQ(a->markers.front().action, visualization_msgs::Marker::DELETEALL);
    const auto* ws = find(*a, "workspace");
    ASSERT_TRUE(ws);
    EXPECT_EQ(ws->header.frame_id, "base_link");
    EXPECT_EQ(ws->type, visualization_msgs::Marker::CYLINDER);
    EXPECT_NEAR(ws->pose.position.x, kTurned.x(), 1e-12);
    EXPECT_NEAR(ws->pose.position.y, kTurned.y(), 1e-12);
    EXPECT_NEAR(ws->pose.position.z, 0.475, 1e-12);
    EXPECT_NEAR(ws->pose.orientation.z, std::sin(kYaw / 2), 1e-9);
    EXPECT_NEAR(ws->pose.orientation.w, std::cos(kYaw / 2), 1e-9);
    EXPECT_NEAR(ws->scale.x, 0.01, 1e-12);
    const auto* w = find(*a, "witness");
    EXPECT_EQ(w != nullptr, rf.has_witness);
    if (w) {
      const auto p = toBase(to6(rf.witness_pose), kTurned, kYaw);
      EXPECT_NEAR(w->pose.position.x, p[0], 1e-12);
      EXPECT_NEAR(w->pose.position.y, p[1], 1e-12);
      EXPECT_NEAR(w->pose.position.z, p[2], 1e-12);
      EXPECT_EQ(w->color.r, 1.0f);
      EXPECT_EQ(w->color.g, 0.0f);
    }
  }
}

TEST(Frames, BaseFrameByNameIsTheBaseFrame) {
  auto req = smallRequest(kGenerous);
  req.threads = 1;
  const auto a = verify(req);
  req.frame_id = "base_link";
  const auto b = verify(req);
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_TRUE(b.success) << b.message;
  EXPECT_EQ(b.verdict, "SAFE");
  EXPECT_EQ(b.boxes, a.boxes);  // the same search
  // tf2 drops a leading '/': "/base_link" is the base frame too, and "/work" the frame work.
  req.frame_id = "/base_link";
  const auto c = verify(req);
  ASSERT_TRUE(c.success) << c.message;
  EXPECT_EQ(c.boxes, a.boxes);
  req.frame_id = "/work";
  const auto d = verify(req);
  req.frame_id = "work";
  const auto e = verify(req);
  ASSERT_TRUE(d.success) << d.message;
  ASSERT_TRUE(e.success) << e.message;
  EXPECT_EQ(d.boxes, e.boxes);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(d.upper_bound[k], e.upper_bound[k]) << k;
}

// The lookup of a request's frame (up to ~tf_timeout = 1 s) happens before the request takes a job slot: with
// ~max_parallel_jobs = 1, another request runs while it waits.
TEST(Frames, WaitingForAFrameHoldsNoJobSlot) {
  VerifyWorkspace::Response waiting;
  std::thread t([&] {
    auto req = smallRequest(kGenerous);
    req.frame_id = "appears_never";
    waiting = verify(req);
  });
  ros::WallDuration(0.3).sleep();
  const ros::WallTime t0 = ros::WallTime::now();
  const auto other = verify(smallRequest(kGenerous));
  const double other_s = (ros::WallTime::now() - t0).toSec();
  t.join();
  EXPECT_TRUE(other.success) << other.message;
  EXPECT_FALSE(other.busy) << other.message;
  EXPECT_LT(other_s, 0.6) << "the request waited behind the frame lookup";
  EXPECT_FALSE(waiting.success);
  EXPECT_EQ(waiting.job_id, 0u) << "a request whose frame is unknown is refused before it becomes a job";
  EXPECT_NE(waiting.message.find("appears_never"), std::string::npos) << waiting.message;
}

TEST(Frames, TiltedFrameGivesTheVerdictsOfTheBaseFrame) {
  // A ball maps to a ball under any rigid transform and a fixed orientation to a fixed orientation: the base-frame
  // request below is the tilted frame's (up to the double rounding of its centre and angles, computed here
  // independently of tf2 and of the node).
  const Eigen::Matrix3d rt = rotationOf(kTiltedRpy.x(), kTiltedRpy.y(), kTiltedRpy.z());
  const Eigen::Vector3d centreBase(0.01, -0.01, 0.475), rpyFrame(0.02, -0.1, -0.3);
  const Eigen::Vector3d centreFrame = rt.transpose() * (centreBase - kTilted);
  const Eigen::Vector3d rpyBase = rpyOf(rt * rotationOf(rpyFrame.x(), rpyFrame.y(), rpyFrame.z()));
  auto ball = [](const Eigen::Vector3d& c, const Eigen::Vector3d& rpy, const std::array<double, 6>& th) {
    VerifyWorkspace::Request r = smallRequest(th);
    r.region_type = "sphere";
    r.center.x = c.x();
    r.center.y = c.y();
    r.center.z = c.z();
    r.radius = 0.005;
    r.roll_min = r.roll_max = rpy.x();
    r.pitch_min = r.pitch_max = rpy.y();
    r.yaw_min = r.yaw_max = rpy.z();
    return r;
  };
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto base = ball(centreBase, rpyBase, th);
    auto framed = ball(centreFrame, rpyFrame, th);
    framed.frame_id = "tilted";
    const auto rb = verify(base);
    const auto rf = verify(framed);
    ASSERT_TRUE(rb.success) << rb.message;
    ASSERT_TRUE(rf.success) << rf.message;
    EXPECT_EQ(rb.verdict, expected) << rb.message;
    EXPECT_EQ(rf.verdict, rb.verdict) << rf.message;
    if (rf.has_witness) {
      // In the frame's ball, with the frame's orientation; violating the threshold in the base frame.
      const auto w = to6(rf.witness_pose);
      EXPECT_LE((Eigen::Vector3d(w[0], w[1], w[2]) - centreFrame).norm(), 0.005 * (1 + 1e-12));
      EXPECT_EQ(w[3], rpyFrame.x());
      const Eigen::Vector3d p = kTilted + rt * Eigen::Vector3d(w[0], w[1], w[2]);
      const auto c = static_cast<std::size_t>(rf.witness_component);
      ASSERT_LT(c, 6u);
      EXPECT_GT(worstErrorAt({p.x(), p.y(), p.z(), rpyBase.x(), rpyBase.y(), rpyBase.z()})[c], th[c]);
    }
  }
}

TEST(Frames, UnknownFrameIsRefusedNamingIt) {
  auto req = smallRequest(kGenerous);
  req.frame_id = "no_such_frame";
  const ros::WallTime t0 = ros::WallTime::now();
  const auto r = verify(req);
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 5.0);  // ~tf_timeout = 1 s
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.verdict, "");
  EXPECT_NE(r.message.find("frame_id: no transform from frame \"no_such_frame\""), std::string::npos) << r.message;
  // Still serving.
  const auto ok = verify(smallRequest(kGenerous));
  EXPECT_TRUE(ok.success) << ok.message;
}

// ---- /verify_trajectory in frames ----------------------------------------------------------------------------

/// shortTrajectory() in `mode` (max_error to 5%).
VerifyTrajectory::Request baseTrajectory(const std::array<double, 6>& th, const std::string& interpolation,
                                         const std::string& mode = "verify") {
  VerifyTrajectory::Request r = shortTrajectory(th, interpolation);
  r.mode = mode;
  r.alpha = 0.05;
  return r;
}

/// The waypoints of `base` expressed in the frame whose pose in the base frame is (t, rt), computed in double
/// independently of tf2 and of the node: p_F = rt^T (p - t), R_F = rt^T R.
VerifyTrajectory::Request inFrame(const VerifyTrajectory::Request& base, const Eigen::Vector3d& t,
                                  const Eigen::Matrix3d& rt, const std::string& frame) {
  VerifyTrajectory::Request r = base;
  for (std::size_t i = 0; i < base.times.size(); ++i) {
    const Eigen::Vector3d p = rt.transpose() * (Eigen::Vector3d(base.x[i], base.y[i], base.z[i]) - t);
    const Eigen::Vector3d a = rpyOf(rt.transpose() * rotationOf(base.roll[i], base.pitch[i], base.yaw[i]));
    r.x[i] = p.x();
    r.y[i] = p.y();
    r.z[i] = p.z();
    r.roll[i] = a.x();
    r.pitch[i] = a.y();
    r.yaw[i] = a.z();
  }
  r.frame_id = frame;
  return r;
}

VerifyTrajectory::Response verifyTrajectory(const VerifyTrajectory::Request& req) {
  EXPECT_TRUE(ros::service::waitForService("/verify_trajectory", ros::Duration(20.0)));
  VerifyTrajectory srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call("/verify_trajectory", srv));
  return srv.response;
}

/// The framed request gives the base request's verdict (and overlapping max_error brackets); its witness pose is the
/// framed trajectory's position at witness_t and, mapped to the base frame, violates the threshold.
void expectSameTrajectoryAnswer(const VerifyTrajectory::Request& base, const VerifyTrajectory::Request& framed,
                                const Eigen::Vector3d& t, const Eigen::Matrix3d& rt, const std::string& expected) {
  const auto rb = verifyTrajectory(base);
  const auto rf = verifyTrajectory(framed);
  ASSERT_TRUE(rb.success) << rb.message;
  ASSERT_TRUE(rf.success) << rf.message;
  EXPECT_EQ(rb.verdict, expected) << rb.message;
  EXPECT_EQ(rf.verdict, rb.verdict) << rf.message;
  if (base.mode == "max_error") {
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_LE(rf.lower_bound[k], rb.upper_bound[k]) << k;
      EXPECT_LE(rb.lower_bound[k], rf.upper_bound[k]) << k;
      EXPECT_GT(rf.lower_bound[k], 0.0) << k;
    }
  }
  if (rf.verdict != "UNSAFE") return;
  ASSERT_TRUE(rf.has_witness);
  const auto c = static_cast<std::size_t>(rf.witness_component);
  ASSERT_LT(c, 6u);
  // The position of the framed trajectory at witness_t (linear between its waypoints, in the frame).
  const double wt = rf.witness_t;
  ASSERT_GE(wt, framed.times.front());
  ASSERT_LE(wt, framed.times.back());
  std::size_t i = 0;
  while (i + 2 < framed.times.size() && wt > framed.times[i + 1]) ++i;
  const double s = (wt - framed.times[i]) / (framed.times[i + 1] - framed.times[i]);
  const Eigen::Vector3d a(framed.x[i], framed.y[i], framed.z[i]), b(framed.x[i + 1], framed.y[i + 1], framed.z[i + 1]);
  const Eigen::Vector3d w(rf.witness_pose[0], rf.witness_pose[1], rf.witness_pose[2]);
  EXPECT_LT((w - (a + s * (b - a))).norm(), 1e-9) << "witness_pose is not the framed trajectory's pose at witness_t";
  const Eigen::Vector3d p = t + rt * w;
  const Eigen::Vector3d rpy = rpyOf(rt * rotationOf(rf.witness_pose[3], rf.witness_pose[4], rf.witness_pose[5]));
  const auto f = worstErrorAt({p.x(), p.y(), p.z(), rpy.x(), rpy.y(), rpy.z()});
  EXPECT_GT(f[c], framed.thresholds[c]);
  EXPECT_GE(f[c], rf.witness_error[c] * (1.0 - 1e-9));
}

TEST(Frames, TrajectoryInATiltedFrameGivesTheVerdictsOfTheBaseFrame) {
  const Eigen::Matrix3d rt = rotationOf(kTiltedRpy.x(), kTiltedRpy.y(), kTiltedRpy.z());
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto base = baseTrajectory(th, "slerp");
    expectSameTrajectoryAnswer(base, inFrame(base, kTilted, rt, "tilted"), kTilted, rt, expected);
  }
  const auto base = baseTrajectory(kNone, "slerp", "max_error");
  expectSameTrajectoryAnswer(base, inFrame(base, kTilted, rt, "tilted"), kTilted, rt, "UNDECIDED");
}

TEST(Frames, LinearRpyTrajectoryInATurnedFrameGivesTheVerdictsOfTheBaseFrame) {
  // Rotated about z: yaw is shifted by a constant, so the linear-RPY interpolant is the same in both frames.
  const Eigen::Matrix3d rt = rotationOf(0.0, 0.0, kYaw);
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto base = baseTrajectory(th, "linear_rpy");
    expectSameTrajectoryAnswer(base, inFrame(base, kTurned, rt, "turned"), kTurned, rt, expected);
  }
}

TEST(Frames, TrajectoryInAnUnknownFrameIsRefusedNamingIt) {
  auto req = baseTrajectory(kGenerous, "slerp");
  req.frame_id = "no_such_frame";
  const auto r = verifyTrajectory(req);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.verdict, "");
  EXPECT_NE(r.message.find("frame_id: no transform from frame \"no_such_frame\""), std::string::npos) << r.message;
  req.frame_id = "base_link";  // the base frame by name
  const auto ok = verifyTrajectory(req);
  EXPECT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.verdict, "SAFE") << ok.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "frames_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  // The static transforms of frames.test are up before the tests start.
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  for (const char* frame : {"work", "turned", "tilted"}) {
    std::string error;
    if (!buffer.canTransform("base_link", frame, ros::Time(0), ros::Duration(20.0), &error)) {
      ROS_ERROR("frames_test: no transform base_link <- %s: %s", frame, error.c_str());
    }
  }
  return RUN_ALL_TESTS();
}
