// Test oracle: the reference robot read directly from config/ref6.yaml with yaml-cpp (independently of the ROS
// parameter server and of the loaders under test).
#pragma once

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#ifndef PKM_SOURCE_DIR
#error "PKM_SOURCE_DIR must be defined by CMake"
#endif

namespace pkm_accuracy_test {

struct Ref6 {
  std::vector<Eigen::Vector3d> base_anchors, platform_anchors;
  std::vector<double> sensor_error;
  Eigen::Vector3d tool_point = Eigen::Vector3d::Zero();
};

inline std::string sourcePath(const std::string& rel) { return std::string(PKM_SOURCE_DIR) + "/" + rel; }

/// A Gough robot file (the keys of config/ref6.yaml; tool_point optional), `rel` to the source directory.
inline Ref6 loadRef6(const std::string& rel = "config/ref6.yaml") {
  const YAML::Node y = YAML::LoadFile(sourcePath(rel));
  Ref6 r;
  auto points = [](const YAML::Node& n) {
    std::vector<Eigen::Vector3d> out;
    for (const auto& p : n) out.emplace_back(p[0].as<double>(), p[1].as<double>(), p[2].as<double>());
    return out;
  };
  r.base_anchors = points(y["base_anchors"]);
  r.platform_anchors = points(y["platform_anchors"]);
  for (const auto& e : y["sensor_error"]) r.sensor_error.push_back(e.as<double>());
  const YAML::Node c = y["tool_point"];
  if (c) r.tool_point = Eigen::Vector3d(c[0].as<double>(), c[1].as<double>(), c[2].as<double>());
  return r;
}

}  // namespace pkm_accuracy_test
