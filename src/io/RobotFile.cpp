#include "pkm_accuracy/io/RobotFile.hpp"

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

Eigen::Vector3d vec3(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

std::vector<Eigen::Vector3d> points(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsSequence()) fail(where, "expected a list of [x, y, z] points");
  std::vector<Eigen::Vector3d> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(vec3(n[i], where + "[" + std::to_string(i) + "]"));
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

domain::Workspace workspace(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsMap()) fail(where, "expected a map with keys x, y, z, roll, pitch, yaw");
  static const char* keys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  std::array<Interval, 6> r;
  for (int i = 0; i < 6; ++i) r[i] = range(n[keys[i]], where + "." + keys[i]);
  const std::array<Interval, 3> orientation = {r[3], r[4], r[5]};
  const YAML::Node reg = n["region"];
  if (!reg) return domain::Workspace::fromRanges(r);
  if (!reg.IsMap() || !reg["type"]) fail(where + ".region", "expected a map with a 'type' key");
  const std::string type = reg["type"].as<std::string>();
  const Eigen::Vector3d lo(r[0].lower(), r[1].lower(), r[2].lower()), hi(r[0].upper(), r[1].upper(), r[2].upper());
  try {
    if (type == "box") return domain::Workspace(domain::PositionRegion::box(lo, hi), orientation);
    if (type == "cylinder") {
      const auto c = numbers(reg["centre"], where + ".region.centre", 2);
      const Interval z = reg["z"] ? range(reg["z"], where + ".region.z") : r[2];
      return domain::Workspace(domain::PositionRegion::cylinder(
                                   c[0], c[1], number(reg["radius"], where + ".region.radius"), z.lower(), z.upper()),
                               orientation);
    }
    if (type == "sphere") {
      return domain::Workspace(domain::PositionRegion::sphere(vec3(reg["centre"], where + ".region.centre"),
                                                              number(reg["radius"], where + ".region.radius")),
                               orientation);
    }
    if (type == "polyhedron") {
      return domain::Workspace(
          domain::PositionRegion::polyhedron(points(reg["normals"], where + ".region.normals"),
                                             numbers(reg["offsets"], where + ".region.offsets"), lo, hi),
          orientation);
    }
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidArgument& e) {
    fail(where + ".region", e.what());
  }
  fail(where + ".region.type", "expected box, cylinder, sphere or polyhedron, got '" + type + "'");
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

RobotFile loadRobotFile(const std::string& path) {
  const YAML::Node root = loadYaml(path);
  if (!root.IsMap()) throw ParseError(path + ": expected a YAML map at top level");
  RobotFile out;
  model::GoughGeometry& g = out.geometry;
  g.base_anchors = points(root["base_anchors"], path + ": base_anchors");
  g.platform_anchors = points(root["platform_anchors"], path + ": platform_anchors");
  const YAML::Node se = root["sensor_error"];
  if (se && se.IsScalar()) {
    g.sensor_error.assign(g.base_anchors.size(), number(se, path + ": sensor_error"));
  } else {
    g.sensor_error = numbers(se, path + ": sensor_error");
  }
  if (root["tool_point"]) g.tool_point = vec3(root["tool_point"], path + ": tool_point");
  if (root["anchor_uncertainty"]) {
    g.setUniformAnchorUncertainty(number(root["anchor_uncertainty"], path + ": anchor_uncertainty"));
  }
  try {
    g.validate();
  } catch (const InvalidGeometry& e) {
    throw InvalidGeometry(path + ": " + e.what());
  }
  if (root["anchor_uncertainty_cases"]) {
    out.anchor_uncertainty_cases = numbers(root["anchor_uncertainty_cases"], path + ": anchor_uncertainty_cases");
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
  const YAML::Node root = loadYaml(path);
  return workspace(root, path);
}

}  // namespace io
}  // namespace pkm_accuracy
