#include "pkm_accuracy/ros/VerifyWorkspaceConversion.hpp"

#include "RequestFields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PoseBox.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/ros/CoreBridge.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

using fields::idx;
using fields::num;
using fields::option;

bool finite(double x, const std::string& field, const char* unit, std::string& error) {
  if (std::isfinite(x)) return true;
  error = field + ": expected a finite number (" + unit + "), got " + num(x);
  return false;
}

bool ordered(double lo, double hi, const std::string& lo_name, const std::string& hi_name, const char* unit,
             std::string& error) {
  if (!finite(lo, lo_name, unit, error) || !finite(hi, hi_name, unit, error)) return false;
  if (lo <= hi) return true;
  error = lo_name + ": expected <= " + hi_name + " = " + num(hi) + " (" + unit + "), got " + num(lo);
  return false;
}

bool positive(double x, const std::string& field, const char* unit, std::string& error) {
  if (!finite(x, field, unit, error)) return false;
  if (x > 0.0) return true;
  error = field + ": expected a number > 0 (" + unit + "), got " + num(x);
  return false;
}

bool readRegion(const VerifyWorkspace::Request& req, PositionRegion& r, std::string& error) {
  using T = PositionRegion::Type;
  if (req.region_type == VerifyWorkspace::Request::REGION_BOX) {
    r.type = T::Box;
  } else if (req.region_type == VerifyWorkspace::Request::REGION_CYLINDER) {
    r.type = T::Cylinder;
  } else if (req.region_type == VerifyWorkspace::Request::REGION_SPHERE) {
    r.type = T::Sphere;
  } else if (req.region_type == VerifyWorkspace::Request::REGION_POLYHEDRON) {
    r.type = T::Polyhedron;
  } else {
    error =
        "region_type: expected one of \"box\", \"cylinder\", \"sphere\", \"polyhedron\" (or a named workspace in "
        "workspace), got \"" +
        req.region_type + "\"";
    return false;
  }
  if (r.type != T::Polyhedron && !(req.halfspace_normals.empty() && req.halfspace_offsets.empty())) {
    error = "halfspace_normals: expected none (half-spaces are only used with region_type \"polyhedron\"), got " +
            std::to_string(req.halfspace_normals.size()) + " normals and " +
            std::to_string(req.halfspace_offsets.size()) + " offsets";
    return false;
  }
  switch (r.type) {
    case T::Box:
    case T::Polyhedron:
      for (std::size_t k = 0; k < 3; ++k) {
        if (!ordered(req.box_min[k], req.box_max[k], idx("box_min", k), idx("box_max", k), "m", error)) return false;
        r.box_min[k] = req.box_min[k];
        r.box_max[k] = req.box_max[k];
      }
      break;
    case T::Sphere:
      if (!finite(req.center.x, "center.x", "m", error) || !finite(req.center.y, "center.y", "m", error) ||
          !finite(req.center.z, "center.z", "m", error) || !positive(req.radius, "radius", "m", error)) {
        return false;
      }
      r.center = Eigen::Vector3d(req.center.x, req.center.y, req.center.z);
      r.radius = req.radius;
      break;
    case T::Cylinder:
      if (!finite(req.center.x, "center.x", "m", error) || !finite(req.center.y, "center.y", "m", error) ||
          !positive(req.radius, "radius", "m", error) || !ordered(req.z_min, req.z_max, "z_min", "z_max", "m", error)) {
        return false;
      }
      r.center = Eigen::Vector3d(req.center.x, req.center.y, 0.0);
      r.radius = req.radius;
      r.z_min = req.z_min;
      r.z_max = req.z_max;
      break;
  }
  if (r.type == T::Polyhedron) {
    if (req.halfspace_normals.empty()) {
      error =
          "halfspace_normals: expected at least one half-space with region_type \"polyhedron\" (use \"box\" "
          "for a box), got none";
      return false;
    }
    if (req.halfspace_normals.size() != req.halfspace_offsets.size()) {
      error = "halfspace_offsets: expected one offset per normal (" + std::to_string(req.halfspace_normals.size()) +
              "), got " + std::to_string(req.halfspace_offsets.size());
      return false;
    }
    for (std::size_t j = 0; j < req.halfspace_normals.size(); ++j) {
      const auto& n = req.halfspace_normals[j];
      const Eigen::Vector3d v(n.x, n.y, n.z);
      if (!v.allFinite() || v.norm() == 0.0) {
        error = idx("halfspace_normals", j) + ": expected a finite non-zero vector, got [" + num(n.x) + ", " +
                num(n.y) + ", " + num(n.z) + "]";
        return false;
      }
      if (!finite(req.halfspace_offsets[j], idx("halfspace_offsets", j), "m", error)) return false;
      r.halfspace_normals.push_back(v);
      r.halfspace_offsets.push_back(req.halfspace_offsets[j]);
    }
    // The core refuses a polyhedron it proves empty (a verification over it would be vacuous): before the request
    // becomes a job.
    try {
      domain::PositionRegion::polyhedron(r.halfspace_normals, r.halfspace_offsets, r.box_min, r.box_max);
    } catch (const InvalidArgument& e) {
      error = std::string("halfspace_normals, halfspace_offsets: ") + e.what();
      return false;
    }
  }
  return true;
}

