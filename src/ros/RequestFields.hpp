// Checks of request fields and the response fields shared by the /verify_workspace, /verify_trajectory and
// /verify_variety translations. Each returns false with `error` naming the field, what was expected and what was
// given. Internal to the ROS layer.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Quaternion.h>
#include <Eigen/Core>

#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace fields {

/// The request fields of the six pose coordinates, and their units.
constexpr const char* kPoseFields[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
constexpr const char* kPoseUnits[6] = {"m", "m", "m", "rad", "rad", "rad"};

/// A tf2 frame name as tf2 compares it: without a leading '/'.
std::string frameName(const std::string& frame);

/// A pose x, y, z (m), roll, pitch, yaw (rad), R = Rz(yaw) Ry(pitch) Rx(roll), as a geometry_msgs/Pose (orientation:
/// the unit quaternion of R).
geometry_msgs::Pose poseMsg(const std::array<double, 6>& pose);
/// The identity pose (position 0, orientation w = 1).
geometry_msgs::Pose identityPose();

/// A pose of a planner's message as x, y, z (m), roll, pitch, yaw (rad) with R = Rz(yaw) Ry(pitch) Rx(roll) equal to
/// the rotation of `q` up to rounding (any rotation, including pitch +-pi/2). `position` must be finite; `q` finite
/// with |q|^2 within 1e-2 of 1 (tf2's tolerance), normalised before use. On failure `error` names `position_field`
/// or `orientation_field`.
bool poseFromParts(const Eigen::Vector3d& position, const geometry_msgs::Quaternion& q,
                   const std::string& position_field, const std::string& orientation_field, std::array<double, 6>& pose,
                   std::string& error);

/// A number for messages (10 significant digits).
std::string num(double x);
/// "field[i]".
std::string idx(const char* field, std::size_t i);
/// An option where 0 means "default": finite, >= 0 and < upper; `out` gets the value or the default.
bool option(double x, double dflt, const char* field, const char* expected, double& out, std::string& error,
            double upper = HUGE_VAL);
/// `threads`: 0 (all hardware threads) to the node's limit.
bool threads(std::uint32_t requested, std::string& error);
/// `method`: "" gives `dflt` (the node's ~default_method, itself possibly "" = the verifier's); any other value must
/// be a registered enclosure method name.
bool method(const std::string& requested, const std::string& dflt, std::string& out, std::string& error);

/// `geometry_splitting`: "" (= "auto"), "auto", "never" or "always"; `out` gets the name ("" becomes "auto").
bool geometrySplitting(const std::string& requested, std::string& out, std::string& error);

/// The error components of a robot as the messages name them: "dx, dy, dz".
std::string errorNames(const std::vector<model::PoseComponent>& pose);

/// `thresholds`: one number > 0 per error component of the robot (`pose`, n of them: entries 0 .. n-1, in the unit of
/// their component; +inf allowed) and 0 in the entries n .. 5 (`type` names the robot in that message); in max_error
/// mode all six may be 0 ("none given", then `given` is false).
template <class Array>
bool thresholds(const Array& requested, bool maxError, const std::vector<model::PoseComponent>& pose,
                const std::string& type, std::array<double, 6>& out, bool& given, std::string& error) {
  const std::size_t n = std::min<std::size_t>(pose.size(), 6);
  bool allZero = true;
  for (double t : requested) allZero = allZero && t == 0.0;
  out.fill(0.0);
  for (std::size_t k = n; k < 6; ++k) {
    if (requested[k] == 0.0) continue;
    error = idx("thresholds", k) + ": expected 0 (robot type " + type + " has " + std::to_string(n) +
            " error components, " + errorNames(pose) + ": entries " + std::to_string(n) + " to 5 are unused), got " +
            num(requested[k]);
    return false;
  }
  given = !(maxError && allZero);
  if (!given) return true;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = requested[k];
    if (!(t > 0.0)) {  // also rejects NaN; +inf is allowed
      error = idx("thresholds", k) + " (" + pose[k].errorName() + "): expected a number > 0 (" + pose[k].unit +
              ") or .inf" + (maxError ? " (or all 0 in mode max_error)" : "") + ", got " + num(t);
      return false;
    }
    out[k] = t;
  }
  return true;
}

/// For a robot whose pose is not the rigid-body pose (`defaults.pose`), the refusal of a /verify_trajectory or
/// /verify_variety request (`service`), naming the robot's type and the service; "" for a rigid-body robot.
std::string rigidBodyOnly(const QueryDefaults& defaults, const char* service);

/// `frame_id` as tf2 names it (tf2 drops a leading '/', so "/base_link" is "base_link"), or "" for the base frame.
inline std::string frameId(const std::string& requested, const std::string& base_frame) {
  std::string f = requested;
  while (!f.empty() && f.front() == '/') f.erase(0, 1);
  return f == base_frame ? std::string() : f;
}

