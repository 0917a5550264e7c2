#include "pkm_accuracy/ros/CoreBridge.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

domain::PositionRegion toRegion(const PositionRegion& r) {
  switch (r.type) {
    case PositionRegion::Type::Box:
      return domain::PositionRegion::box(r.box_min, r.box_max);
    case PositionRegion::Type::Cylinder:
      return domain::PositionRegion::cylinder(r.center.x(), r.center.y(), r.radius, r.z_min, r.z_max);
    case PositionRegion::Type::Sphere:
      return domain::PositionRegion::sphere(r.center, r.radius);
    case PositionRegion::Type::Polyhedron:
      return domain::PositionRegion::polyhedron(r.halfspace_normals, r.halfspace_offsets, r.box_min, r.box_max);
  }
  return domain::PositionRegion::box(r.box_min, r.box_max);
}

Box6 toBox6(const IVec& b) {
  Box6 box;
  for (int i = 0; i < 6 && i < b.size(); ++i) {
    box.lo[static_cast<std::size_t>(i)] = b[i].lower();
    box.hi[static_cast<std::size_t>(i)] = b[i].upper();
  }
  return box;
}

void copy6(const DVec& v, std::array<double, 6>& out) {
  for (int k = 0; k < 6 && k < v.size(); ++k) out[static_cast<std::size_t>(k)] = v[k];
}

void append(const DVec& v, std::vector<double>& out) {
  for (int i = 0; i < v.size(); ++i) out.push_back(v[i]);
}

/// The domain of a query in its own frame (no transform).
std::unique_ptr<domain::Domain> inOwnFrame(const WorkspaceQuery& query) {
  switch (query.domain) {
    case QueryDomain::Trajectory:
      return toTrajectory(query.trajectory);
    case QueryDomain::Variety:
      return toVariety(query.variety);
    case QueryDomain::Workspace:
      break;
  }
  return std::make_unique<domain::Workspace>(toWorkspace(query.workspace));
}

}  // namespace

domain::Workspace toWorkspace(const WorkspaceSpec& spec) {
  std::array<Interval, 3> angles;
  for (int k = 0; k < 3; ++k) angles[k] = Interval(spec.angle_min[k], spec.angle_max[k]);
  return domain::Workspace(toRegion(spec.position), angles);
}

std::unique_ptr<domain::PiecewiseTrajectory> toTrajectory(const TrajectorySpec& spec) {
  if (!spec.segments.empty()) return std::make_unique<domain::PolynomialTrajectory>(spec.segments);
  std::vector<domain::WaypointTrajectory::Waypoint> waypoints(spec.times.size());
  for (std::size_t i = 0; i < waypoints.size() && i < spec.poses.size(); ++i) {
    waypoints[i].t = spec.times[i];
    waypoints[i].pose = spec.poses[i];
  }
  return std::make_unique<domain::WaypointTrajectory>(
      std::move(waypoints), spec.slerp ? domain::WaypointTrajectory::Interpolation::Slerp
                                       : domain::WaypointTrajectory::Interpolation::LinearRpy);
}

std::unique_ptr<domain::ParametricVariety> toVariety(const VarietySpec& spec) {
  return std::make_unique<domain::ParametricVariety>(spec.parameters, spec.coordinates);
}

std::shared_ptr<const domain::Domain> toDomain(const WorkspaceQuery& query) {
  if (query.domain == QueryDomain::Workspace && query.pose_domain) {
    if (query.has_transform)
      throw InvalidArgument("frame_id \"" + query.frame_id + "\": the robot's own pose coordinates");
    return query.pose_domain;
  }
  std::unique_ptr<domain::Domain> inFrame = inOwnFrame(query);
  if (!query.has_transform) return inFrame;
  domain::RigidTransform t;
  t.rotation = query.rotation;
  t.translation = query.translation;
  try {
    return std::make_unique<domain::TransformedDomain>(std::move(inFrame), t);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument("frame_id \"" + query.frame_id + "\": " + e.what());
  }
}