/// The first field describing the workspace itself that is set (not "", 0 or empty), or "" if none: a request naming
/// a workspace must leave them all unset.
std::string setRegionField(const VerifyWorkspace::Request& req) {
  if (!req.region_type.empty()) return "region_type";
  for (std::size_t k = 0; k < 3; ++k) {
    if (req.box_min[k] != 0.0) return idx("box_min", k);
    if (req.box_max[k] != 0.0) return idx("box_max", k);
  }
  if (req.center.x != 0.0 || req.center.y != 0.0 || req.center.z != 0.0) return "center";
  if (req.radius != 0.0) return "radius";
  if (req.z_min != 0.0) return "z_min";
  if (req.z_max != 0.0) return "z_max";
  if (!req.halfspace_normals.empty()) return "halfspace_normals";
  if (!req.halfspace_offsets.empty()) return "halfspace_offsets";
  const double angles[6] = {req.roll_min, req.roll_max, req.pitch_min, req.pitch_max, req.yaw_min, req.yaw_max};
  const char* const names[6] = {"roll_min", "roll_max", "pitch_min", "pitch_max", "yaw_min", "yaw_max"};
  for (int k = 0; k < 6; ++k) {
    if (angles[k] != 0.0) return names[k];
  }
  return "";
}

/// The workspace named by req.workspace (QueryDefaults::workspaces), in the base frame.
bool readNamedWorkspace(const VerifyWorkspace::Request& req, const std::string& base_frame,
                        const QueryDefaults& defaults, WorkspaceQuery& q, std::string& error) {
  std::string field = setRegionField(req);
  if (field.empty() && !req.pose_min.empty()) field = "pose_min";
  if (field.empty() && !req.pose_max.empty()) field = "pose_max";
  if (!field.empty()) {
    error = field + ": expected it unset (\"\", 0 or empty) with a named workspace (workspace \"" + req.workspace +
            "\"): a request gives its workspace either by name or by its fields";
    return false;
  }
  const auto it = defaults.workspaces.find(req.workspace);
  if (it == defaults.workspaces.end()) {
    std::string names;
    for (const auto& w : defaults.workspaces) names += (names.empty() ? "\"" : ", \"") + w.first + "\"";
    error = "workspace: expected " +
            (names.empty() ? std::string("\"\" (the robot has no named workspaces: parameter ~workspaces)")
                           : "one of the robot's named workspaces " + names + " or \"\"") +
            ", got \"" + req.workspace + "\"";
    return false;
  }
  if (it->second.has_frame) {
    error = "workspace: \"" + req.workspace +
            "\" is given in a frame of its own (its `frame` key), which the node does not verify; give the region "
            "by its fields with frame_id naming that frame in tf2";
    return false;
  }
  if (!req.frame_id.empty() && fields::frameName(req.frame_id) != fields::frameName(base_frame)) {
    error = "frame_id: expected \"\" or the base frame \"" + base_frame + "\" with a named workspace (workspace \"" +
            req.workspace + "\" is in the base frame), got \"" + req.frame_id + "\"";
    return false;
  }
  q.workspace = it->second.spec;
  q.pose_domain = it->second.domain;
  q.workspace_name = req.workspace;
  q.frame_id.clear();
  return true;
}

