#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"

#include "RequestFields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <vector>

#include <Eigen/Core>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

using fields::idx;
using fields::num;
using fields::option;
using pkm_accuracy::PolynomialSegment;

bool readWaypoints(const VerifyTrajectory::Request& req, TrajectorySpec& spec, std::string& error) {
  const std::size_t n = req.times.size();
  if (n < 2) {
    error =
        "times: expected at least 2 waypoints (one time each, s), or the trajectory as polynomial_segments, path or "
        "multi_dof_trajectory instead, got " +
        std::to_string(n) + " waypoints";
    return false;
  }
  const std::vector<double>* coords[6] = {&req.x, &req.y, &req.z, &req.roll, &req.pitch, &req.yaw};
  const char* const* names = fields::kPoseFields;
  const char* const* units = fields::kPoseUnits;
  for (std::size_t k = 0; k < 6; ++k) {
    if (coords[k]->size() != n) {
      error = std::string(names[k]) + ": expected " + std::to_string(n) + " values (one per waypoint, as times), got " +
              std::to_string(coords[k]->size());
      return false;
    }
  }
  spec.times.assign(n, 0.0);
  spec.poses.assign(n, std::array<double, 6>{});
  for (std::size_t i = 0; i < n; ++i) {
    const double t = req.times[i];
    if (!std::isfinite(t)) {
      error = idx("times", i) + ": expected a finite time (s), got " + num(t);
      return false;
    }
    if (i > 0 && !(t > req.times[i - 1])) {
      error = idx("times", i) + ": expected a time greater than " + idx("times", i - 1) + " = " +
              num(req.times[i - 1]) + " s (times must increase strictly), got " + num(t);
      return false;
    }
    spec.times[i] = t;
    for (std::size_t k = 0; k < 6; ++k) {
      const double v = (*coords[k])[i];
      if (!std::isfinite(v)) {
        error = idx(names[k], i) + ": expected a finite number (" + units[k] + "), got " + num(v);
        return false;
      }
      spec.poses[i][k] = v;
    }
  }
  if (req.interpolation.empty() || req.interpolation == VerifyTrajectory::Request::INTERPOLATION_SLERP) {
    spec.slerp = true;
  } else if (req.interpolation == VerifyTrajectory::Request::INTERPOLATION_LINEAR_RPY) {
    spec.slerp = false;
  } else {
    error = "interpolation: expected \"slerp\", \"linear_rpy\" or \"\" (slerp), got \"" + req.interpolation + "\"";
    return false;
  }
  return true;
}

bool readPolynomialSegments(const VerifyTrajectory::Request& req, TrajectorySpec& spec, std::string& error) {
  if (!req.interpolation.empty()) {
    error = "interpolation: expected \"\" with polynomial_segments (it applies to waypoints), got \"" +
            req.interpolation + "\"";
    return false;
  }
  spec.segments.clear();
  for (const PolynomialSegment& m : req.polynomial_segments) {
    domain::PolynomialTrajectory::Segment seg;
    seg.start = m.t[0];
    seg.end = m.t[1];
    seg.coefficients = {m.x, m.y, m.z, m.roll, m.pitch, m.yaw};
    spec.segments.push_back(std::move(seg));
  }
  // The core's own checks (tiling, finite values, degrees), whose messages name polynomial_segments[k].t / .x[j] ...
  std::unique_ptr<domain::PolynomialTrajectory> trajectory;
  try {
    trajectory = std::make_unique<domain::PolynomialTrajectory>(spec.segments);
  } catch (const InvalidArgument& e) {
    error = e.what();
    return false;
  }
  // The segment boundaries, and the poses at both ends of every segment (its own side of a boundary; reports only).
  spec.times = trajectory->times();
  spec.poses.clear();
  for (std::size_t k = 0; k + 1 < spec.times.size(); ++k) {
    for (double t : {spec.times[k], std::nextafter(spec.times[k + 1], spec.times[k])}) {
      const DVec p = trajectory->pointAtTime(t).pose;
      spec.poses.push_back({p[0], p[1], p[2], p[3], p[4], p[5]});
    }
  }
  return true;
}

/// Whether the request gives its trajectory as waypoints (any of the seven arrays not empty).
bool hasWaypoints(const VerifyTrajectory::Request& req) {
  return !(req.times.empty() && req.x.empty() && req.y.empty() && req.z.empty() && req.roll.empty() &&
           req.pitch.empty() && req.yaw.empty());
}

/// Whether a header names a frame other than `frame` ("" names none; a leading '/' is ignored, as tf2 does).
bool otherFrame(const std::string& header_frame, const std::string& frame) {
  return !header_frame.empty() && fields::frameName(header_frame) != fields::frameName(frame);
}

