// rostest (standard_messages.test): the standard ROS messages the node accepts and gives, on the reference robot of
// config/ref6.yaml.
// - /verify_trajectory with a nav_msgs/Path (times from the poses' stamps) and a trajectory_msgs/
//   MultiDOFJointTrajectory (times from time_from_start): the verdicts of the same trajectory as waypoints, the
//   UNSAFE witness checked against an independent oracle (interpolated position, worst error in double); the action
//   ~verify_trajectory takes them too.
// - Exactly one form of trajectory per request: two at once are refused naming the second (service and action).
// - Malformed messages (frames, quaternions, times, joints) are refused naming the field.
// - Witnesses and argmax poses as geometry_msgs/Pose: the same poses as the arrays, the orientation checked against
//   R = Rz(yaw) Ry(pitch) Rx(roll) built here from elementary rotations.
// - /verify_workspace by name (`workspace: paper_40deg`): the verdict of the same workspace given by its fields (read
//   here from config/ref6.yaml), ~describe lists the names, and a name with region fields, an unknown name or
//   another frame is refused naming the field; loadNamedWorkspaces() on good and malformed parameters.
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "ActionHelpers.hpp"
#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyTrajectoryAction.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/ros/RobotLoader.hpp"
#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"

namespace {

using pkm_accuracy::VerificationResult;
using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy::VerifyTrajectoryAction;
using pkm_accuracy::VerifyTrajectoryGoal;
using pkm_accuracy::VerifyWorkspace;
using pkm_accuracy_test::kGenerous;
using pkm_accuracy_test::kNone;
using pkm_accuracy_test::kPaper;
using pkm_accuracy_test::kTiny;
using pkm_accuracy_test::shortTrajectory;
using pkm_accuracy_test::to6;
using pkm_accuracy_test::worstErrorAt;
using Client = actionlib::SimpleActionClient<VerifyTrajectoryAction>;

constexpr const char* kTrajectoryService = "/verify_trajectory";
constexpr const char* kTrajectoryAction = "/pkm_accuracy/verify_trajectory";

VerifyTrajectory::Response call(const VerifyTrajectory::Request& req) {
  EXPECT_TRUE(ros::service::waitForService(kTrajectoryService, ros::Duration(20.0)));
  VerifyTrajectory srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call(kTrajectoryService, srv));  // transport success even for bad requests
  return srv.response;
}

// ---- an independent rotation: R = Rz(yaw) Ry(pitch) Rx(roll) from the elementary matrices ----------------------

Eigen::Matrix3d rotation(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d rx, ry, rz;
  rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return rz * ry * rx;
}