/// The robot's pose coordinates with their units, as ~describe's pose_components: "x [m]", ...
std::vector<std::string> poseNames(const QueryDefaults& defaults) {
  std::vector<std::string> names;
  for (const model::PoseComponent& c : defaults.pose) names.push_back(c.name + " [" + c.unit + "]");
  return names;
}

/// The workspace of a request by pose_min / pose_max: one finite range per pose coordinate of the robot. A rigid-body
/// robot's box becomes a box region with angle ranges (in frame_id); another robot's a domain::PoseBox of its own
/// coordinates (base frame only).
bool readPoseBox(const VerifyWorkspace::Request& req, const QueryDefaults& defaults, WorkspaceQuery& q,
                 std::string& error) {
  const std::string field = setRegionField(req);
  if (!field.empty()) {
    error = field + ": expected it unset (\"\", 0 or empty) with pose_min / pose_max: a request gives its workspace " +
            "by name, as a position region with angle ranges, or as a box of the pose coordinates";
    return false;
  }
  const std::vector<std::string> names = poseNames(defaults);
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  for (const auto& [values, name] :
       {std::make_pair(&req.pose_min, "pose_min"), std::make_pair(&req.pose_max, "pose_max")}) {
    if (values->size() == names.size()) continue;
    error = std::string(name) + ": expected " + std::to_string(names.size()) +
            " numbers, one per pose coordinate of robot type " + defaults.robot_type + " (" + list +
            ", ~describe's pose_components), got " + std::to_string(values->size());
    return false;
  }
  IVec box(static_cast<int>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const char* unit = defaults.pose[k].unit.c_str();
    if (!ordered(req.pose_min[k], req.pose_max[k], idx("pose_min", k), idx("pose_max", k), unit, error)) return false;
    box[static_cast<int>(k)] = Interval(req.pose_min[k], req.pose_max[k]);
  }
  if (!defaults.rigidBodyPose()) {
    if (!q.frame_id.empty()) {
      error = "frame_id: expected \"\" or the base frame with a robot of type " + defaults.robot_type + " (its pose (" +
              list + ") is in its own coordinates, which another frame does not transform), got \"" + req.frame_id +
              "\"";
      return false;
    }
    try {
      q.pose_domain = std::make_shared<domain::PoseBox>(names, box);
    } catch (const InvalidArgument& e) {
      error = std::string("pose_min, pose_max: ") + e.what();
      return false;
    }
    return true;
  }
  for (int k = 0; k < 3; ++k) {
    q.workspace.position.box_min[k] = req.pose_min[static_cast<std::size_t>(k)];
    q.workspace.position.box_max[k] = req.pose_max[static_cast<std::size_t>(k)];
  }
  for (std::size_t k = 3; k < 6; ++k) {
    for (const auto& [value, name] :
         {std::make_pair(req.pose_min[k], "pose_min"), std::make_pair(req.pose_max[k], "pose_max")}) {
      if (std::fabs(value) > domain::Workspace::kMaxAngle) {
        error = idx(name, k) + ": expected an angle within [-2 pi, 2 pi] (rad; angles are periodic, so such a range " +
                "covers every orientation), got " + num(value);
        return false;
      }
    }
    q.workspace.angle_min[static_cast<int>(k) - 3] = req.pose_min[k];
    q.workspace.angle_max[static_cast<int>(k) - 3] = req.pose_max[k];
  }
  return true;
}

/// A robot whose pose is not the rigid-body pose has no position region: the refusal of a request giving neither a
/// name nor pose_min / pose_max.
std::string noPoseWorkspace(const VerifyWorkspace::Request& req, const QueryDefaults& defaults) {
  std::string list;
  for (const std::string& n : poseNames(defaults)) list += (list.empty() ? "" : ", ") + n;
  const std::string field = setRegionField(req);
  return (field.empty() ? std::string("pose_min, pose_max") : field) + ": robot type " + defaults.robot_type +
         " has the pose (" + list + "), not the rigid-body pose of the region and angle fields: give its workspace " +
         "by name (workspace) or as a box of its pose coordinates (pose_min, pose_max)";
}

}  // namespace

