// rostest (trajectory.test): /verify_trajectory on the reference robot of config/ref6.yaml. A 3-waypoint trajectory
// inside the paper workspace is SAFE with generous thresholds and UNSAFE with tiny ones; the UNSAFE witness is checked
// independently: its time lies in the span, its pose is the linear interpolant of the waypoints there (position),
// and the worst error at that pose, evaluated in double from the yaml geometry (GoughPlatform::worstErrorAt, not the
// verifier), exceeds the violated threshold. Every malformed field gives success = false naming it, and the node
// keeps serving. The last job's ~verdict describes the trajectory.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/ros/BoxMarkers.hpp"
#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"

namespace {

using pkm_accuracy::VerificationResult;
using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy_test::kGenerous;
using pkm_accuracy_test::kNone;
using pkm_accuracy_test::kTiny;
using pkm_accuracy_test::shortTrajectory;
using pkm_accuracy_test::to6;
using pkm_accuracy_test::worstErrorAt;

constexpr const char* kService = "/verify_trajectory";

VerifyTrajectory::Response call(const VerifyTrajectory::Request& req) {
  EXPECT_TRUE(ros::service::waitForService(kService, ros::Duration(20.0)));
  VerifyTrajectory srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call(kService, srv));  // transport success even for bad requests
  return srv.response;
}

/// Linear interpolation of a coordinate of the waypoints at time t (the interpolant's position, docs/trajectories.md).
double interpolate(const std::vector<double>& times, const std::vector<double>& values, double t) {
  for (std::size_t i = 0; i + 1 < times.size(); ++i) {
    if (t <= times[i + 1]) {
      const double s = (t - times[i]) / (times[i + 1] - times[i]);
      return values[i] + s * (values[i + 1] - values[i]);
    }
  }
  return values.back();
}

TEST(VerifyTrajectory, SafeWithGenerousThresholds) {
  for (const std::string interpolation : {"slerp", "linear_rpy"}) {
    const VerifyTrajectory::Response res = call(shortTrajectory(kGenerous, interpolation));
    ASSERT_TRUE(res.success) << interpolation << ": " << res.message;
    EXPECT_EQ(res.verdict, VerifyTrajectory::Response::VERDICT_SAFE) << interpolation << ": " << res.message;
    EXPECT_FALSE(res.has_witness);
    EXPECT_EQ(res.witness_component, -1);
    EXPECT_GT(res.job_id, 0u);
    EXPECT_GT(res.boxes, 0u);
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_EQ(res.lower_bound[k], 0.0);
      EXPECT_EQ(res.upper_bound[k], kGenerous[k]);
    }
    EXPECT_DOUBLE_EQ(res.safe_fraction, 1.0);
    EXPECT_TRUE(res.undecided_t_start.empty());
  }
}

TEST(VerifyTrajectory, UnsafeWithTinyThresholdsHasAnIndependentlyCheckedWitness) {
  const VerifyTrajectory::Request req = shortTrajectory(kTiny, "linear_rpy");
  const VerifyTrajectory::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.verdict, VerifyTrajectory::Response::VERDICT_UNSAFE) << res.message;
  ASSERT_TRUE(res.has_witness);
  EXPECT_GE(res.witness_t, req.times.front());
  EXPECT_LE(res.witness_t, req.times.back());
  ASSERT_GE(res.witness_component, 0);
  ASSERT_LT(res.witness_component, 6);
  const auto k = static_cast<std::size_t>(res.witness_component);
  EXPECT_GT(res.witness_error[k], kTiny[k]);
  EXPECT_EQ(res.lower_bound[k], res.witness_error[k]);
  EXPECT_TRUE(std::isinf(res.upper_bound[k]));

  // The witness pose is the trajectory's pose at witness_t (linear_rpy: every coordinate linear between waypoints).
  const std::vector<double>* coords[6] = {&req.x, &req.y, &req.z, &req.roll, &req.pitch, &req.yaw};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(res.witness_pose[i], interpolate(req.times, *coords[i], res.witness_t), 1e-9) << "coordinate " << i;
  }
  // Independent oracle: the worst error there, from the yaml geometry in double, exceeds the threshold.
  const std::array<double, 6> e = worstErrorAt(to6(res.witness_pose));
  EXPECT_GT(e[k], kTiny[k]) << "component " << k;
  EXPECT_GE(e[k], res.witness_error[k] * (1.0 - 1e-9));  // the certified lower bound is below the true error
}