geometry_msgs::Quaternion quaternion(double roll, double pitch, double yaw) {
  const Eigen::Quaterniond q(rotation(roll, pitch, yaw));
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

/// The pose message equals the pose x, y, z, roll, pitch, yaw: same position, and its quaternion (unit) gives R.
::testing::AssertionResult samePose(const geometry_msgs::Pose& m, const std::array<double, 6>& p) {
  const Eigen::Quaterniond q(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z);
  if (std::fabs(q.norm() - 1.0) > 1e-12) return ::testing::AssertionFailure() << "|q| = " << q.norm();
  const double dr = (q.toRotationMatrix() - rotation(p[3], p[4], p[5])).cwiseAbs().maxCoeff();
  if (dr > 1e-12) return ::testing::AssertionFailure() << "rotation differs by " << dr;
  if (m.position.x != p[0] || m.position.y != p[1] || m.position.z != p[2]) {
    return ::testing::AssertionFailure() << "position [" << m.position.x << ", " << m.position.y << ", " << m.position.z
                                         << "] vs [" << p[0] << ", " << p[1] << ", " << p[2] << "]";
  }
  return ::testing::AssertionSuccess();
}

// ---- the short trajectory (VerifyHelpers.hpp) as a Path and as a MultiDOFJointTrajectory -------------------------

/// shortTrajectory(thresholds) with its waypoints moved into a nav_msgs/Path: pose i at stamp times[i].
VerifyTrajectory::Request asPath(const std::array<double, 6>& thresholds, const std::string& frame = "") {
  const VerifyTrajectory::Request w = shortTrajectory(thresholds);
  VerifyTrajectory::Request r = w;
  r.times.clear();
  r.x.clear();
  r.y.clear();
  r.z.clear();
  r.roll.clear();
  r.pitch.clear();
  r.yaw.clear();
  r.interpolation.clear();
  r.path.header.frame_id = frame;
  for (std::size_t i = 0; i < w.times.size(); ++i) {
    geometry_msgs::PoseStamped p;
    p.header.stamp = ros::Time(w.times[i]);
    p.pose.position.x = w.x[i];
    p.pose.position.y = w.y[i];
    p.pose.position.z = w.z[i];
    p.pose.orientation = quaternion(w.roll[i], w.pitch[i], w.yaw[i]);
    r.path.poses.push_back(p);
  }
  return r;
}

/// The same as a MultiDOFJointTrajectory of one joint: point i at time_from_start times[i].
VerifyTrajectory::Request asMultiDof(const std::array<double, 6>& thresholds) {
  const VerifyTrajectory::Request p = asPath(thresholds);
  VerifyTrajectory::Request r = p;
  r.path = nav_msgs::Path();
  r.multi_dof_trajectory.joint_names = {"platform"};
  for (const auto& s : p.path.poses) {
    trajectory_msgs::MultiDOFJointTrajectoryPoint point;
    geometry_msgs::Transform t;
    t.translation.x = s.pose.position.x;
    t.translation.y = s.pose.position.y;
    t.translation.z = s.pose.position.z;
    t.rotation = s.pose.orientation;
    point.transforms.push_back(t);
    point.time_from_start = ros::Duration(s.header.stamp.toSec());
    r.multi_dof_trajectory.points.push_back(point);
  }
  return r;
}

/// Linear interpolation of the waypoints' coordinate at time t.
double interpolate(const std::vector<double>& times, const std::vector<double>& values, double t) {
  for (std::size_t i = 0; i + 1 < times.size(); ++i) {
    if (t <= times[i + 1]) return values[i] + (t - times[i]) / (times[i + 1] - times[i]) * (values[i + 1] - values[i]);
  }
  return values.back();
}

/// An UNSAFE answer's witness, checked independently: a time of the span, the interpolated position there, an error
/// above the violated threshold (worst error in double from the yaml geometry), and the Pose field equal to the array.
template <class Answer>
void expectCheckedWitness(const Answer& res, const std::array<double, 6>& thresholds) {
  const VerifyTrajectory::Request w = shortTrajectory(thresholds);
  ASSERT_TRUE(res.has_witness);
  EXPECT_GE(res.witness_t, w.times.front());
  EXPECT_LE(res.witness_t, w.times.back());
  const std::vector<double>* coords[3] = {&w.x, &w.y, &w.z};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(res.witness_pose[i], interpolate(w.times, *coords[i], res.witness_t), 1e-9) << "coordinate " << i;
  }
  ASSERT_GE(res.witness_component, 0);
  ASSERT_LT(res.witness_component, 6);
  const auto k = static_cast<std::size_t>(res.witness_component);
  EXPECT_GT(worstErrorAt(to6(res.witness_pose))[k], thresholds[k]);
  EXPECT_TRUE(samePose(res.witness, to6(res.witness_pose)));
}

/// A malformed request: success false, no job, and the message names `field` first.
void expectRefused(const VerifyTrajectory::Request& req, const std::string& field) {
  const VerifyTrajectory::Response res = call(req);
  EXPECT_FALSE(res.success) << field;
  EXPECT_EQ(res.job_id, 0u) << field;
  const std::string prefix = "invalid request: " + field + ":";
  EXPECT_EQ(res.message.compare(0, prefix.size(), prefix), 0)
      << "expected the message to name " << field << ": " << res.message;
}

TEST(StandardMessages, PathGivesTheVerdictsOfTheSameWaypoints) {
  for (const auto& th : {kGenerous, kTiny}) {
    const VerifyTrajectory::Response rw = call(shortTrajectory(th));
    const VerifyTrajectory::Response rp = call(asPath(th));
    ASSERT_TRUE(rw.success) << rw.message;
    ASSERT_TRUE(rp.success) << rp.message;
    EXPECT_EQ(rp.verdict, rw.verdict) << rp.message;
    EXPECT_EQ(rp.verdict, th == kGenerous ? "SAFE" : "UNSAFE") << rp.message;
    if (rp.verdict == "UNSAFE") expectCheckedWitness(rp, th);
  }
  // The path's header names the base frame: the same.
  const VerifyTrajectory::Response rb = call(asPath(kTiny, "base_link"));
  ASSERT_TRUE(rb.success) << rb.message;
  EXPECT_EQ(rb.verdict, "UNSAFE");
}