/// The frame of a planner's message (path, multi_dof_trajectory) against the request's frame_id: its header.frame_id
/// becomes the trajectory's frame when frame_id is ""; otherwise both must name the same frame.
bool messageFrame(const std::string& header_frame, const std::string& field, std::string& frame_id,
                  std::string& error) {
  if (frame_id.empty()) {
    frame_id = header_frame;
    return true;
  }
  if (!otherFrame(header_frame, frame_id)) return true;
  error = field + ".header.frame_id: expected \"\" or frame_id's frame \"" + frame_id +
          "\" (one frame per request), got \"" + header_frame + "\"";
  return false;
}

/// The interpolation of a planner's message: slerp only (its orientations are quaternions; linear_rpy would
/// interpolate angles that the quaternions do not give).
bool quaternionInterpolation(const VerifyTrajectory::Request& req, const char* field, TrajectorySpec& spec,
                             std::string& error) {
  if (req.interpolation.empty() || req.interpolation == VerifyTrajectory::Request::INTERPOLATION_SLERP) {
    spec.slerp = true;
    return true;
  }
  error = std::string("interpolation: expected \"slerp\" or \"\" with ") + field +
          " (its orientations are quaternions; linear_rpy interpolates roll, pitch and yaw), got \"" +
          req.interpolation + "\"";
  return false;
}

/// One waypoint of a planner's message: its time (s, finite, after the previous one) and its pose (position finite,
/// quaternion as fields::poseFromParts).
bool addWaypoint(double t, const Eigen::Vector3d& position, const geometry_msgs::Quaternion& q, const std::string& at,
                 const std::string& time_field, const std::string& position_field, const std::string& orientation_field,
                 TrajectorySpec& spec, std::string& error) {
  if (!std::isfinite(t)) {
    error = time_field + ": expected a finite time (s), got " + num(t);
    return false;
  }
  if (!spec.times.empty() && !(t > spec.times.back())) {
    error = time_field + ": expected a time greater than the previous " + at + "'s, " + num(spec.times.back()) +
            " s (times must increase strictly), got " + num(t);
    return false;
  }
  std::array<double, 6> pose{};
  if (!fields::poseFromParts(position, q, position_field, orientation_field, pose, error)) return false;
  spec.times.push_back(t);
  spec.poses.push_back(pose);
  return true;
}

bool readPath(const VerifyTrajectory::Request& req, TrajectorySpec& spec, std::string& frame_id, std::string& error) {
  const nav_msgs::Path& path = req.path;
  if (path.poses.size() < 2) {
    error = "path.poses: expected at least 2 poses (waypoints, timed by their header.stamp), got " +
            std::to_string(path.poses.size());
    return false;
  }
  if (!quaternionInterpolation(req, "path", spec, error)) return false;
  for (std::size_t i = 0; i < path.poses.size(); ++i) {
    const geometry_msgs::PoseStamped& p = path.poses[i];
    const std::string at = idx("path.poses", i);
    if (otherFrame(p.header.frame_id, path.header.frame_id)) {
      error = at + ".header.frame_id: expected \"\" or path.header.frame_id \"" + path.header.frame_id +
              "\" (one frame per path), got \"" + p.header.frame_id + "\"";
      return false;
    }
    const Eigen::Vector3d position(p.pose.position.x, p.pose.position.y, p.pose.position.z);
    if (!addWaypoint(p.header.stamp.toSec(), position, p.pose.orientation, "pose", at + ".header.stamp",
                     at + ".pose.position", at + ".pose.orientation", spec, error)) {
      return false;
    }
  }
  return messageFrame(path.header.frame_id, "path", frame_id, error);
}

bool readMultiDofTrajectory(const VerifyTrajectory::Request& req, TrajectorySpec& spec, std::string& frame_id,
                            std::string& error) {
  const trajectory_msgs::MultiDOFJointTrajectory& m = req.multi_dof_trajectory;
  if (m.joint_names.size() > 1) {
    std::string names;
    for (const auto& n : m.joint_names) names += (names.empty() ? "\"" : ", \"") + n + "\"";
    error = "multi_dof_trajectory.joint_names: expected at most one joint (the platform frame's pose), got " +
            std::to_string(m.joint_names.size()) + ": " + names;
    return false;
  }
  if (m.points.size() < 2) {
    error =
        "multi_dof_trajectory.points: expected at least 2 points (waypoints, timed by their time_from_start), got " +
        std::to_string(m.points.size());
    return false;
  }
  if (!quaternionInterpolation(req, "multi_dof_trajectory", spec, error)) return false;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const trajectory_msgs::MultiDOFJointTrajectoryPoint& p = m.points[i];
    const std::string at = idx("multi_dof_trajectory.points", i);
    if (p.transforms.size() != 1) {
      error = at + ".transforms: expected 1 transform (the platform frame's pose), got " +
              std::to_string(p.transforms.size());
      return false;
    }
    const geometry_msgs::Transform& tf = p.transforms[0];
    const Eigen::Vector3d position(tf.translation.x, tf.translation.y, tf.translation.z);
    if (!addWaypoint(p.time_from_start.toSec(), position, tf.rotation, "point", at + ".time_from_start",
                     at + ".transforms[0].translation", at + ".transforms[0].rotation", spec, error)) {
      return false;
    }
  }
  return messageFrame(m.header.frame_id, "multi_dof_trajectory", frame_id, error);
}