/// `mode`: "" or "verify" (Verify), "max_error" (MaxError).
inline bool mode(const std::string& requested, QueryMode& out, std::string& error) {
  if (requested.empty() || requested == "verify") {
    out = QueryMode::Verify;
  } else if (requested == "max_error") {
    out = QueryMode::MaxError;
  } else {
    error = "mode: expected \"verify\", \"max_error\" or \"\" (verify), got \"" + requested + "\"";
    return false;
  }
  return true;
}

/// The options every request (and goal) shares, after `mode`: thresholds, alpha,
/// time_budget, threads, method, geometry_splitting (min_width differs in unit: the caller reads it).
/// @return false with `error` naming the field.
template <class Request>
bool sharedOptions(const Request& req, const QueryDefaults& defaults, WorkspaceQuery& q, std::string& error) {
  q.components = static_cast<int>(defaults.pose.size());
  q.rigid_body_pose = defaults.rigidBodyPose();
  if (!thresholds(req.thresholds, q.mode == QueryMode::MaxError, defaults.pose, defaults.robot_type, q.thresholds,
                  q.has_thresholds, error)) {
    return false;
  }
  if (!option(req.alpha, defaults.alpha, "alpha", "a finite number >= 0 (relative, 0 = default)", q.alpha, error) ||
      !option(req.time_budget, defaults.time_budget, "time_budget", "a finite number >= 0 (s, 0 = default)",
              q.time_budget, error)) {
    return false;
  }
  if (!threads(req.threads, error)) return false;
  q.threads = req.threads;
  if (!method(req.method, defaults.method, q.method, error)) return false;
  return geometrySplitting(req.geometry_splitting, q.geometry_splitting, error);
}

/// Copies the options every request and action goal has (thresholds, mode, alpha, time_budget, min_width, threads,
/// method, frame_id, geometry_splitting) from `from` to `to`, field for field.
template <class From, class To>
void copyOptions(const From& from, To& to) {
  to.thresholds = from.thresholds;
  to.mode = from.mode;
  to.alpha = from.alpha;
  to.time_budget = from.time_budget;
  to.min_width = from.min_width;
  to.threads = from.threads;
  to.method = from.method;
  to.frame_id = from.frame_id;
  to.geometry_splitting = from.geometry_splitting;
}

/// The fields that every response, action result and the ~verdict message share, from a
/// job's outcome.
template <class Response, class Outcome>
void fillCommonResponse(const Outcome& o, Response& res) {
  res.success = o.success;
  res.message = o.message;
  res.job_id = o.job_id;
  res.verdict = o.verdict;
  res.reason = o.reason;
  for (std::size_t k = 0; k < 6; ++k) {
    res.lower_bound[k] = o.lower_bound[k];
    res.upper_bound[k] = o.upper_bound[k];
    res.witness_pose[k] = o.witness_pose[k];
    res.witness_error[k] = o.witness_error[k];
  }
  res.converged = o.converged;
  res.lower_bound_geometries = o.lower_bound_geometries;
  res.has_witness = o.has_witness;
  res.witness = o.has_witness && o.rigid_body_pose ? poseMsg(o.witness_pose) : identityPose();
  res.argmax_poses.clear();
  for (std::size_t row = 0; o.rigid_body_pose && row + 6 <= o.lower_bound_poses.size(); row += 6) {
    std::array<double, 6> pose{};
    for (std::size_t k = 0; k < 6; ++k) pose[k] = o.lower_bound_poses[row + k];
    res.argmax_poses.push_back(poseMsg(pose));
  }
  res.witness_component = o.witness_component;
  res.singular = o.singular;
  for (std::size_t i = 0; i < 12; ++i) res.singular_poses[i] = o.singular_poses[i];
  res.boxes = o.boxes;
  res.max_depth = o.max_depth;
  res.threads = o.threads;
  res.seconds = o.seconds;
  res.safe_fraction = o.safe_fraction;
  res.unsafe_fraction = o.unsafe_fraction;
  res.undecided_fraction = o.undecided_fraction;
  res.undecided_boxes = o.undecided_boxes;
  res.undecided_boxes_recorded = o.undecided_boxes_recorded;
  res.geometry_switches = o.geometry_switches;
  res.geometry_splits = o.geometry_splits;
  res.face_switches = o.face_switches;
  res.face_boxes = o.face_boxes;
  res.unenclosed_boxes = o.unenclosed_boxes;
  res.sensitive_poses = o.sensitive_poses;
  const SensitiveSummary& s = o.sensitive;
  res.sensitive_component = s.component;
  res.sensitive_failing_lower = s.failing_lower;
  for (std::size_t k = 0; k < 6; ++k) res.sensitive_pose[k] = s.pose[k];
  res.sensitive_failing_geometry = s.failing_geometry;
  res.sensitive_passing_geometry = s.passing_geometry;
  res.sensitive_passing_upper = s.passing_upper;
  res.sensitive_passes_all = s.passes_all;
}

}  // namespace fields
}  // namespace ros_layer
}  // namespace pkm_accuracy