TEST(StandardMessages, MultiDofTrajectoryGivesTheVerdictsOfTheSameWaypoints) {
  for (const auto& th : {kGenerous, kTiny}) {
    const VerifyTrajectory::Response rm = call(asMultiDof(th));
    ASSERT_TRUE(rm.success) << rm.message;
    EXPECT_EQ(rm.verdict, th == kGenerous ? "SAFE" : "UNSAFE") << rm.message;
    if (rm.verdict == "UNSAFE") expectCheckedWitness(rm, th);
  }
  // No joint name at all is one joint as well.
  VerifyTrajectory::Request r = asMultiDof(kGenerous);
  r.multi_dof_trajectory.joint_names.clear();
  const VerifyTrajectory::Response rn = call(r);
  EXPECT_TRUE(rn.success) << rn.message;
  EXPECT_EQ(rn.verdict, "SAFE");
}

TEST(StandardMessages, QuaternionsBecomeTheSameRotations) {
  // Read by the conversion directly: every orientation, including pitch +-pi/2 (where roll and yaw are not unique),
  // comes back as roll, pitch, yaw whose R is the quaternion's.
  const double h = M_PI / 2;
  const std::vector<std::array<double, 3>> rpy = {{0.1, -0.2, 0.3}, {2.5, 1.2, -3.0}, {0.4, h, -0.7},
                                                  {-1.0, -h, 2.0},  {3.1, 0.0, -3.1}, {0.0, h - 1e-9, 0.5}};
  VerifyTrajectory::Request r;
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = kGenerous[k];
  for (std::size_t i = 0; i < rpy.size(); ++i) {
    geometry_msgs::PoseStamped p;
    p.header.stamp = ros::Time(1.0 + static_cast<double>(i));
    p.pose.position.z = 0.47;
    p.pose.orientation = quaternion(rpy[i][0], rpy[i][1], rpy[i][2]);
    r.path.poses.push_back(p);
  }
  pkm_accuracy::ros_layer::WorkspaceQuery q;
  std::string error;
  ASSERT_TRUE(pkm_accuracy::ros_layer::fromRequest(r, "base_link", pkm_accuracy::ros_layer::QueryDefaults(), q, error))
      << error;
  ASSERT_EQ(q.trajectory.poses.size(), rpy.size());
  EXPECT_TRUE(q.trajectory.slerp);
  for (std::size_t i = 0; i < rpy.size(); ++i) {
    const auto& p = q.trajectory.poses[i];
    EXPECT_EQ(q.trajectory.times[i], 1.0 + static_cast<double>(i));
    const double d = (rotation(p[3], p[4], p[5]) - rotation(rpy[i][0], rpy[i][1], rpy[i][2])).cwiseAbs().maxCoeff();
    EXPECT_LE(d, 1e-12) << "pose " << i;
  }
}

