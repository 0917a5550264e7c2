// Reading values out of YAML documents with error messages that name the file, the key and what was expected.
// Internal to the io library (shared by the robot, planar robot and trajectory readers).
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"

namespace pkm_accuracy {
namespace io {
namespace yaml {

/// @throws ParseError "<where>: <what>".
[[noreturn]] void fail(const std::string& where, const std::string& what);
/// Short description of a node for messages ("'abc'", "a list", "a map", "nothing").
std::string show(const YAML::Node& n);
/// A finite number.
double number(const YAML::Node& n, const std::string& where);
/// A list of finite numbers (exactly `expected` of them unless 0); `shape` is appended to the expectation.
std::vector<double> numbers(const YAML::Node& n, const std::string& where, std::size_t expected = 0,
                            const std::string& shape = "");
/// An integer in [lo, hi].
int integer(const YAML::Node& n, const std::string& where, int lo, int hi);
/// Fails on keys of `map` that are not in `allowed`.
void checkKeys(const YAML::Node& map, const std::string& where, const std::set<std::string>& allowed);
Eigen::Vector2d vec2(const YAML::Node& n, const std::string& where);
Eigen::Vector3d vec3(const YAML::Node& n, const std::string& where);
std::vector<Eigen::Vector2d> points2(const YAML::Node& n, const std::string& where);
std::vector<Eigen::Vector3d> points3(const YAML::Node& n, const std::string& where);
/// [min, max] with finite min <= max.
Interval range(const YAML::Node& n, const std::string& where);
/// A frame F fixed to the robot's base frame, `{translation: [x, y, z], rpy: [roll, pitch, yaw]}` (m, rad; R =
/// Rz(yaw) Ry(pitch) Rx(roll); each key optional, 0): the pose of F in the base frame.
domain::RigidTransform frame(const YAML::Node& n, const std::string& where);
/// The document of a file. @throws ParseError "<path>: cannot open file" / "<path>: invalid YAML: ...".
YAML::Node loadFile(const std::string& path);

}  // namespace yaml
}  // namespace io
}  // namespace pkm_accuracy
