#include "pkm_accuracy/io/RobotFile.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
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

std::string triple(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
  return os.str();
}

/// Half-widths (m) of the anchors of one kind: a number (every coordinate of the 6 anchors) or 6 triples
/// [hx, hy, hz], every value finite and >= 0.
std::vector<Eigen::Vector3d> halfwidths(const YAML::Node& n, const std::string& where) {
  std::vector<Eigen::Vector3d> out;
  if (n.IsScalar()) {
    out.assign(6, Eigen::Vector3d::Constant(number(n, where)));
  } else if (n.IsSequence() && n.size() == 6) {
    out = yaml::points3(n, where);
  } else {
    fail(where, "expected a half-width >= 0 (m) for every coordinate, or 6 triples [hx, hy, hz] (m), got " +
                    (n.IsSequence() ? "a list of " + std::to_string(n.size()) + " items" : yaml::show(n)));
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if ((out[i].array() < 0.0).any()) {
      fail(n.IsScalar() ? where : where + "[" + std::to_string(i) + "]",
           "expected half-widths >= 0 (m), got " + triple(out[i]));
    }
  }
  return out;
}

/// The name of key `key` of the map named `where`: "file.yaml: key" at the top of a file (`where` ending in ':'),
/// "file.yaml: workspaces.paper.key" inside.
std::string child(const std::string& where, const std::string& key) {
  return !where.empty() && where.back() == ':' ? where + " " + key : where + "." + key;
}

domain::Workspace workspace(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsMap()) fail(where, "expected a map with keys x, y, z, roll, pitch, yaw");
  yaml::checkKeys(n, where, {"x", "y", "z", "roll", "pitch", "yaw", "region"});
  static const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::array<Interval, 6> r;
  for (int i = 0; i < 6; ++i) r[i] = range(n[keys[i]], child(where, keys[i]));
  const std::array<Interval, 3> orientation = {r[3], r[4], r[5]};
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
  // Per-anchor half-widths replace anchor_uncertainty for their kind of anchor.
  if (root["base_anchor_uncertainty"]) {
    g.base_anchor_halfwidth = halfwidths(root["base_anchor_uncertainty"], path + ": base_anchor_uncertainty");
  }
  if (root["platform_anchor_uncertainty"]) {
    g.platform_anchor_halfwidth =
        halfwidths(root["platform_anchor_uncertainty"], path + ": platform_anchor_uncertainty");
  }
  if (root["tool_point_uncertainty"]) {
    const std::string where = path + ": tool_point_uncertainty";
    g.tool_point_halfwidth = vec3(root["tool_point_uncertainty"], where);
    if ((g.tool_point_halfwidth.array() < 0.0).any()) {
      fail(where, "expected half-widths [hx, hy, hz] >= 0 (m), got " + triple(g.tool_point_halfwidth));
    }
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
    }
  }
  return out;
}

domain::Workspace parseWorkspaceFile(const std::string& path) {
  const YAML::Node root = yaml::loadFile(path);
  return workspace(root, path + ":");
}

}  // namespace io
}  // namespace pkm_accuracy
