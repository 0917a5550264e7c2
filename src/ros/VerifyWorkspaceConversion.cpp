#include "pkm_accuracy/ros/VerifyWorkspaceConversion.hpp"

#include <cmath>
#include <sstream>

namespace pkm_accuracy {
namespace ros_layer {
namespace {

const char* const kComponent[6] = {"dx", "dy", "dz", "drx", "dry", "drz"};

std::string num(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

std::string idx(const char* field, std::size_t i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

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

/// An option where 0 means "default": finite, >= 0 (and < upper if given).
bool option(double x, double dflt, const char* field, const char* expected, double upper, double& out,
            std::string& error) {
  if (!std::isfinite(x) || x < 0.0 || !(x < upper)) {
    error = std::string(field) + ": expected " + expected + ", got " + num(x);
    return false;
  }
  out = x == 0.0 ? dflt : x;
  return true;
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
    error = "region_type: expected one of \"box\", \"cylinder\", \"sphere\", \"polyhedron\", got \"" + req.region_type +
            "\"";
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
  }
  return true;
}

}  // namespace

bool fromRequest(const VerifyWorkspace::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error) {
  WorkspaceQuery q;
  if (!req.frame_id.empty() && req.frame_id != base_frame) {
    error = "frame_id: expected \"\" or the robot's base frame \"" + base_frame + "\", got \"" + req.frame_id + "\"";
    return false;
  }
  if (req.mode.empty() || req.mode == VerifyWorkspace::Request::MODE_VERIFY) {
    q.mode = QueryMode::Verify;
  } else if (req.mode == VerifyWorkspace::Request::MODE_MAX_ERROR) {
    q.mode = QueryMode::MaxError;
  } else {
    error = "mode: expected \"verify\", \"max_error\" or \"\" (verify), got \"" + req.mode + "\"";
    return false;
  }
  if (!readRegion(req, q.workspace.position, error)) return false;

  const double angle_min[3] = {req.roll_min, req.pitch_min, req.yaw_min};
  const double angle_max[3] = {req.roll_max, req.pitch_max, req.yaw_max};
  const char* const names[3] = {"roll", "pitch", "yaw"};
  for (int k = 0; k < 3; ++k) {
    if (!ordered(angle_min[k], angle_max[k], std::string(names[k]) + "_min", std::string(names[k]) + "_max", "rad",
                 error)) {
      return false;
    }
    q.workspace.angle_min[k] = angle_min[k];
    q.workspace.angle_max[k] = angle_max[k];
  }

  bool all_zero = true;
  for (double t : req.thresholds) all_zero = all_zero && t == 0.0;
  q.has_thresholds = !(q.mode == QueryMode::MaxError && all_zero);
  if (q.has_thresholds) {
    for (std::size_t k = 0; k < 6; ++k) {
      const double t = req.thresholds[k];
      if (!(t > 0.0)) {  // also rejects NaN; +inf is allowed
        error = idx("thresholds", k) + " (" + kComponent[k] + "): expected a number > 0 (" + (k < 3 ? "m" : "rad") +
                ") or .inf" + (q.mode == QueryMode::MaxError ? " (or all 0 in mode max_error)" : "") + ", got " +
                num(t);
        return false;
      }
      q.thresholds[k] = t;
    }
  }

  if (!option(req.alpha, defaults.alpha, "alpha", "a finite number >= 0 (relative, 0 = default)", HUGE_VAL, q.alpha,
              error) ||
      !option(req.time_budget, defaults.time_budget, "time_budget", "a finite number >= 0 (s, 0 = default)", HUGE_VAL,
              q.time_budget, error) ||
      !option(req.min_width, defaults.min_width, "min_width", "a finite number >= 0 (m / rad, 0 = default)", HUGE_VAL,
              q.min_width, error)) {
    return false;
  }
  q.threads = req.threads;
  out = q;
  return true;
}

void toResponse(const WorkspaceOutcome& o, VerifyWorkspace::Response& res) {
  res.success = o.success;
  res.message = o.message;
  res.verdict = o.verdict;
  for (std::size_t k = 0; k < 6; ++k) {
    res.lower_bound[k] = o.lower_bound[k];
    res.upper_bound[k] = o.upper_bound[k];
    res.witness_pose[k] = o.witness_pose[k];
    res.witness_error[k] = o.witness_error[k];
  }
  res.has_witness = o.has_witness;
  res.boxes = o.boxes;
  res.seconds = o.seconds;
  res.safe_fraction = o.safe_fraction;
  res.unsafe_fraction = o.unsafe_fraction;
  res.undecided_fraction = o.undecided_fraction;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