/// Exactly one form of trajectory: waypoints, polynomial_segments, path or multi_dof_trajectory. A form counts as
/// given when any of its fields is not empty (a path's or trajectory's header alone does not count).
bool oneForm(const VerifyTrajectory::Request& req, std::string& error) {
  std::vector<std::pair<std::string, std::string>> given;  // (field, what it holds)
  if (hasWaypoints(req)) given.emplace_back("times", "waypoints (" + std::to_string(req.times.size()) + " times)");
  if (!req.polynomial_segments.empty()) {
    given.emplace_back("polynomial_segments", std::to_string(req.polynomial_segments.size()) + " polynomial segments");
  }
  if (!req.path.poses.empty())
    given.emplace_back("path", "a path of " + std::to_string(req.path.poses.size()) + " poses");
  const auto& m = req.multi_dof_trajectory;
  if (!m.points.empty() || !m.joint_names.empty()) {
    given.emplace_back("multi_dof_trajectory",
                       "a multi_dof_trajectory of " + std::to_string(m.points.size()) + " points");
  }
  if (given.size() <= 1) return true;
  error = given[1].first +
          ": expected one form of trajectory per request (waypoints, polynomial_segments, path or "
          "multi_dof_trajectory), got " +
          std::to_string(given.size()) + ":";
  for (std::size_t i = 0; i < given.size(); ++i) error += (i == 0 ? " " : ", ") + given[i].second;
  return false;
}

}  // namespace

bool fromRequest(const VerifyTrajectory::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error) {
  error = fields::rigidBodyOnly(defaults, "verify_trajectory");
  if (!error.empty()) return false;
  WorkspaceQuery q;
  q.domain = QueryDomain::Trajectory;
  if (!fields::mode(req.mode, q.mode, error)) return false;
  if (!oneForm(req, error)) return false;
  std::string frame = req.frame_id;
  bool read = false;
  if (!req.polynomial_segments.empty()) {
    read = readPolynomialSegments(req, q.trajectory, error);
  } else if (!req.path.poses.empty()) {
    read = readPath(req, q.trajectory, frame, error);
  } else if (!req.multi_dof_trajectory.points.empty() || !req.multi_dof_trajectory.joint_names.empty()) {
    read = readMultiDofTrajectory(req, q.trajectory, frame, error);
  } else {
    read = readWaypoints(req, q.trajectory, error);
  }
  if (!read) return false;
  // Another frame is looked up in tf2 by the node when the job starts (an unknown one is refused then).
  q.frame_id = fields::frameId(frame, base_frame);
  if (!fields::sharedOptions(req, defaults, q, error)) return false;
  // min_width is a duration (s) here; the node's ~default_min_width (m / rad, for workspaces) does not apply.
  if (!option(req.min_width, 0.0, "min_width", "a finite number >= 0 (s, 0 = the verifier's choice)", q.min_width,
              error)) {
    return false;
  }
  out = q;
  return true;
}

namespace {

// The response and the action result have the same fields.
template <class Response>
void fillResponse(const WorkspaceOutcome& o, Response& res) {
  fields::fillCommonResponse(o, res);
  res.busy = o.busy;
  res.lower_bound_times = o.lower_bound_times;
  res.witness_t = o.witness_t;
  res.singular_t[0] = o.singular_t[0];
  res.singular_t[1] = o.singular_t[1];
  res.sensitive_t = o.sensitive.t;
  res.sensitive_t_start = o.sensitive.t_start;
  res.sensitive_t_end = o.sensitive.t_end;
  res.undecided_t_start.clear();
  res.undecided_t_end.clear();
  for (const auto& iv : o.undecided_times) {
    res.undecided_t_start.push_back(iv.first);
    res.undecided_t_end.push_back(iv.second);
  }
}

}  // namespace

void toResponse(const WorkspaceOutcome& o, VerifyTrajectory::Response& res) { fillResponse(o, res); }

void toResult(const WorkspaceOutcome& o, VerifyTrajectoryResult& result) { fillResponse(o, result); }

VerifyTrajectory::Request toRequest(const VerifyTrajectoryGoal& g) {
  VerifyTrajectory::Request r;
  r.times = g.times;
  r.x = g.x;
  r.y = g.y;
  r.z = g.z;
  r.roll = g.roll;
  r.pitch = g.pitch;
  r.yaw = g.yaw;
  r.interpolation = g.interpolation;
  r.polynomial_segments = g.polynomial_segments;
  r.path = g.path;
  r.multi_dof_trajectory = g.multi_dof_trajectory;
  fields::copyOptions(g, r);
  return r;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