bool fromRequest(const VerifyWorkspace::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error) {
  WorkspaceQuery q;
  q.frame_id = fields::frameId(req.frame_id, base_frame);
  if (!fields::mode(req.mode, q.mode, error)) return false;
  if (!req.workspace.empty()) {
    if (!readNamedWorkspace(req, base_frame, defaults, q, error)) return false;
  } else if (!req.pose_min.empty() || !req.pose_max.empty()) {
    if (!readPoseBox(req, defaults, q, error)) return false;
  } else if (!defaults.rigidBodyPose()) {
    error = noPoseWorkspace(req, defaults);
    return false;
  } else {
    if (!readRegion(req, q.workspace.position, error)) return false;
    const double angle_min[3] = {req.roll_min, req.pitch_min, req.yaw_min};
    const double angle_max[3] = {req.roll_max, req.pitch_max, req.yaw_max};
    const char* const names[3] = {"roll", "pitch", "yaw"};
    for (int k = 0; k < 3; ++k) {
      if (!ordered(angle_min[k], angle_max[k], std::string(names[k]) + "_min", std::string(names[k]) + "_max", "rad",
                   error)) {
        return false;
      }
      for (const auto& [value, field] : {std::make_pair(angle_min[k], std::string(names[k]) + "_min"),
                                         std::make_pair(angle_max[k], std::string(names[k]) + "_max")}) {
        if (std::fabs(value) > domain::Workspace::kMaxAngle) {
          error = field + ": expected an angle within [-2 pi, 2 pi] (rad; angles are periodic, so such a range " +
                  "covers every orientation), got " + num(value);
          return false;
        }
      }
      q.workspace.angle_min[k] = angle_min[k];
      q.workspace.angle_max[k] = angle_max[k];
    }
  }

  if (!fields::sharedOptions(req, defaults, q, error)) return false;
  if (!option(req.min_width, defaults.min_width, "min_width", "a finite number >= 0 (m / rad, 0 = default)",
              q.min_width, error)) {
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
  for (std::size_t k = 0; k < 6; ++k) {
    res.undecided_min[k] = o.undecided_min[k];
    res.undecided_max[k] = o.undecided_max[k];
  }
  res.lower_bound_poses = o.lower_bound_poses;
  res.outside_fraction = o.outside_fraction;
  for (std::size_t k = 0; k < 6; ++k) {
    res.sensitive_region_min[k] = o.sensitive.region.lo[k];
    res.sensitive_region_max[k] = o.sensitive.region.hi[k];
  }
}

}  // namespace

void toResponse(const WorkspaceOutcome& o, VerifyWorkspace::Response& res) { fillResponse(o, res); }

void toResult(const WorkspaceOutcome& o, VerifyWorkspaceResult& result) { fillResponse(o, result); }

VerifyWorkspace::Request toRequest(const VerifyWorkspaceGoal& g) {
  VerifyWorkspace::Request r;
  r.workspace = g.workspace;
  r.region_type = g.region_type;
  r.box_min = g.box_min;
  r.box_max = g.box_max;
  r.center = g.center;
  r.radius = g.radius;
  r.z_min = g.z_min;
  r.z_max = g.z_max;
  r.halfspace_normals = g.halfspace_normals;
  r.halfspace_offsets = g.halfspace_offsets;
  r.roll_min = g.roll_min;
  r.roll_max = g.roll_max;
  r.pitch_min = g.pitch_min;
  r.pitch_max = g.pitch_max;
  r.yaw_min = g.yaw_min;
  r.yaw_max = g.yaw_max;
  r.pose_min = g.pose_min;
  r.pose_max = g.pose_max;
  fields::copyOptions(g, r);
  return r;
}