TEST(StandardMessages, MalformedPlannerMessagesAreRefusedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  {
    auto r = asPath(kGenerous);
    r.path.poses[2].header.stamp = r.path.poses[1].header.stamp;  // times must increase strictly
    expectRefused(r, "path.poses[2].header.stamp");
  }
  {
    auto r = asPath(kGenerous);
    r.path.poses.resize(1);
    expectRefused(r, "path.poses");
  }
  {
    auto r = asPath(kGenerous);
    r.path.poses[1].pose.orientation = geometry_msgs::Quaternion();  // all 0: an unset orientation
    expectRefused(r, "path.poses[1].pose.orientation");
  }
  {
    auto r = asPath(kGenerous);
    r.path.poses[0].pose.position.y = nan;
    expectRefused(r, "path.poses[0].pose.position");
  }
  {
    auto r = asPath(kGenerous, "map");
    r.path.poses[1].header.frame_id = "odom";
    expectRefused(r, "path.poses[1].header.frame_id");
  }
  {
    auto r = asPath(kGenerous, "map");
    r.frame_id = "base_link";
    expectRefused(r, "path.header.frame_id");
  }
  {
    auto r = asPath(kGenerous);
    r.interpolation = "linear_rpy";
    expectRefused(r, "interpolation");
  }
  {
    auto r = asMultiDof(kGenerous);
    r.multi_dof_trajectory.joint_names = {"platform", "gripper"};
    expectRefused(r, "multi_dof_trajectory.joint_names");
  }
  {
    auto r = asMultiDof(kGenerous);
    r.multi_dof_trajectory.points[1].transforms.clear();
    expectRefused(r, "multi_dof_trajectory.points[1].transforms");
  }
  {
    auto r = asMultiDof(kGenerous);
    r.multi_dof_trajectory.points[2].time_from_start = ros::Duration(0.5);
    expectRefused(r, "multi_dof_trajectory.points[2].time_from_start");
  }
  {
    auto r = asMultiDof(kGenerous);
    r.multi_dof_trajectory.points[0].transforms[0].rotation.w *= 2.0;  // |q|^2 far from 1
    expectRefused(r, "multi_dof_trajectory.points[0].transforms[0].rotation");
  }
  // A path in an unknown frame is looked up in tf2 like frame_id, and refused naming it.
  const VerifyTrajectory::Response res = call(asPath(kGenerous, "nowhere"));
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("frame_id: no transform from frame \"nowhere\""), std::string::npos) << res.message;
}

TEST(StandardMessages, TwoFormsOfTrajectoryAtOnceAreRefused) {
  const auto path = asPath(kGenerous);
  const auto multi = asMultiDof(kGenerous);
  const auto waypoints = shortTrajectory(kGenerous);
  {
    auto r = waypoints;
    r.path = path.path;
    expectRefused(r, "path");
  }
  {
    auto r = path;
    r.multi_dof_trajectory = multi.multi_dof_trajectory;
    expectRefused(r, "multi_dof_trajectory");
  }
  {
    auto r = waypoints;
    r.multi_dof_trajectory = multi.multi_dof_trajectory;
    const VerifyTrajectory::Response res = call(r);
    EXPECT_FALSE(res.success);
    EXPECT_NE(res.message.find("expected one form of trajectory per request"), std::string::npos) << res.message;
    EXPECT_NE(res.message.find("waypoints (3 times), a multi_dof_trajectory of 3 points"), std::string::npos)
        << res.message;
  }
  {
    auto r = path;
    pkm_accuracy::PolynomialSegment s;
    s.t = {1.0, 4.0};
    s.x = s.y = s.roll = s.pitch = s.yaw = {0.0};
    s.z = {0.47};
    r.polynomial_segments.push_back(s);
    expectRefused(r, "path");  // (polynomial_segments comes before path in the order of the forms)
  }
  // The action refuses the same goal, naming the field.
  Client client(kTrajectoryAction, true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(20.0)));
  auto r = waypoints;
  r.path = path.path;
  client.sendGoal(pkm_accuracy_test::convert<VerifyTrajectoryGoal>(r));
  ASSERT_TRUE(client.waitForResult(ros::Duration(20.0)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::REJECTED);
  EXPECT_EQ(client.getResult()->message.find("invalid request: path: expected one form of trajectory"), 0u)
      << client.getResult()->message;
}

TEST(StandardMessages, TheActionTakesAPathAndAMultiDofTrajectory) {
  Client client(kTrajectoryAction, true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(20.0)));
  for (const auto& req : {asPath(kTiny), asMultiDof(kTiny)}) {
    client.sendGoal(pkm_accuracy_test::convert<VerifyTrajectoryGoal>(req));
    ASSERT_TRUE(client.waitForResult(ros::Duration(30.0)));
    EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED);
    const auto result = client.getResult();
    ASSERT_TRUE(result->success) << result->message;
    EXPECT_EQ(result->verdict, "UNSAFE");
    expectCheckedWitness(*result, kTiny);
  }
}

// ---- poses as geometry_msgs/Pose ------------------------------------------------------------------------------