TEST(VerifyTrajectory, SlerpUnsafeWitnessIsInsideTheSpan) {
  const VerifyTrajectory::Request req = shortTrajectory(kTiny, "slerp");
  const VerifyTrajectory::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.verdict, VerifyTrajectory::Response::VERDICT_UNSAFE) << res.message;
  EXPECT_GE(res.witness_t, 1.0);
  EXPECT_LE(res.witness_t, 4.0);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::vector<double>* c = i == 0 ? &req.x : i == 1 ? &req.y : &req.z;
    EXPECT_NEAR(res.witness_pose[i], interpolate(req.times, *c, res.witness_t), 1e-9) << "coordinate " << i;
  }
  const auto k = static_cast<std::size_t>(res.witness_component);
  ASSERT_LT(k, 6u);
  EXPECT_GT(worstErrorAt(to6(res.witness_pose))[k], kTiny[k]);
}

TEST(VerifyTrajectory, MaxErrorBracketsTheWaypointErrors) {
  VerifyTrajectory::Request req = shortTrajectory({0, 0, 0, 0, 0, 0});
  req.mode = VerifyTrajectory::Request::MODE_MAX_ERROR;
  req.alpha = 0.05;
  const VerifyTrajectory::Response res = call(req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_EQ(res.lower_bound_times.size(), 6u);
  for (std::size_t i = 0; i < req.times.size(); ++i) {
    const std::array<double, 6> e = worstErrorAt({req.x[i], req.y[i], req.z[i], req.roll[i], req.pitch[i], req.yaw[i]});
    for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(e[k], res.upper_bound[k] * (1.0 + 1e-9)) << "waypoint " << i;
  }
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_LE(res.lower_bound[k], res.upper_bound[k]);
    EXPECT_GE(res.lower_bound_times[k], 1.0);
    EXPECT_LE(res.lower_bound_times[k], 4.0);
  }
}

/// A malformed request: success false, no job, and the message names `field`.
void expectRefused(const VerifyTrajectory::Request& req, const std::string& field) {
  const VerifyTrajectory::Response res = call(req);
  EXPECT_FALSE(res.success) << field;
  EXPECT_EQ(res.verdict, "") << field;
  EXPECT_EQ(res.job_id, 0u) << field;
  // "invalid request: <field>: ..." or "invalid request: <field> (<component>): ..."
  const std::string prefix = "invalid request: " + field;
  const bool named = res.message.compare(0, prefix.size(), prefix) == 0 && res.message.size() > prefix.size() &&
                     (res.message[prefix.size()] == ':' || res.message[prefix.size()] == ' ');
  EXPECT_TRUE(named) << "expected the message to name " << field << ": " << res.message;
}

TEST(VerifyTrajectory, MalformedFieldsAreRefusedByNameAndTheNodeKeepsServing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  {
    auto r = shortTrajectory(kGenerous);
    r.y[1] = nan;
    expectRefused(r, "y[1]");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.times[0] = nan;
    expectRefused(r, "times[0]");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.times = {1.0, 3.0, 2.0};
    expectRefused(r, "times[2]");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.times = {1.0, 1.0, 2.0};
    expectRefused(r, "times[1]");
  }
  {
    VerifyTrajectory::Request r = shortTrajectory(kGenerous);
    r.times = {1.0};
    r.x = {0.0};
    r.y = {0.0};
    r.z = {0.475};
    r.roll = r.pitch = r.yaw = {0.0};
    expectRefused(r, "times");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.yaw.pop_back();
    expectRefused(r, "yaw");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.x.push_back(0.0);
    expectRefused(r, "x");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.interpolation = "cubic";
    expectRefused(r, "interpolation");
  }
  {
    auto r = shortTrajectory({1e-3, 1e-3, 0.0, 1e-2, 1e-2, 1e-2});
    expectRefused(r, "thresholds[2]");
  }
  {
    auto r = shortTrajectory({0, 0, 0, 0, 0, 0});
    expectRefused(r, "thresholds[0]");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.mode = "fast";
    expectRefused(r, "mode");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.time_budget = -1.0;
    expectRefused(r, "time_budget");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.method = "magic";
    expectRefused(r, "method");
  }
  {
    auto r = shortTrajectory(kGenerous);
    r.geometry_splitting = "often";
    expectRefused(r, "geometry_splitting");
  }
  // Still serving, both services.
  const VerifyTrajectory::Response res = call(shortTrajectory(kGenerous));
  EXPECT_TRUE(res.success) << res.message;
  EXPECT_EQ(res.verdict, VerifyTrajectory::Response::VERDICT_SAFE);
  const auto ws = pkm_accuracy_test::verify(pkm_accuracy_test::smallRequest(kGenerous));
  EXPECT_TRUE(ws.success) << ws.message;
  EXPECT_EQ(ws.verdict, "SAFE");
}

