#include "pkm_accuracy/ros/BoxMarkers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "pkm_accuracy/ros/CoreBridge.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

std_msgs::ColorRGBA color(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

/// Places markers given in the query's frame into the base frame.
class Placement {
 public:
  explicit Placement(const WorkspaceQuery& q)
      : rotation_(q.has_transform ? q.rotation : Eigen::Matrix3d::Identity()),
        translation_(q.has_transform ? q.translation : Eigen::Vector3d::Zero()),
        orientation_(Eigen::Quaterniond(rotation_).normalized()) {}

  /// Sets the marker's pose: origin at `centre` (query frame), axes of the query frame.
  void place(visualization_msgs::Marker& m, const Eigen::Vector3d& centre) const {
    m.pose.position = point(translation_ + rotation_ * centre);
    m.pose.orientation.w = orientation_.w();
    m.pose.orientation.x = orientation_.x();
    m.pose.orientation.y = orientation_.y();
    m.pose.orientation.z = orientation_.z();
  }

  /// Sets a CUBE marker to the position projection of a box (query frame), no thinner than `thin` (m).
  void placeBox(visualization_msgs::Marker& m, const Box6& b, double thin) const {
    place(m, Eigen::Vector3d(0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])));
    m.scale.x = std::max(b.hi[0] - b.lo[0], thin);
    m.scale.y = std::max(b.hi[1] - b.lo[1], thin);
    m.scale.z = std::max(b.hi[2] - b.lo[2], thin);
  }

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d translation_;
  Eigen::Quaterniond orientation_;
};

visualization_msgs::Marker newMarker(const std::string& frame, const ros::Time& stamp, const char* ns, int id,
                                     int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  return m;
}

/// Clears the previous job's markers.
visualization_msgs::Marker deleteAll(const std::string& frame, const ros::Time& stamp) {
  visualization_msgs::Marker clear;
  clear.header.frame_id = frame;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  clear.pose.orientation.w = 1.0;
  return clear;
}

/// The witness, the singular segment and the first uncertainty-sensitive pose (with its search box when
/// `sensitiveRegion`), sized by `unit` (m).
void addPoseMarkers(const WorkspaceOutcome& o, const Placement& placement, const std::string& frame,
                    const ros::Time& stamp, double unit, bool sensitiveRegion, visualization_msgs::MarkerArray& array) {
  const double thin = 1e-3 * unit;
  if (o.has_witness) {
    visualization_msgs::Marker m = newMarker(frame, stamp, kMarkerNsWitness, 0, visualization_msgs::Marker::SPHERE);
    placement.place(m, Eigen::Vector3d(o.witness_pose[0], o.witness_pose[1], o.witness_pose[2]));
    m.scale.x = m.scale.y = m.scale.z = 0.04 * unit;
    m.color = color(1.0f, 0.0f, 0.0f, 1.0f);
    array.markers.push_back(m);
  }

  // A certified singular pose: the segment it lies on (the positions of its two ends; query frame).
  if (o.singular) {
    visualization_msgs::Marker m = newMarker(frame, stamp, kMarkerNsSingular, 0, visualization_msgs::Marker::LINE_LIST);
    const Eigen::Vector3d from(o.singular_poses[0], o.singular_poses[1], o.singular_poses[2]);
    const Eigen::Vector3d to(o.singular_poses[6], o.singular_poses[7], o.singular_poses[8]);
    placement.place(m, from);
    m.scale.x = 6e-3 * unit;
    m.color = color(1.0f, 0.0f, 0.6f, 1.0f);
    m.points.push_back(point(Eigen::Vector3d::Zero()));
    m.points.push_back(point(to - from));
    array.markers.push_back(m);
  }

  // The first uncertainty-sensitive pose and its region (the search box it was found in).
  if (o.sensitive_poses > 0 && o.sensitive.component >= 0) {
    const SensitiveSummary& sp = o.sensitive;
    visualization_msgs::Marker m = newMarker(frame, stamp, kMarkerNsSensitive, 0, visualization_msgs::Marker::SPHERE);
    placement.place(m, Eigen::Vector3d(sp.pose[0], sp.pose[1], sp.pose[2]));
    m.scale.x = m.scale.y = m.scale.z = 0.04 * unit;
    m.color = color(1.0f, 0.9f, 0.0f, 1.0f);
    array.markers.push_back(m);
    if (sensitiveRegion) {
      visualization_msgs::Marker r = newMarker(frame, stamp, kMarkerNsSensitive, 1, visualization_msgs::Marker::CUBE);
      placement.placeBox(r, sp.region, thin);
      r.color = color(1.0f, 0.9f, 0.0f, 0.35f);
      array.markers.push_back(r);
    }
  }
}