verify::VerifierOptions toVerifierOptions(const WorkspaceQuery& q, const JobHooks& hooks) {
  verify::VerifierOptions o;
  o.mode = q.mode == QueryMode::MaxError ? verify::Mode::MaxError : verify::Mode::Verify;
  if (q.has_thresholds) {
    o.thresholds = DVec(q.components);
    for (int k = 0; k < q.components; ++k) {
      const double t = q.thresholds[static_cast<std::size_t>(k)];
      o.thresholds[k] = t == kInf ? std::numeric_limits<double>::max() : t;
    }
  }
  o.alpha = q.alpha;
  o.alpha_relative = true;
  if (!q.method.empty()) o.method = q.method;
  if (q.min_width > 0.0) {
    if (q.domain == QueryDomain::Trajectory) {
      // One variable u in [0, 1] over the time span: a minimum duration (s) is that fraction of the span.
      const double span = q.trajectory.times.empty() ? 0.0 : q.trajectory.times.back() - q.trajectory.times.front();
      if (span > 0.0) o.min_width = DVec::Constant(1, q.min_width / span);
    } else if (q.domain == QueryDomain::Variety) {
      o.min_width = DVec::Constant(q.variety.parameters, q.min_width);  // the parameters themselves
    } else {
      o.min_width = DVec::Constant(q.pose_domain ? q.pose_domain->variables() : 6, q.min_width);
    }
  }
  o.time_limit_s = q.time_budget;
  o.threads = static_cast<int>(q.threads);
  if (q.geometry_splitting == "never") {
    o.geometry_splitting = verify::GeometrySplitting::Never;
  } else if (q.geometry_splitting == "always") {
    o.geometry_splitting = verify::GeometrySplitting::Always;
  } else {
    o.geometry_splitting = verify::GeometrySplitting::Auto;
  }
  if (q.domain == QueryDomain::Workspace) o.max_recorded_safe_boxes = q.record_safe_boxes;
  o.cancel = hooks.cancel;
  o.progress = hooks.progress;
  o.progress_period_s = hooks.progress_period_s;
  return o;
}