TEST(VerifyTrajectory, VerdictTopicDescribesTheTrajectoryJob) {
  const VerifyTrajectory::Response res = call(shortTrajectory(kGenerous));
  ASSERT_TRUE(res.success) << res.message;
  std::mutex m;
  VerificationResult got;
  bool have = false;
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<VerificationResult>("/pkm_accuracy/verdict", 1,
                                                         [&](const pkm_accuracy::VerificationResultConstPtr& msg) {
                                                           std::lock_guard<std::mutex> lock(m);
                                                           got = *msg;
                                                           have = true;
                                                         });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (have) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  std::lock_guard<std::mutex> lock(m);
  ASSERT_TRUE(have);
  EXPECT_EQ(got.job_id, res.job_id);
  EXPECT_EQ(got.region_type, "trajectory");
  EXPECT_EQ(got.verdict, "SAFE");
  EXPECT_DOUBLE_EQ(got.workspace_min[0], -0.01);
  EXPECT_DOUBLE_EQ(got.workspace_max[2], 0.48);
}

// ---- polynomial segments ----------------------------------------------------------------------------------------

using pkm_accuracy::PolynomialSegment;

/// Horner's scheme in double (the oracle's evaluation of a segment).
double horner(const std::vector<double>& c, double tau) {
  double v = 0.0;
  for (std::size_t j = c.size(); j-- > 0;) v = v * tau + c[j];
  return v;
}

/// The linear_rpy waypoint trajectory `w` as linear polynomial segments (the same trajectory up to rounding).
VerifyTrajectory::Request asSegments(const VerifyTrajectory::Request& w) {
  VerifyTrajectory::Request r = w;
  r.times.clear();
  r.x.clear();
  r.y.clear();
  r.z.clear();
  r.roll.clear();
  r.pitch.clear();
  r.yaw.clear();
  r.interpolation.clear();
  const std::vector<double>* coords[6] = {&w.x, &w.y, &w.z, &w.roll, &w.pitch, &w.yaw};
  for (std::size_t i = 0; i + 1 < w.times.size(); ++i) {
    PolynomialSegment seg;
    seg.t = {w.times[i], w.times[i + 1]};
    std::vector<double>* out[6] = {&seg.x, &seg.y, &seg.z, &seg.roll, &seg.pitch, &seg.yaw};
    const double h = w.times[i + 1] - w.times[i];
    for (std::size_t k = 0; k < 6; ++k) *out[k] = {(*coords[k])[i], ((*coords[k])[i + 1] - (*coords[k])[i]) / h};
    r.polynomial_segments.push_back(seg);
  }
  return r;
}

/// The pose of segment trajectory `r` at time t (the segment containing t, the first one at a boundary).
std::array<double, 6> segmentPose(const VerifyTrajectory::Request& r, double t) {
  std::size_t i = 0;
  while (i + 1 < r.polynomial_segments.size() && t > r.polynomial_segments[i].t[1]) ++i;
  const PolynomialSegment& s = r.polynomial_segments[i];
  const std::vector<double>* c[6] = {&s.x, &s.y, &s.z, &s.roll, &s.pitch, &s.yaw};
  std::array<double, 6> p{};
  for (std::size_t k = 0; k < 6; ++k) p[k] = horner(*c[k], t - s.t[0]);
  return p;
}

