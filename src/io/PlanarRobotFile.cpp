#include "pkm_accuracy/io/PlanarRobotFile.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
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
using yaml::vec2;

domain::PlanarWorkspace workspace(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsMap()) fail(where, "expected a map with keys x, y, theta (or theta and region)");
  const Interval theta = range(n["theta"], where + ".theta");
  const YAML::Node reg = n["region"];
  if (!reg)
    return domain::PlanarWorkspace::fromRanges({range(n["x"], where + ".x"), range(n["y"], where + ".y"), theta});
  if (!reg.IsMap() || !reg["type"] || !reg["type"].IsScalar()) {
    fail(where + ".region", "expected a map with a 'type' key");
  }
  const std::string type = reg["type"].Scalar();
  if (type != "disc") fail(where + ".region.type", "expected disc, got '" + type + "'");
  for (const char* key : {"x", "y"}) {
    if (n[key]) fail(where + "." + key, "not allowed with a disc region (the disc gives the x and y ranges)");
  }
  const Eigen::Vector2d centre = vec2(reg["centre"], where + ".region.centre");
  const double radius = number(reg["radius"], where + ".region.radius");
  try {
    return domain::PlanarWorkspace::disc(centre, radius, theta);
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidArgument& e) {
    fail(where + ".region", e.what());
  }
}

/// A planar robot file's document; `path` names it in messages.
PlanarRobotFile parsePlanar(const YAML::Node& root, const std::string& path) {
  if (!root.IsMap()) throw ParseError(path + ": expected a YAML map at top level");
  if (const YAML::Node t = root["type"]) {
    if (!t.IsScalar() || t.Scalar() != "planar3rpr") {
      throw ParseError(path + ": type: expected planar3rpr, got '" + (t.IsScalar() ? t.Scalar() : "<not a scalar>") +
                       "'");
    }
  }
  PlanarRobotFile out;
  model::Planar3RPRGeometry& g = out.geometry;
  g.base_anchors = yaml::points2(root["base_anchors"], path + ": base_anchors");
  g.platform_anchors = yaml::points2(root["platform_anchors"], path + ": platform_anchors");
  const YAML::Node se = root["sensor_error"];
  if (se && se.IsScalar()) {
    g.sensor_error.assign(g.base_anchors.size(), number(se, path + ": sensor_error"));
  } else {
    g.sensor_error = numbers(se, path + ": sensor_error");
  }
  if (root["tool_point"]) g.tool_point = vec2(root["tool_point"], path + ": tool_point");
  try {
    g.validate();
  } catch (const InvalidGeometry& e) {
    throw InvalidGeometry(path + ": " + e.what());
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

}  // namespace

PlanarRobotFile loadPlanarRobotFile(const std::string& path) { return parsePlanar(yaml::loadFile(path), path); }

PlanarRobotFile parsePlanarRobotDocument(const std::string& yamlText, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(yamlText);
  } catch (const YAML::Exception& e) {
    throw ParseError(name + ": invalid YAML: " + e.what());
  }
  return parsePlanar(root, name);
}

}  // namespace io
}  // namespace pkm_accuracy
