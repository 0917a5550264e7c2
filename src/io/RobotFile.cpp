#include "pkm_accuracy/io/RobotFile.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "YamlReading.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

using yaml::fail;
using yaml::number;
using yaml::numbers;
using yaml::range;
using yaml::vec3;

using Bounds3 = std::array<model::CoordinateBound, 3>;

/// One coordinate's bound: a half-width h >= 0 (m) or offsets [lo, hi] (m) with lo <= hi.
model::CoordinateBound coordinateBound(const YAML::Node& n, const std::string& where) {
  if (n && n.IsSequence()) {
    const auto v = numbers(n, where, 2, " [lo, hi] (offsets, m)");
    if (!(v[0] <= v[1])) {
      std::ostringstream os;
      os << "expected offsets [lo, hi] with lo <= hi (m), got [" << v[0] << ", " << v[1] << "]";
      fail(where, os.str());
    }
    return model::CoordinateBound::offsets(v[0], v[1]);
  }
  if (!n || !n.IsScalar()) fail(where, "expected a half-width >= 0 (m) or offsets [lo, hi] (m), got " + yaml::show(n));
  const double h = number(n, where);
  if (!(h >= 0.0)) {
    std::ostringstream os;
    os << "expected a half-width >= 0 (m), got " << h;
    fail(where, os.str());
  }
  return model::CoordinateBound::halfwidth(h);
}

/// The bounds of a point's 3 coordinates: [bx, by, bz], each a half-width or offsets [lo, hi].
Bounds3 pointBounds(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsSequence() || n.size() != 3) {
    fail(where, "expected [bx, by, bz], each a half-width >= 0 (m) or offsets [lo, hi] (m), got " +
                    (n && n.IsSequence() ? "a list of " + std::to_string(n.size()) + " items" : yaml::show(n)));
  }
  Bounds3 out;
  for (int k = 0; k < 3; ++k) out[k] = coordinateBound(n[k], where + "[" + std::to_string(k) + "]");
  return out;
}

/// The bounds of the anchors of one kind: a half-width (every coordinate of the 6 anchors) or 6 triples, each
/// coordinate a half-width or offsets [lo, hi].
std::vector<Bounds3> anchorBounds(const YAML::Node& n, const std::string& where) {
  if (n.IsScalar()) {
    const model::CoordinateBound b = coordinateBound(n, where);
    return std::vector<Bounds3>(6, Bounds3{b, b, b});
  }
  if (!n.IsSequence() || n.size() != 6) {
    fail(where,
         "expected a half-width >= 0 (m) for every coordinate, or 6 triples [bx, by, bz] (each a half-width "
         "or offsets [lo, hi], m), got " +
             (n.IsSequence() ? "a list of " + std::to_string(n.size()) + " items" : yaml::show(n)));
  }
  std::vector<Bounds3> out;
  for (std::size_t i = 0; i < 6; ++i) out.push_back(pointBounds(n[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

/// Applies the bounds to a point and its half-widths (an asymmetric range moves the coordinate to its centre).
void applyBounds(const Bounds3& b, Eigen::Vector3d& point, Eigen::Vector3d& halfwidth, const std::string& where) {
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    try {
      model::applyCoordinateBound(b[k], point[k], halfwidth[k]);
    } catch (const InvalidGeometry& e) {
      fail(where + "[" + std::to_string(k) + "] (" + kAxis[k] + ")", e.what());
    }
  }
}

/// The name of key `key` of the map named `where`: "file.yaml: key" at the top of a file (`where` ending in ':'),
/// "file.yaml: workspaces.paper.key" inside.
std::string child(const std::string& where, const std::string& key) {
  return !where.empty() && where.back() == ':' ? where + " " + key : where + "." + key;
}

/// A workspace's optional `frame` (yaml::frame: finite values, a rotation built from roll, pitch, yaw).
std::optional<domain::RigidTransform> workspaceFrame(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsMap() || !n["frame"]) return std::nullopt;
  return yaml::frame(n["frame"], child(where, "frame"));
}

domain::Workspace workspace(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsMap()) fail(where, "expected a map with keys x, y, z, roll, pitch, yaw");
  yaml::checkKeys(n, where, {"x", "y", "z", "roll", "pitch", "yaw", "region", "frame"});
  static const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::array<Interval, 6> r;
  for (int i = 0; i < 6; ++i) r[i] = range(n[keys[i]], child(where, keys[i]));
  const std::array<Interval, 3> orientation = {r[3], r[4], r[5]};
  try {
    domain::Workspace::fromRanges(r);  // the six ranges alone (e.g. an angle beyond 2 pi), named as such
  } catch (const InvalidArgument& e) {
    fail(where, e.what());
  }
  const YAML::Node reg = n["region"];
  const std::string rw = child(where, "region");
  if (!reg) return domain::Workspace::fromRanges(r);
  if (!reg.IsMap() || !reg["type"]) fail(rw, "expected a map with a 'type' key");
  const std::string type = reg["type"].as<std::string>();
  const std::map<std::string, std::set<std::string>> regionKeys = {{"box", {"type"}},
                                                                   {"cylinder", {"type", "centre", "radius", "z"}},
                                                                   {"sphere", {"type", "centre", "radius"}},
                                                                   {"polyhedron", {"type", "normals", "offsets"}}};
  if (regionKeys.count(type)) yaml::checkKeys(reg, rw, regionKeys.at(type));
  const Eigen::Vector3d lo(r[0].lower(), r[1].lower(), r[2].lower()), hi(r[0].upper(), r[1].upper(), r[2].upper());
  try {
    if (type == "box") return domain::Workspace(domain::PositionRegion::box(lo, hi), orientation);
    if (type == "cylinder") {
      const auto c = numbers(reg["centre"], rw + ".centre", 2);
      const Interval z = reg["z"] ? range(reg["z"], rw + ".z") : r[2];
      return domain::Workspace(
          domain::PositionRegion::cylinder(c[0], c[1], number(reg["radius"], rw + ".radius"), z.lower(), z.upper()),
          orientation);
    }
    if (type == "sphere") {
      return domain::Workspace(
          domain::PositionRegion::sphere(vec3(reg["centre"], rw + ".centre"), number(reg["radius"], rw + ".radius")),
          orientation);
    }
    if (type == "polyhedron") {
      return domain::Workspace(domain::PositionRegion::polyhedron(yaml::points3(reg["normals"], rw + ".normals"),
                                                                  numbers(reg["offsets"], rw + ".offsets"), lo, hi),
                               orientation);
    }
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidArgument& e) {
    fail(rw, e.what());
  }
  fail(rw + ".type", "expected box, cylinder, sphere or polyhedron, got '" + type + "'");
}

}  // namespace