TEST(VerifyTrajectory, PolynomialSegmentsGiveTheVerdictsOfTheSameWaypointTrajectory) {
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto waypoints = shortTrajectory(th, "linear_rpy");
    const auto segments = asSegments(waypoints);
    const auto rw = call(waypoints);
    const auto rs = call(segments);
    ASSERT_TRUE(rw.success) << rw.message;
    ASSERT_TRUE(rs.success) << rs.message;
    EXPECT_EQ(rw.verdict, expected) << rw.message;
    EXPECT_EQ(rs.verdict, expected) << rs.message;
    if (rs.verdict != "UNSAFE") continue;
    // The witness: a time of the span, the segments' pose there, violating the threshold (independent oracle).
    ASSERT_TRUE(rs.has_witness);
    EXPECT_GE(rs.witness_t, 1.0);
    EXPECT_LE(rs.witness_t, 4.0);
    const auto pose = segmentPose(segments, rs.witness_t);
    for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(rs.witness_pose[k], pose[k], 1e-9) << k;
    const auto c = static_cast<std::size_t>(rs.witness_component);
    ASSERT_LT(c, 6u);
    EXPECT_GT(worstErrorAt(pose)[c], th[c]);
  }
  // max_error: overlapping brackets.
  auto waypoints = shortTrajectory(kNone, "linear_rpy");
  waypoints.mode = "max_error";
  waypoints.alpha = 0.05;
  const auto rw = call(waypoints);
  const auto rs = call(asSegments(waypoints));
  ASSERT_TRUE(rw.success && rs.success) << rw.message << " / " << rs.message;
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_GT(rs.lower_bound[k], 0.0) << k;
    EXPECT_LE(rs.lower_bound[k], rw.upper_bound[k]) << k;
    EXPECT_LE(rw.lower_bound[k], rs.upper_bound[k]) << k;
  }
}

TEST(VerifyTrajectory, QuinticSegmentsMaxErrorContainsTheSampledMaxima) {
  // Two quintic-ish segments (curved in every coordinate) inside the paper workspace.
  VerifyTrajectory::Request r = asSegments(shortTrajectory(kNone, "linear_rpy"));
  r.polynomial_segments.resize(1);
  PolynomialSegment& a = r.polynomial_segments[0];
  a.t = {0.5, 1.5};
  a.x = {-0.01, 0.02, -0.01, 0.0, 0.0, 0.001};
  a.y = {0.0, 0.0, 0.01};
  a.z = {0.47, 0.005, 0.0, 0.002};
  a.roll = {0.0, 0.02, -0.02};
  a.pitch = {0.01, -0.01};
  a.yaw = {0.0, 0.0, 0.0, 0.0, 0.0, 0.01};
  PolynomialSegment b;
  b.t = {1.5, 2.0};
  b.x = {horner(a.x, 1.0), -0.01};
  b.y = {horner(a.y, 1.0)};
  b.z = {horner(a.z, 1.0), 0.0, -0.01};
  b.roll = {horner(a.roll, 1.0)};
  b.pitch = {horner(a.pitch, 1.0), 0.0, 0.02};
  b.yaw = {horner(a.yaw, 1.0), 0.005};
  r.polynomial_segments.push_back(b);
  r.mode = "max_error";
  r.alpha = 0.02;
  const auto res = call(r);
  ASSERT_TRUE(res.success) << res.message;
  EXPECT_TRUE(res.converged) << res.message;
  std::array<double, 6> sampled{};
  for (int n = 0; n <= 3000; ++n) {
    const auto f = worstErrorAt(segmentPose(r, 0.5 + 1.5 * n / 3000.0));
    for (std::size_t k = 0; k < 6; ++k) sampled[k] = std::max(sampled[k], f[k]);
  }
  ASSERT_EQ(res.lower_bound_times.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_LE(sampled[k], res.upper_bound[k]) << k;                 // certified over every time
    EXPECT_GE(sampled[k], res.lower_bound[k] * (1.0 - 1e-3)) << k;  // dense sampling gets near the maximum
    EXPECT_LE(res.lower_bound[k], worstErrorAt(segmentPose(r, res.lower_bound_times[k]))[k] * (1 + 1e-9)) << k;
  }
}