TEST(StandardMessages, WorkspaceWitnessAndArgmaxAsPoses) {
  const VerifyWorkspace::Response unsafe = pkm_accuracy_test::verify(pkm_accuracy_test::smallRequest(kTiny));
  ASSERT_TRUE(unsafe.success) << unsafe.message;
  ASSERT_TRUE(unsafe.has_witness);
  EXPECT_TRUE(samePose(unsafe.witness, to6(unsafe.witness_pose)));
  EXPECT_TRUE(unsafe.argmax_poses.empty());  // mode verify

  const VerifyWorkspace::Response safe = pkm_accuracy_test::verify(pkm_accuracy_test::smallRequest(kGenerous));
  ASSERT_TRUE(safe.success) << safe.message;
  ASSERT_FALSE(safe.has_witness);
  EXPECT_TRUE(samePose(safe.witness, {0, 0, 0, 0, 0, 0}));  // the identity

  VerifyWorkspace::Request req = pkm_accuracy_test::boxRequest(0.05, 0.46, 0.49, 0.1, kNone, "max_error");
  req.alpha = 0.1;
  const VerifyWorkspace::Response m = pkm_accuracy_test::verify(req);
  ASSERT_TRUE(m.success) << m.message;
  ASSERT_EQ(m.lower_bound_poses.size(), 36u);
  ASSERT_EQ(m.argmax_poses.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    std::array<double, 6> row{};
    for (std::size_t i = 0; i < 6; ++i) row[i] = m.lower_bound_poses[6 * k + i];
    EXPECT_TRUE(samePose(m.argmax_poses[k], row)) << "component " << k;
    // The pose attains the lower bound (independent oracle in double).
    EXPECT_GE(worstErrorAt(row)[k], m.lower_bound[k] * (1.0 - 1e-9)) << "component " << k;
  }
}

TEST(StandardMessages, TrajectoryArgmaxPosesAreTheTrajectorysPosesAtTheArgmaxTimes) {
  VerifyTrajectory::Request req = shortTrajectory(kNone, "linear_rpy");
  req.mode = "max_error";
  req.alpha = 0.05;
  const VerifyTrajectory::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.lower_bound_times.size(), 6u);
  ASSERT_EQ(res.argmax_poses.size(), 6u);
  const std::vector<double>* coords[6] = {&req.x, &req.y, &req.z, &req.roll, &req.pitch, &req.yaw};
  for (std::size_t k = 0; k < 6; ++k) {
    std::array<double, 6> pose{};  // linear_rpy: every coordinate linear between the waypoints
    for (std::size_t i = 0; i < 6; ++i) pose[i] = interpolate(req.times, *coords[i], res.lower_bound_times[k]);
    const geometry_msgs::Pose& m = res.argmax_poses[k];
    EXPECT_NEAR(m.position.x, pose[0], 1e-9) << k;
    EXPECT_NEAR(m.position.y, pose[1], 1e-9) << k;
    EXPECT_NEAR(m.position.z, pose[2], 1e-9) << k;
    const Eigen::Quaterniond q(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z);
    EXPECT_LE((q.toRotationMatrix() - rotation(pose[3], pose[4], pose[5])).cwiseAbs().maxCoeff(), 1e-9) << k;
    EXPECT_GE(worstErrorAt(pose)[k], res.lower_bound[k] * (1.0 - 1e-6)) << k;
  }
}

// ---- workspaces by name ------------------------------------------------------------------------------------------

/// Workspace `name` of config/ref6.yaml given by its fields (read here with yaml-cpp, not by the node's loader).
VerifyWorkspace::Request fromYaml(const std::string& name, const std::array<double, 6>& thresholds) {
  const YAML::Node w = YAML::LoadFile(pkm_accuracy_test::sourcePath("config/ref6.yaml"))["workspaces"][name];
  VerifyWorkspace::Request r;
  r.region_type = "box";
  const char* const xyz[3] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k) {
    r.box_min[k] = w[xyz[k]][0].as<double>();
    r.box_max[k] = w[xyz[k]][1].as<double>();
  }
  r.roll_min = w["roll"][0].as<double>();
  r.roll_max = w["roll"][1].as<double>();
  r.pitch_min = w["pitch"][0].as<double>();
  r.pitch_max = w["pitch"][1].as<double>();
  r.yaw_min = w["yaw"][0].as<double>();
  r.yaw_max = w["yaw"][1].as<double>();
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.time_budget = 20.0;
  return r;
}

VerifyWorkspace::Request byName(const std::string& name, const std::array<double, 6>& thresholds) {
  VerifyWorkspace::Request r;
  r.workspace = name;
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = thresholds[k];
  r.time_budget = 20.0;
  return r;
}