RobotFile loadRobotFile(const std::string& path) {
  const YAML::Node root = yaml::loadFile(path);
  if (!root.IsMap()) throw ParseError(path + ": expected a YAML map at top level");
  RobotFile out;
  model::GoughGeometry& g = out.geometry;
  g.base_anchors = yaml::points3(root["base_anchors"], path + ": base_anchors");
  g.platform_anchors = yaml::points3(root["platform_anchors"], path + ": platform_anchors");
  const YAML::Node se = root["sensor_error"];
  if (se && se.IsScalar()) {
    g.sensor_error.assign(g.base_anchors.size(), number(se, path + ": sensor_error"));
  } else {
    g.sensor_error = numbers(se, path + ": sensor_error");
  }
  if (root["tool_point"]) g.tool_point = vec3(root["tool_point"], path + ": tool_point");
  if (root["anchor_uncertainty"]) {
    const double h = number(root["anchor_uncertainty"], path + ": anchor_uncertainty");
    if (!(h >= 0.0))
      fail(path + ": anchor_uncertainty",
           "expected a half-width >= 0 (m), got " + yaml::show(root["anchor_uncertainty"]));
    g.setUniformAnchorUncertainty(h);
  }
  // Per-anchor bounds replace anchor_uncertainty for their kind of anchor (offsets [lo, hi] move the anchor's
  // coordinate to the centre of its range).
  const auto anchors = [&](const char* key, std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>& h) {
    if (!root[key]) return;
    const std::string where = path + ": " + key;
    const std::vector<Bounds3> b = anchorBounds(root[key], where);
    if (points.size() != 6) fail(where, "needs the 6 anchors it bounds, got " + std::to_string(points.size()));
    h.assign(6, Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < 6; ++i) applyBounds(b[i], points[i], h[i], where + "[" + std::to_string(i) + "]");
  };
  anchors("base_anchor_uncertainty", g.base_anchors, g.base_anchor_halfwidth);
  anchors("platform_anchor_uncertainty", g.platform_anchors, g.platform_anchor_halfwidth);
  if (root["tool_point_uncertainty"]) {
    const std::string where = path + ": tool_point_uncertainty";
    applyBounds(pointBounds(root["tool_point_uncertainty"], where), g.tool_point, g.tool_point_halfwidth, where);
  }
  try {
    g.validate();
  } catch (const InvalidGeometry& e) {
    throw InvalidGeometry(path + ": " + e.what());
  }
  if (root["anchor_uncertainty_cases"]) {
    out.anchor_uncertainty_cases = numbers(root["anchor_uncertainty_cases"], path + ": anchor_uncertainty_cases");
  }
  static const std::set<std::string> kKnown = {
      // this file's keys
      "base_anchors", "platform_anchors", "sensor_error", "tool_point", "anchor_uncertainty", "base_anchor_uncertainty",
      "platform_anchor_uncertainty", "tool_point_uncertainty", "anchor_uncertainty_cases", "workspaces",
      // the node's other parameters (the same file loads as its parameters)
      "robot_source", "base_frame", "platform_frame", "base_anchor_pattern", "platform_anchor_pattern",
      "anchor_first_index", "publish_anchor_frames", "default_time_budget", "default_alpha", "default_min_width",
      "default_method", "max_parallel_jobs", "progress_rate", "tf_timeout", "max_box_markers"};
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (!kKnown.count(key)) out.unknown_keys.push_back(key);
  }
  if (const YAML::Node ws = root["workspaces"]) {
    if (!ws.IsMap()) throw ParseError(path + ": workspaces: expected a map of named workspaces");
    for (const auto& kv : ws) {
      const std::string name = kv.first.as<std::string>();
      out.workspaces.emplace(name, workspace(kv.second, path + ": workspaces." + name));
      if (auto f = workspaceFrame(kv.second, path + ": workspaces." + name)) out.workspace_frames.emplace(name, *f);
    }
  }
  return out;
}

domain::Workspace parseWorkspaceFile(const std::string& path, std::optional<domain::RigidTransform>* frame) {
  const YAML::Node root = yaml::loadFile(path);
  domain::Workspace w = workspace(root, path + ":");
  const std::optional<domain::RigidTransform> f = workspaceFrame(root, path + ":");
  if (frame) *frame = f;
  return w;
}

}  // namespace io
}  // namespace pkm_accuracy