/// The verdict as a text at `where` (query frame).
void addLabel(const WorkspaceOutcome& o, const Placement& placement, const std::string& frame, const ros::Time& stamp,
              const Eigen::Vector3d& where, double unit, const char* what, visualization_msgs::MarkerArray& array) {
  visualization_msgs::Marker m =
      newMarker(frame, stamp, kMarkerNsLabel, 0, visualization_msgs::Marker::TEXT_VIEW_FACING);
  placement.place(m, where);
  m.scale.z = 0.06 * unit;
  m.color = color(1.0f, 1.0f, 1.0f, 1.0f);
  char text[160];
  std::snprintf(text, sizeof(text), "job %llu: %s%s%s, %llu undecided %s", static_cast<unsigned long long>(o.job_id),
                o.success ? o.verdict.c_str() : "failed", o.reason.empty() ? "" : " ", o.reason.c_str(),
                static_cast<unsigned long long>(o.undecided_boxes), what);
  m.text = text;
  array.markers.push_back(m);
}

/// A LINE_LIST drawn piece by piece (positions in the query's frame), each piece coloured by what the verifier reports
/// about it: orange where it meets a recorded undecided box, green where every other point is proven within the
/// thresholds (`proven`), blue otherwise.
class ColouredLines {
 public:
  ColouredLines(const WorkspaceQuery& q, const WorkspaceOutcome& o, const std::string& frame, const ros::Time& stamp,
                const char* ns)
      : marker_(newMarker(frame, stamp, ns, 0, visualization_msgs::Marker::LINE_LIST)),
        proven_(q.mode == QueryMode::Verify && o.success && !o.has_witness && o.verdict != "UNSAFE" &&
                o.undecided_boxes_recorded == o.undecided_boxes) {}

  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool undecided) {
    marker_.points.push_back(point(a));
    marker_.points.push_back(point(b));
    lo_ = lo_.cwiseMin(a).cwiseMin(b);
    hi_ = hi_.cwiseMax(a).cwiseMax(b);
    const std_msgs::ColorRGBA c = undecided ? color(1.0f, 0.55f, 0.0f, 1.0f)
                                  : proven_ ? color(0.1f, 0.8f, 0.2f, 1.0f)
                                            : color(0.2f, 0.6f, 1.0f, 1.0f);
    marker_.colors.push_back(c);
    marker_.colors.push_back(c);
  }

  /// Appends the lines (`width` times the drawing's size), then the witness, singular and sensitive markers and the
  /// label above them (`boxes`: what the label counts, e.g. "time interval(s)").
  void finish(const WorkspaceOutcome& o, const Placement& placement, double width, const char* boxes,
              visualization_msgs::MarkerArray& array) {
    const Eigen::Vector3d size = hi_ - lo_, centre = 0.5 * (lo_ + hi_);
    const double unit = std::max(size.norm(), 1e-3);  // scale of the drawing (m)
    placement.place(marker_, Eigen::Vector3d::Zero());
    marker_.scale.x = width * unit;
    marker_.color = color(1.0f, 1.0f, 1.0f, 1.0f);  // (per-point colours above)
    array.markers.push_back(marker_);
    const std::string& frame = marker_.header.frame_id;
    const ros::Time& stamp = marker_.header.stamp;
    addPoseMarkers(o, placement, frame, stamp, unit, /*sensitiveRegion=*/false, array);
    addLabel(o, placement, frame, stamp, Eigen::Vector3d(centre.x(), centre.y(), hi_.z() + 0.1 * unit), unit, boxes,
             array);
  }

 private:
  visualization_msgs::Marker marker_;
  bool proven_;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi_ = -lo_;
};

}  // namespace