std::string toString(const PositionRegion::Type type) {
  switch (type) {
    case PositionRegion::Type::Box:
      return VerifyWorkspace::Request::REGION_BOX;
    case PositionRegion::Type::Cylinder:
      return VerifyWorkspace::Request::REGION_CYLINDER;
    case PositionRegion::Type::Sphere:
      return VerifyWorkspace::Request::REGION_SPHERE;
    case PositionRegion::Type::Polyhedron:
      return VerifyWorkspace::Request::REGION_POLYHEDRON;
  }
  return "";
}

void toResultMessage(const WorkspaceQuery& q, const std::string& method, const WorkspaceOutcome& o,
                     VerificationResult& msg) {
  msg.job_id = o.job_id;
  msg.mode =
      q.mode == QueryMode::MaxError ? VerifyWorkspace::Request::MODE_MAX_ERROR : VerifyWorkspace::Request::MODE_VERIFY;
  msg.method = method;
  msg.workspace = q.workspace_name;
  if (q.domain == QueryDomain::Variety) {
    // /verify_variety: region_type "variety", workspace_min / max = an enclosure of all its poses (the interval
    // evaluation of its polynomials over [0, 1]^m).
    msg.region_type = "variety";
    const auto variety = toVariety(q.variety);
    enclosure::BoxInput view;
    variety->poseView(variety->initialBox(), /*gradient=*/false, view);
    for (std::size_t k = 0; k < 6 && static_cast<int>(k) < view.pose.size(); ++k) {
      msg.workspace_min[k] = view.pose[static_cast<int>(k)].lower();
      msg.workspace_max[k] = view.pose[static_cast<int>(k)].upper();
    }
  } else if (q.domain == QueryDomain::Trajectory) {
    // /verify_trajectory: region_type "trajectory", workspace_min / max = the bounding box of its waypoints.
    msg.region_type = "trajectory";
    const auto& poses = q.trajectory.poses;
    for (std::size_t k = 0; k < 6; ++k) {
      msg.workspace_min[k] = poses.empty() ? 0.0 : poses.front()[k];
      msg.workspace_max[k] = msg.workspace_min[k];
      for (const auto& p : poses) {
        msg.workspace_min[k] = std::min(msg.workspace_min[k], p[k]);
        msg.workspace_max[k] = std::max(msg.workspace_max[k], p[k]);
      }
    }
  } else if (q.pose_domain) {
    // A robot's own pose coordinates: region_type "pose_box", workspace_min / max = the domain's box of them.
    msg.region_type = "pose_box";
    const IVec& box = q.pose_domain->initialBox();
    for (int k = 0; k < 6 && k < box.size(); ++k) {
      msg.workspace_min[static_cast<std::size_t>(k)] = box[k].lower();
      msg.workspace_max[static_cast<std::size_t>(k)] = box[k].upper();
    }
  } else {
    msg.region_type = toString(q.workspace.position.type);
    Eigen::Vector3d lo, hi;
    q.workspace.position.boundingBox(lo, hi);
    for (int k = 0; k < 3; ++k) {
      msg.workspace_min[k] = lo[k];
      msg.workspace_max[k] = hi[k];
      msg.workspace_min[3 + k] = q.workspace.angle_min[k];
      msg.workspace_max[3 + k] = q.workspace.angle_max[k];
    }
  }
  for (std::size_t k = 0; k < 6; ++k) msg.thresholds[k] = q.has_thresholds ? q.thresholds[k] : 0.0;
  msg.alpha = q.alpha;
  msg.time_budget = q.time_budget;
  msg.min_width = q.min_width;
  msg.threads_requested = q.threads;
  msg.geometry_splitting = q.geometry_splitting;

  fields::fillCommonResponse(o, msg);
  for (std::size_t k = 0; k < 6; ++k) {
    msg.undecided_min[k] = o.undecided_min[k];
    msg.undecided_max[k] = o.undecided_max[k];
  }
  msg.lower_bound_poses = o.lower_bound_poses;
  msg.outside_fraction = o.outside_fraction;
  if (q.domain == QueryDomain::Workspace) {
    for (std::size_t k = 0; k < 6; ++k) {
      msg.sensitive_region_min[k] = o.sensitive.region.lo[k];
      msg.sensitive_region_max[k] = o.sensitive.region.hi[k];
    }
  }
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