TEST(StandardMessages, DescribeListsTheNamedWorkspaces) {
  const auto d = pkm_accuracy_test::describe();
  ASSERT_TRUE(d.success) << d.message;
  EXPECT_EQ(d.workspaces, (std::vector<std::string>{"paper", "paper_40deg"}));
}

TEST(StandardMessages, WorkspaceByNameIsTheWorkspaceOfTheRobotFile) {
  const VerifyWorkspace::Request fields = fromYaml("paper_40deg", kPaper);
  const VerifyWorkspace::Response rf = pkm_accuracy_test::verify(fields);
  const VerifyWorkspace::Response rn = pkm_accuracy_test::verify(byName("paper_40deg", kPaper));
  ASSERT_TRUE(rf.success) << rf.message;
  ASSERT_TRUE(rn.success) << rn.message;
  EXPECT_EQ(rn.verdict, "UNSAFE");
  EXPECT_EQ(rn.verdict, rf.verdict);
  ASSERT_TRUE(rn.has_witness);
  EXPECT_TRUE(pkm_accuracy_test::poseInWorkspace(to6(rn.witness_pose), fields));
  const auto c = static_cast<std::size_t>(rn.witness_component);
  ASSERT_LT(c, 6u);
  EXPECT_GT(worstErrorAt(to6(rn.witness_pose))[c], kPaper[c]);

  // ~verdict names it and gives its box.
  pkm_accuracy_test::Latest<VerificationResult> verdict("/pkm_accuracy/verdict");
  const auto v = verdict.waitFor([&](const VerificationResult& m) { return m.job_id == rn.job_id; });
  ASSERT_TRUE(v);
  EXPECT_EQ(v->workspace, "paper_40deg");
  EXPECT_EQ(v->region_type, "box");
  EXPECT_EQ(v->workspace_min[0], fields.box_min[0]);
  EXPECT_EQ(v->workspace_max[5], fields.yaw_max);
  EXPECT_TRUE(samePose(v->witness, to6(v->witness_pose)));

  // The same in mode max_error on `paper`: the bracket of the fields' request contains the name's lower bounds.
  VerifyWorkspace::Request mf = fromYaml("paper", kNone), mn = byName("paper", kNone);
  mf.mode = mn.mode = "max_error";
  mf.alpha = mn.alpha = 0.5;
  const VerifyWorkspace::Response xf = pkm_accuracy_test::verify(mf);
  const VerifyWorkspace::Response xn = pkm_accuracy_test::verify(mn);
  ASSERT_TRUE(xf.success) << xf.message;
  ASSERT_TRUE(xn.success) << xn.message;
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_LE(xn.lower_bound[k], xf.upper_bound[k]) << k;
    EXPECT_LE(xf.lower_bound[k], xn.upper_bound[k]) << k;
  }
}

void expectWorkspaceRefused(const VerifyWorkspace::Request& req, const std::string& field) {
  const VerifyWorkspace::Response res = pkm_accuracy_test::verify(req);
  EXPECT_FALSE(res.success) << field;
  EXPECT_EQ(res.job_id, 0u) << field;
  const std::string prefix = "invalid request: " + field + ":";
  EXPECT_EQ(res.message.compare(0, prefix.size(), prefix), 0)
      << "expected the message to name " << field << ": " << res.message;
}

TEST(StandardMessages, WorkspaceNamesAreRefusedWithRegionFieldsUnknownNamesAndOtherFrames) {
  {
    auto r = byName("paper", kPaper);
    r.region_type = "box";
    expectWorkspaceRefused(r, "region_type");
  }
  {
    auto r = byName("paper", kPaper);
    r.roll_max = 0.1;
    expectWorkspaceRefused(r, "roll_max");
  }
  {
    auto r = byName("paper", kPaper);
    r.box_max[2] = 0.5;
    expectWorkspaceRefused(r, "box_max[2]");
  }
  {
    const auto r = byName("papier", kPaper);
    const VerifyWorkspace::Response res = pkm_accuracy_test::verify(r);
    EXPECT_FALSE(res.success);
    EXPECT_EQ(res.message,
              "invalid request: workspace: expected one of the robot's named workspaces \"paper\", \"paper_40deg\" or "
              "\"\", got \"papier\"");
  }
  {
    auto r = byName("paper", kPaper);
    r.frame_id = "table";
    expectWorkspaceRefused(r, "frame_id");
  }
  {
    auto r = byName("paper", kPaper);
    r.frame_id = "base_link";  // the base frame: accepted
    const VerifyWorkspace::Response res = pkm_accuracy_test::verify(r);
    EXPECT_TRUE(res.success) << res.message;
  }
}