visualization_msgs::MarkerArray makeJobMarkers(const WorkspaceQuery& q, const WorkspaceOutcome& o,
                                               const std::string& base_frame, const ros::Time& stamp,
                                               std::size_t max_boxes) {
  visualization_msgs::MarkerArray array;
  const Placement placement(q);
  auto marker = [&](const char* ns, int id, int type) { return newMarker(base_frame, stamp, ns, id, type); };
  array.markers.push_back(deleteAll(base_frame, stamp));
  if (q.pose_domain) {
    // A robot's own pose coordinates are no positions of the base frame: only the label, at the origin.
    addLabel(o, placement, base_frame, stamp, Eigen::Vector3d::Zero(), 1.0, "box(es)", array);
    return array;
  }
  Eigen::Vector3d lo, hi;
  q.workspace.position.boundingBox(lo, hi);
  const Eigen::Vector3d size = hi - lo, centre = 0.5 * (lo + hi);
  const double unit = std::max(size.norm(), 1e-3);  // scale of the drawing (m)
  const double thin = 1e-3 * unit;                  // smallest drawn thickness (RViz ignores zero scales)

  // The region.
  {
    const PositionRegion& r = q.workspace.position;
    visualization_msgs::Marker m = marker(kMarkerNsWorkspace, 0, visualization_msgs::Marker::CUBE);
    m.color = color(0.2f, 0.6f, 1.0f, 0.15f);
    switch (r.type) {
      case PositionRegion::Type::Sphere:
        m.type = visualization_msgs::Marker::SPHERE;
        placement.place(m, r.center);
        m.scale.x = m.scale.y = m.scale.z = 2.0 * r.radius;
        break;
      case PositionRegion::Type::Cylinder:
        m.type = visualization_msgs::Marker::CYLINDER;
        placement.place(m, Eigen::Vector3d(r.center.x(), r.center.y(), 0.5 * (r.z_min + r.z_max)));
        m.scale.x = m.scale.y = 2.0 * r.radius;
        m.scale.z = std::max(r.z_max - r.z_min, thin);
        break;
      case PositionRegion::Type::Box:
      case PositionRegion::Type::Polyhedron:  // drawn as its bounding box
        placement.place(m, centre);
        m.scale.x = std::max(size.x(), thin);
        m.scale.y = std::max(size.y(), thin);
        m.scale.z = std::max(size.z(), thin);
        break;
    }
    array.markers.push_back(m);
  }

  // Its bounding box, as a wireframe (12 edges, corners relative to the centre).
  {
    visualization_msgs::Marker m = marker(kMarkerNsBounds, 0, visualization_msgs::Marker::LINE_LIST);
    placement.place(m, centre);
    m.scale.x = 3e-3 * unit;
    m.color = color(0.2f, 0.6f, 1.0f, 0.9f);
    const Eigen::Vector3d h = 0.5 * size;
    auto corner = [&](int c) {
      return Eigen::Vector3d((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y(), (c & 4) ? h.z() : -h.z());
    };
    for (int c = 0; c < 8; ++c) {
      for (int bit = 1; bit < 8; bit <<= 1) {
        if (c & bit) continue;  // each edge once, from its lower corner
        m.points.push_back(point(corner(c)));
        m.points.push_back(point(corner(c | bit)));
      }
    }
    array.markers.push_back(m);
  }

  // Recorded boxes as cubes, one per distinct position projection, at most `max` of them: the boxes proven safe
  // (translucent green) and the undecided ones (orange).
  auto addCubes = [&](const std::vector<Box6>& boxes, const char* ns, const std_msgs::ColorRGBA& c, std::size_t max) {
    std::set<std::array<double, 6>> seen;
    int id = 0;
    for (const Box6& b : boxes) {
      if (static_cast<std::size_t>(id) >= max) break;
      const std::array<double, 6> key = {b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]};
      if (!seen.insert(key).second) continue;
      visualization_msgs::Marker m = marker(ns, id++, visualization_msgs::Marker::CUBE);
      placement.placeBox(m, b, thin);
      m.color = c;
      array.markers.push_back(m);
    }
  };
  addCubes(o.safe_recorded, kMarkerNsSafe, color(0.1f, 0.8f, 0.2f, 0.12f), o.safe_recorded.size());
  addCubes(o.undecided_recorded, kMarkerNsUndecided, color(1.0f, 0.55f, 0.0f, 0.5f), max_boxes);

  addPoseMarkers(o, placement, base_frame, stamp, unit, /*sensitiveRegion=*/true, array);
  addLabel(o, placement, base_frame, stamp, Eigen::Vector3d(centre.x(), centre.y(), hi.z() + 0.1 * unit), unit,
           "box(es)", array);
  return array;
}