WorkspaceOutcome toOutcome(const verify::VerifierResult& r, const WorkspaceQuery& q, const model::RobotModel& model) {
  WorkspaceOutcome out;
  out.success = true;
  out.rigid_body_pose = q.rigid_body_pose;
  out.message = r.message;
  out.verdict = verify::toString(r.verdict);
  out.reason = r.verdict == verify::Verdict::Undecided ? verify::toString(r.reason) : "";

  // Bounds on the maximal errors: the verifier's enclosure in max_error mode; in verify mode only what the verdict
  // itself proves (documented in srv/VerifyWorkspace.srv). A robot's n components come first, then zeros.
  const int n = q.components;
  const auto N = static_cast<std::size_t>(n);
  out.lower_bound.fill(0.0);
  out.upper_bound.fill(0.0);
  for (std::size_t k = 0; k < N && k < 6; ++k) out.upper_bound[k] = kInf;

  // The pose at a point of the box variables, for the response: a workspace's variables are its poses in the
  // query's frame; a trajectory's or variety's pose is the midpoint of the verifier's certified enclosure of the
  // base-frame pose there (`basePose`), or, in another frame or where the verifier gives none, of the domain's own
  // pose (in the query's frame).
  const bool workspace = q.domain == QueryDomain::Workspace;
  const int variables = workspace                             ? (q.pose_domain ? q.pose_domain->variables() : 6)
                        : q.domain == QueryDomain::Trajectory ? 1
                                                              : q.variety.parameters;
  const std::unique_ptr<domain::Domain> own = workspace ? nullptr : inOwnFrame(q);
  const auto poseAt = [&](const DVec& point, const IVec& basePose) {
    std::array<double, 6> out{};
    if (workspace) {
      copy6(point, out);
      return out;
    }
    const IVec pose = q.has_transform || basePose.size() != 6 ? own->poseAt(point) : basePose;
    for (int k = 0; k < 6 && k < pose.size(); ++k) out[static_cast<std::size_t>(k)] = pose[k].mid();
    return out;
  };

  if (q.mode == QueryMode::MaxError) {
    copy6(r.max_lower, out.lower_bound);
    copy6(r.max_upper, out.upper_bound);
    out.converged = r.converged;
    if (q.domain == QueryDomain::Trajectory) {
      // The argmax times and the trajectory's poses there (the start where the verifier gives no time).
      out.lower_bound_times.assign(6, q.trajectory.timeOf(0.0));
      out.lower_bound_poses.assign(36, 0.0);
      for (std::size_t k = 0; k < 6; ++k) {
        DVec u = DVec::Zero(1);
        if (k < r.max_argmax.size() && r.max_argmax[k].size() >= 1) u[0] = r.max_argmax[k][0];
        out.lower_bound_times[k] = q.trajectory.timeOf(u[0]);
        const std::array<double, 6> pose = poseAt(u, IVec());
        for (std::size_t i = 0; i < 6; ++i) out.lower_bound_poses[6 * k + i] = pose[i];
      }
    } else {
      // Workspace: the argmax poses; variety: the argmax parameter points and their poses (the verifier gives the
      // points only: the pose is the domain's there).
      const auto m = static_cast<std::size_t>(variables);
      out.lower_bound_poses.assign(36, 0.0);
      if (!workspace) out.lower_bound_parameters.assign(6 * m, 0.0);
      for (std::size_t k = 0; k < 6 && k < r.max_argmax.size(); ++k) {
        const DVec& p = r.max_argmax[k];
        if (p.size() != variables) continue;
        const std::array<double, 6> pose = poseAt(p, IVec());  // (the verifier gives no pose here)
        for (std::size_t i = 0; i < 6; ++i) out.lower_bound_poses[6 * k + i] = pose[i];
        for (std::size_t i = 0; i < m && !workspace; ++i) {
          out.lower_bound_parameters[m * k + i] = p[static_cast<int>(i)];
        }
      }
    }
    // With uncertain geometry: the geometry attaining each lower bound. A component whose bound holds for every
    // geometry (the verifier leaves its row empty) is attained by any: the centre geometry is reported.
    const int params = model.geometryParameterCount();
    if (params > 0 && r.max_argmax_geometry.size() == N) {
      const auto P = static_cast<std::size_t>(params);
      out.lower_bound_geometries.assign(6 * P, 0.0);
      for (std::size_t k = 0; k < N && k < 6; ++k) {
        const std::vector<double>& g = r.max_argmax_geometry[k];
        for (std::size_t p = 0; p < P; ++p) {
          out.lower_bound_geometries[P * k + p] =
              g.size() == P ? g[p] : model.geometryParameterCentre(static_cast<int>(p));
        }
      }
    }
  } else {
    if (r.verdict == verify::Verdict::Safe) out.upper_bound = q.thresholds;
    if (r.witness_error_lower.size() == n) copy6(r.witness_error_lower, out.lower_bound);
  }

  const bool witness = r.witness.size() == variables && (workspace || r.witness_pose.size() == 6);
  if (r.verdict == verify::Verdict::Unsafe && witness && r.witness_component >= 0) {
    out.has_witness = true;
    out.witness_pose = poseAt(r.witness, r.witness_pose);
    if (q.domain == QueryDomain::Trajectory) out.witness_t = q.trajectory.timeOf(r.witness[0]);  // the variable is u
    if (q.domain == QueryDomain::Variety) append(r.witness, out.witness_parameters);
    out.witness_component = r.witness_component;
    if (r.witness_error_lower.size() == n) {
      copy6(r.witness_error_lower, out.witness_error);
    } else {
      IVec f;
      if (enclosure::errorAtPose(model, r.witness_pose, f) && f.size() == n) {
        for (int k = 0; k < n && k < 6; ++k) out.witness_error[static_cast<std::size_t>(k)] = f[k].lower();
      }
    }
    auto& e = out.witness_error[static_cast<std::size_t>(r.witness_component)];
    e = std::max(e, r.witness_lower_bound);
  }

  if (r.singular && r.singular_pose_from.size() == n && r.singular_pose_to.size() == n) {
    out.singular = true;
    // (Like the witness, through poseAt(); the certified base-frame poses where the points are missing.)
    const bool points = r.singular_from.size() == variables && r.singular_to.size() == variables;
    std::array<double, 6> from{}, to{};
    for (int i = 0; i < n && i < 6; ++i) {
      from[static_cast<std::size_t>(i)] = r.singular_pose_from[i].mid();
      to[static_cast<std::size_t>(i)] = r.singular_pose_to[i].mid();
    }
    if (points) {
      from = poseAt(r.singular_from, r.singular_pose_from);
      to = poseAt(r.singular_to, r.singular_pose_to);
      if (q.domain == QueryDomain::Trajectory) {
        out.singular_t[0] = q.trajectory.timeOf(r.singular_from[0]);
        out.singular_t[1] = q.trajectory.timeOf(r.singular_to[0]);
      }
      if (q.domain == QueryDomain::Variety) {
        append(r.singular_from, out.singular_parameters);
        append(r.singular_to, out.singular_parameters);
      }
    }
    for (std::size_t k = 0; k < 6; ++k) {
      out.singular_poses[k] = from[k];
      out.singular_poses[k + 6] = to[k];
    }
  }

  out.boxes = r.stats.boxes;
  out.max_depth = static_cast<unsigned>(std::max(0, r.stats.max_depth));
  out.threads = static_cast<unsigned>(std::max(0, r.stats.threads));
  out.seconds = r.stats.seconds;
  out.safe_fraction = r.stats.safe_fraction;
  out.unsafe_fraction = r.stats.unsafe_fraction;
  out.undecided_fraction = r.stats.undecided_fraction;
  out.outside_fraction = r.stats.outside_fraction;

  // Geometric uncertainty: the statistics and the first uncertainty-sensitive pose.
  out.geometry_switches = r.stats.geometry_switches;
  out.geometry_splits = r.stats.geometry_splits;
  out.face_switches = r.stats.face_switches;
  out.face_boxes = r.stats.face_boxes;
  out.unenclosed_boxes = r.stats.unenclosed_boxes;
  out.sensitive_poses = r.sensitive_count;
  if (!r.sensitive.empty()) {
    const verify::SensitivePose& p = r.sensitive.front();
    SensitiveSummary& s = out.sensitive;
    s.component = p.component;
    s.failing_lower = p.failing_lower;
    s.failing_geometry = p.failing_geometry;
    s.passing_geometry = p.passing_geometry;
    s.passing_upper = p.passing_geometry.empty() ? 0.0 : p.passing_upper;
    s.passes_all = !p.passing_geometry.empty() && p.passes_all;
    if (!workspace) {
      // As the witness.
      if (p.point.size() == variables) {
        s.pose = poseAt(p.point, p.pose);
        if (q.domain == QueryDomain::Trajectory) s.t = q.trajectory.timeOf(p.point[0]);
        if (q.domain == QueryDomain::Variety) append(p.point, s.parameters);
      } else {
        for (int k = 0; k < 6 && k < p.pose.size(); ++k) s.pose[static_cast<std::size_t>(k)] = p.pose[k].mid();
      }
      if (p.region.size() == variables && !p.region[0].isEmpty()) {
        if (q.domain == QueryDomain::Trajectory) {
          s.t_start = q.trajectory.timeOf(p.region[0].lower());
          s.t_end = q.trajectory.timeOf(p.region[0].upper());
        } else {
          for (int i = 0; i < variables; ++i) {
            s.region_lower.push_back(p.region[i].lower());
            s.region_upper.push_back(p.region[i].upper());
          }
        }
      }
    } else {
      // The workspace's variables (in the query's frame), as the witness and the undecided boxes.
      copy6(p.point, s.pose);
      for (int i = 0; i < 6 && i < p.region.size(); ++i) {
        s.region.lo[static_cast<std::size_t>(i)] = p.region[i].lower();
        s.region.hi[static_cast<std::size_t>(i)] = p.region[i].upper();
      }
    }
  }

  out.undecided_boxes = r.undecided_box_count;
  out.undecided_boxes_recorded = r.undecided_boxes.size();
  out.undecided_min.fill(0.0);
  out.undecided_max.fill(0.0);
  bool first = true;
  out.undecided_recorded.reserve(r.undecided_boxes.size());
  if (q.domain == QueryDomain::Variety) {
    // The parameter boxes themselves.
    for (const verify::BoxRecord& b : r.undecided_boxes) {
      if (b.box.size() != variables) continue;
      for (int i = 0; i < variables; ++i) {
        out.undecided_parameters_lower.push_back(b.box[i].lower());
        out.undecided_parameters_upper.push_back(b.box[i].upper());
      }
    }
    return out;
  }
  if (q.domain == QueryDomain::Trajectory) {
    // One variable (u): the undecided boxes as time intervals, sorted and merged (as pkm_verify's undecided_t).
    for (const verify::BoxRecord& b : r.undecided_boxes) {
      if (b.box.size() < 1 || b.box[0].isEmpty()) continue;
      out.undecided_times.emplace_back(q.trajectory.timeOf(b.box[0].lower()), q.trajectory.timeOf(b.box[0].upper()));
    }
    std::sort(out.undecided_times.begin(), out.undecided_times.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& iv : out.undecided_times) {
      if (!merged.empty() && iv.first <= merged.back().second) {
        merged.back().second = std::max(merged.back().second, iv.second);
      } else {
        merged.push_back(iv);
      }
    }
    out.undecided_times = std::move(merged);
    return out;
  }
  for (const verify::BoxRecord& b : r.safe_boxes) out.safe_recorded.push_back(toBox6(b.box));
  for (const verify::BoxRecord& b : r.undecided_boxes) {
    out.undecided_recorded.push_back(toBox6(b.box));
    for (int i = 0; i < 6 && i < b.box.size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      out.undecided_min[k] = first ? b.box[i].lower() : std::min(out.undecided_min[k], b.box[i].lower());
      out.undecided_max[k] = first ? b.box[i].upper() : std::max(out.undecided_max[k], b.box[i].upper());
    }
    first = false;
  }
  return out;
}

WorkspaceOutcome runWorkspaceQuery(const model::RobotModel& model, const WorkspaceQuery& query, const JobHooks& hooks) {
  const std::shared_ptr<const domain::Domain> domain = toDomain(query);
  const verify::VerifierOptions options = toVerifierOptions(query, hooks);
  const verify::VerifierResult result = verify::Verifier::run(model, *domain, options);
  return toOutcome(result, query, model);
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
