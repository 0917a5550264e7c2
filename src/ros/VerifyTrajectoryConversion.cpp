#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"

#include "RequestFields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <vector>

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
    error = "times: expected at least 2 waypoints (one time each, s), or polynomial_segments instead, got " +
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
  const std::vector<double>* waypointArrays[7] = {&req.times, &req.x, &req.y, &req.z, &req.roll, &req.pitch, &req.yaw};
  const char* const waypointNames[7] = {"times", "x", "y", "z", "roll", "pitch", "yaw"};
  for (std::size_t k = 0; k < 7; ++k) {
    if (!waypointArrays[k]->empty()) {
      error = std::string(
                  "polynomial_segments: expected the waypoint arrays to be empty with polynomial segments (one "
                  "form of trajectory per request), got ") +
              std::to_string(waypointArrays[k]->size()) + " values in " + waypointNames[k];
      return false;
    }
  }
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

}  // namespace

bool fromRequest(const VerifyTrajectory::Request& req, const std::string& base_frame, const QueryDefaults& defaults,
                 WorkspaceQuery& out, std::string& error) {
  WorkspaceQuery q;
  q.domain = QueryDomain::Trajectory;
  // Another frame is looked up in tf2 by the node when the job starts (an unknown one is refused then).
  q.frame_id = fields::frameId(req.frame_id, base_frame);
  if (!fields::mode(req.mode, q.mode, error)) return false;
  if (req.polynomial_segments.empty() ? !readWaypoints(req, q.trajectory, error)
                                      : !readPolynomialSegments(req, q.trajectory, error)) {
    return false;
  }
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
  fields::copyOptions(g, r);
  return r;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