visualization_msgs::MarkerArray makeTrajectoryMarkers(const WorkspaceQuery& q, const WorkspaceOutcome& o,
                                                      const std::string& base_frame, const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  const Placement placement(q);
  array.markers.push_back(deleteAll(base_frame, stamp));

  // The path: pieces [ta, tb] of at most 1/kTrajectoryPieces of the span, at least one per segment (query frame),
  // unless the trajectory has more than kMaxPathSegments segments: then pieces of 1/kMaxPathSegments of the span
  // whatever the segments (a chord may then cut a corner of the path; the marker stays small, ~1 MB, where one piece
  // per segment of a 10^6-waypoint trajectory took ~80 MB, kept by the latched topic).
  const std::unique_ptr<domain::PiecewiseTrajectory> trajectory = toTrajectory(q.trajectory);
  const std::vector<double>& times = trajectory->times();
  const double span = trajectory->endTime() - trajectory->startTime();
  std::vector<std::pair<double, double>> pieces;
  constexpr std::size_t kMaxPathSegments = 10000;
  if (times.size() > kMaxPathSegments + 1) {
    const double t0 = trajectory->startTime();
    for (std::size_t i = 0; i < kMaxPathSegments; ++i) {
      pieces.emplace_back(t0 + span * static_cast<double>(i) / kMaxPathSegments,
                          i + 1 == kMaxPathSegments ? trajectory->endTime()
                                                    : t0 + span * static_cast<double>(i + 1) / kMaxPathSegments);
    }
  } else {
    for (std::size_t k = 0; k + 1 < times.size(); ++k) {
      const int n = std::max(1, static_cast<int>(std::ceil(kTrajectoryPieces * (times[k + 1] - times[k]) / span)));
      for (int i = 0; i < n; ++i) {
        pieces.emplace_back(times[k] + (times[k + 1] - times[k]) * i / n,
                            i + 1 == n ? times[k + 1] : times[k] + (times[k + 1] - times[k]) * (i + 1) / n);
      }
    }
  }
  // Positions within a segment (at its end: the segment's own one-sided pose, via a time just inside it).
  auto position = [&](double t, double inside) {
    const DVec p = trajectory->pointAtTime(t == inside ? t : std::nextafter(t, inside)).pose;
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  ColouredLines path(q, o, base_frame, stamp, kMarkerNsTrajectory);
  for (const auto& [ta, tb] : pieces) {
    bool undecided = false;
    for (const auto& [ua, ub] : o.undecided_times) undecided = undecided || (ua <= tb && ta <= ub);
    path.add(position(ta, tb), position(tb, ta), undecided);
  }
  path.finish(o, placement, 4e-3, "time interval(s)", array);
  return array;
}

visualization_msgs::MarkerArray makeVarietyMarkers(const WorkspaceQuery& q, const WorkspaceOutcome& o,
                                                   const std::string& base_frame, const ros::Time& stamp) {
  visualization_msgs::MarkerArray array;
  const Placement placement(q);
  array.markers.push_back(deleteAll(base_frame, stamp));

  // The grid: for each parameter i, the lines along it with every other parameter at one of `values` grid values,
  // each line in `pieces` pieces (parameter space).
  const std::unique_ptr<domain::ParametricVariety> variety = toVariety(q.variety);
  const int m = q.variety.parameters;
  int values = 2;
  while (m > 1 && m * std::pow(values + 1, m - 1) <= kVarietyGridLines && values < kVarietyGridValues) ++values;
  const int pieces = m == 1 ? kTrajectoryPieces : kVarietyLinePieces;
  int others = 1;
  for (int i = 1; i < m; ++i) others *= values;
  const auto m6 = static_cast<std::size_t>(m);
  const std::size_t undecided = o.undecided_parameters_lower.size() / m6;
  ColouredLines grid(q, o, base_frame, stamp, kMarkerNsVariety);
  DVec t(m), pose;
  DMat jac;
  auto position = [&](const DVec& at) {
    variety->pointAt(at, pose, jac);
    return Eigen::Vector3d(pose[0], pose[1], pose[2]);
  };
  for (int i = 0; i < m; ++i) {
    for (int line = 0; line < others; ++line) {
      // The other parameters' grid values, from the digits of `line` in base `values`.
      for (int v = 0, rest = line; v < m; ++v) {
        if (v == i) continue;
        t[v] = static_cast<double>(rest % values) / (values - 1);
        rest /= values;
      }
      for (int k = 0; k < pieces; ++k) {
        const double a = static_cast<double>(k) / pieces, b = static_cast<double>(k + 1) / pieces;
        t[i] = a;
        const Eigen::Vector3d pa = position(t);
        t[i] = b;
        const Eigen::Vector3d pb = position(t);
        // Does the piece (parameter i in [a, b], the others at t) meet a recorded undecided box?
        bool meets = false;
        for (std::size_t j = 0; j < undecided && !meets; ++j) {
          bool inside = true;
          for (std::size_t v = 0; v < m6 && inside; ++v) {
            const double l = o.undecided_parameters_lower[j * m6 + v], u = o.undecided_parameters_upper[j * m6 + v];
            inside = static_cast<int>(v) == i ? (l <= b && a <= u)
                                              : (l <= t[static_cast<int>(v)] && t[static_cast<int>(v)] <= u);
          }
          meets = inside;
        }
        grid.add(pa, pb, meets);
      }
    }
  }
  grid.finish(o, placement, 2e-3, "parameter box(es)", array);
  return array;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