// ---- loadNamedWorkspaces on the parameter server -----------------------------------------------------------------

XmlRpc::XmlRpcValue range(double lo, double hi) {
  XmlRpc::XmlRpcValue v;
  v.setSize(2);
  v[0] = lo;
  v[1] = hi;
  return v;
}

XmlRpc::XmlRpcValue boxWorkspace() {
  XmlRpc::XmlRpcValue w;
  w["x"] = range(-0.1, 0.1);
  w["y"] = range(-0.1, 0.1);
  w["z"] = range(0.45, 0.5);
  w["roll"] = range(-0.1, 0.1);
  w["pitch"] = range(-0.1, 0.1);
  w["yaw"] = range(-0.1, 0.1);
  return w;
}

/// Sets ~<ns>/workspaces/<name> = `w` and loads them.
bool load(const std::string& ns, const XmlRpc::XmlRpcValue& w,
          std::map<std::string, pkm_accuracy::ros_layer::NamedWorkspace>& out, std::string& error) {
  ros::NodeHandle nh("~" + ns);
  XmlRpc::XmlRpcValue all;
  all["w"] = w;
  nh.setParam("workspaces", all);
  return pkm_accuracy::ros_layer::loadNamedWorkspaces(nh, out, error);
}

TEST(StandardMessages, NamedWorkspaceParametersAreReadOrRefusedByName) {
  std::map<std::string, pkm_accuracy::ros_layer::NamedWorkspace> out;
  std::string error;
  XmlRpc::XmlRpcValue cylinder = boxWorkspace();
  cylinder["region"]["type"] = std::string("cylinder");
  cylinder["region"]["centre"] = range(0.01, 0.02);
  cylinder["region"]["radius"] = 0.05;
  ASSERT_TRUE(load("good", cylinder, out, error)) << error;
  ASSERT_EQ(out.count("w"), 1u);
  const auto& p = out.at("w").spec.position;
  EXPECT_EQ(p.type, pkm_accuracy::ros_layer::PositionRegion::Type::Cylinder);
  EXPECT_EQ(p.center.x(), 0.01);
  EXPECT_EQ(p.radius, 0.05);
  EXPECT_EQ(p.z_min, 0.45);  // the z range
  EXPECT_EQ(out.at("w").spec.angle_max[2], 0.1);
  EXPECT_FALSE(out.at("w").has_frame);

  // Nothing set: no workspaces, no error.
  ros::NodeHandle empty("~none");
  EXPECT_TRUE(pkm_accuracy::ros_layer::loadNamedWorkspaces(empty, out, error)) << error;
  EXPECT_TRUE(out.empty());

  struct Case {
    std::string ns, key;
    XmlRpc::XmlRpcValue value;
  };
  XmlRpc::XmlRpcValue reversed = boxWorkspace();
  reversed["z"] = range(0.5, 0.45);
  XmlRpc::XmlRpcValue unknown = boxWorkspace();
  unknown["rol"] = range(0.0, 0.1);
  XmlRpc::XmlRpcValue badType = boxWorkspace();
  badType["region"]["type"] = std::string("cube");
  XmlRpc::XmlRpcValue badRadius = cylinder;
  badRadius["region"]["radius"] = -1.0;
  const std::vector<Case> cases = {{"reversed", "/w/z:", reversed},
                                   {"unknown", "/w/rol: unknown key", unknown},
                                   {"type", "/w/region/type: expected box, cylinder, sphere or polyhedron", badType},
                                   {"radius", "/w/region/radius: expected a number > 0", badRadius}};
  for (const Case& c : cases) {
    EXPECT_FALSE(load(c.ns, c.value, out, error)) << c.ns;
    EXPECT_NE(error.find(ros::NodeHandle("~" + c.ns).resolveName("workspaces") + c.key), std::string::npos)
        << c.ns << ": " << error;
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "standard_messages_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
