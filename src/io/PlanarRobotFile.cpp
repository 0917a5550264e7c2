#include "pkm_accuracy/io/PlanarRobotFile.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw ParseError(where + ": " + what); }

double number(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsScalar()) fail(where, "expected a number");
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    fail(where, "expected a number, got '" + n.Scalar() + "'");
  }
}

std::vector<double> numbers(const YAML::Node& n, const std::string& where, std::size_t expected = 0) {
  if (!n || !n.IsSequence()) fail(where, "expected a list of numbers");
  if (expected > 0 && n.size() != expected) {
    fail(where, "expected " + std::to_string(expected) + " numbers, got " + std::to_string(n.size()));
  }
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

Eigen::Vector2d vec2(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 2);
  return Eigen::Vector2d(v[0], v[1]);
}

std::vector<Eigen::Vector2d> points(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsSequence()) fail(where, "expected a list of [x, y] points");
  std::vector<Eigen::Vector2d> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(vec2(n[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

Interval range(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 2);
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !(v[0] <= v[1])) {
    std::ostringstream os;
    os << "expected a finite range [min, max] with min <= max, got [" << v[0] << ", " << v[1] << "]";
    fail(where, os.str());
  }
  return Interval(v[0], v[1]);
}

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

YAML::Node loadYaml(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw ParseError(path + ": cannot open file");
  } catch (const YAML::Exception& e) {
    throw ParseError(path + ": invalid YAML: " + e.what());
  }
}

}  // namespace

PlanarRobotFile loadPlanarRobotFile(const std::string& path) {
  const YAML::Node root = loadYaml(path);
  if (!root.IsMap()) throw ParseError(path + ": expected a YAML map at top level");
  if (const YAML::Node t = root["type"]) {
    if (!t.IsScalar() || t.Scalar() != "planar3rpr") {
      throw ParseError(path + ": type: expected planar3rpr, got '" + (t.IsScalar() ? t.Scalar() : "<not a scalar>") +
                       "'");
    }
  }
  PlanarRobotFile out;
  model::Planar3RPRGeometry& g = out.geometry;
  g.base_anchors = points(root["base_anchors"], path + ": base_anchors");
  g.platform_anchors = points(root["platform_anchors"], path + ": platform_anchors");
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

}  // namespace io
}  // namespace pkm_accuracy