TEST(VerifyTrajectory, PolynomialSegmentsAreReadWithTheirBoundaryTimesAndPoses) {
  // (The poses at both ends of every segment give ~verdict's workspace_min / max.)
  const auto w = shortTrajectory(kGenerous, "linear_rpy");
  pkm_accuracy::ros_layer::WorkspaceQuery q;
  std::string error;
  ASSERT_TRUE(pkm_accuracy::ros_layer::fromRequest(asSegments(w), "base_link", pkm_accuracy::ros_layer::QueryDefaults(),
                                                   q, error))
      << error;
  EXPECT_EQ(q.trajectory.times, w.times);
  ASSERT_EQ(q.trajectory.segments.size(), 2u);
  ASSERT_EQ(q.trajectory.poses.size(), 4u);  // segment 0: waypoints 0 and 1, segment 1: waypoints 1 and 2
  const std::size_t waypoint[4] = {0, 1, 1, 2};
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t j = waypoint[i];
    const double expected[6] = {w.x[j], w.y[j], w.z[j], w.roll[j], w.pitch[j], w.yaw[j]};
    for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(q.trajectory.poses[i][k], expected[k], 1e-12) << i << " " << k;
  }
}

TEST(VerifyTrajectory, MalformedPolynomialSegmentsAreRefusedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto good = asSegments(shortTrajectory(kGenerous, "linear_rpy"));
  {
    auto r = good;
    r.times = {1.0, 2.0};
    expectRefused(r, "polynomial_segments");  // both forms
  }
  {
    auto r = good;
    r.interpolation = "slerp";
    expectRefused(r, "interpolation");
  }
  {
    auto r = good;
    r.polynomial_segments[1].t[0] = 2.5;  // a gap after the first segment
    expectRefused(r, "polynomial_segments[1].t");
  }
  {
    auto r = good;
    r.polynomial_segments[0].t = {2.0, 1.0};
    expectRefused(r, "polynomial_segments[0].t");
  }
  {
    auto r = good;
    r.polynomial_segments[0].y[1] = nan;
    expectRefused(r, "polynomial_segments[0].y[1]");
  }
  {
    auto r = good;
    r.polynomial_segments[1].z.clear();
    expectRefused(r, "polynomial_segments[1].z");
  }
  {
    auto r = good;
    r.polynomial_segments.clear();
    expectRefused(r, "times");  // neither form
  }
  const auto ok = call(good);
  EXPECT_TRUE(ok.success) << ok.message;
}

// ---- ~boxes: the path ------------------------------------------------------------------------------------------

const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  for (const auto& m : a.markers)
    if (m.ns == ns) return &m;
  return nullptr;
}

bool green(const std_msgs::ColorRGBA& c) { return c.g > 0.7f && c.r < 0.5f && c.b < 0.5f; }
bool orange(const std_msgs::ColorRGBA& c) { return c.r > 0.9f && c.g > 0.3f && c.g < 0.7f && c.b < 0.1f; }
bool blue(const std_msgs::ColorRGBA& c) { return c.b > 0.9f && c.r < 0.5f; }

TEST(VerifyTrajectory, BoxesDrawThePathAndTheWitness) {
  pkm_accuracy_test::Latest<visualization_msgs::MarkerArray> boxes("/pkm_accuracy/boxes");
  for (const auto& th : {kGenerous, kTiny}) {
    const auto req = shortTrajectory(th, "slerp");
    const auto res = call(req);
    ASSERT_TRUE(res.success) << res.message;
    const std::string label = "job " + std::to_string(res.job_id) + ":";
    const auto msg = boxes.waitFor([&](const visualization_msgs::MarkerArray& a) {
      const auto* l = findMarker(a, "label");
      return l && l->text.compare(0, label.size(), label) == 0;
    });
    ASSERT_TRUE(msg) << "no ~boxes for " << label;
    const auto* path = findMarker(*msg, pkm_accuracy::ros_layer::kMarkerNsTrajectory);
    ASSERT_TRUE(path);
    EXPECT_EQ(path->type, visualization_msgs::Marker::LINE_LIST);
    EXPECT_EQ(path->header.frame_id, "base_link");
    ASSERT_GE(path->points.size(), 2u * pkm_accuracy::ros_layer::kTrajectoryPieces);
    ASSERT_EQ(path->colors.size(), path->points.size());
    // From the first waypoint to the last (the marker's pose is the identity in the base frame).
    EXPECT_NEAR(path->points.front().x, req.x.front(), 1e-12);
    EXPECT_NEAR(path->points.front().z, req.z.front(), 1e-12);
    EXPECT_NEAR(path->points.back().y, req.y.back(), 1e-12);
    EXPECT_NEAR(path->points.back().z, req.z.back(), 1e-12);
    const auto* witness = findMarker(*msg, pkm_accuracy::ros_layer::kMarkerNsWitness);
    if (res.verdict == "SAFE") {
      for (const auto& c : path->colors) EXPECT_TRUE(green(c));  // every time proven within the thresholds
      EXPECT_FALSE(witness);
    } else {
      ASSERT_EQ(res.verdict, "UNSAFE");
      ASSERT_TRUE(witness);
      EXPECT_NEAR(witness->pose.position.x, res.witness_pose[0], 1e-12);
      EXPECT_NEAR(witness->pose.position.z, res.witness_pose[2], 1e-12);
      for (const auto& c : path->colors) EXPECT_FALSE(green(c));  // the search stopped at the witness
    }
  }
}

TEST(VerifyTrajectory, PathColoursFollowTheUndecidedIntervals) {
  // makeTrajectoryMarkers on an outcome with one undecided interval, [2.5, 3] s of the [1, 4] s trajectory.
  pkm_accuracy::ros_layer::WorkspaceQuery q;
  std::string error;
  pkm_accuracy::ros_layer::QueryDefaults defaults;
  ASSERT_TRUE(pkm_accuracy::ros_layer::fromRequest(shortTrajectory(kGenerous), "base_link", defaults, q, error))
      << error;
  pkm_accuracy::ros_layer::WorkspaceOutcome o;
  o.success = true;
  o.verdict = "UNDECIDED";
  o.reason = "time_budget";
  o.undecided_boxes = o.undecided_boxes_recorded = 1;
  o.undecided_times = {{2.5, 3.0}};
  const auto a = pkm_accuracy::ros_layer::makeTrajectoryMarkers(q, o, "base_link", ros::Time(1.0));
  const auto* path = findMarker(a, pkm_accuracy::ros_layer::kMarkerNsTrajectory);
  ASSERT_TRUE(path);
  ASSERT_EQ(path->colors.size(), path->points.size());
  // The pieces meeting [2.5, 3] s are orange, the others green (proven). The [2, 4] s segment has ceil(200 * 2 / 3)
  // = 134 pieces of 2 / 134 s; those meeting the interval are i = 33 ... 67 (the last one touches it at 3 s): 35.
  std::size_t orangePieces = 0, greenPieces = 0;
  for (std::size_t i = 0; i < path->colors.size(); i += 2) {
    orangePieces += orange(path->colors[i]) ? 1 : 0;
    greenPieces += green(path->colors[i]) ? 1 : 0;
  }
  EXPECT_EQ(orangePieces + greenPieces, path->colors.size() / 2);
  EXPECT_EQ(orangePieces, 35u);
  // Not every undecided interval recorded: no claim outside the recorded ones (blue).
  o.undecided_boxes = 2;
  const auto b = pkm_accuracy::ros_layer::makeTrajectoryMarkers(q, o, "base_link", ros::Time(1.0));
  const auto* unproven = findMarker(b, pkm_accuracy::ros_layer::kMarkerNsTrajectory);
  ASSERT_TRUE(unproven);
  for (std::size_t i = 0; i < unproven->colors.size(); ++i) {
    EXPECT_TRUE(orange(unproven->colors[i]) || blue(unproven->colors[i])) << i;
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "trajectory_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
