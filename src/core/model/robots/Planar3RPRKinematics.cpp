#include "pkm_accuracy/core/model/robots/Planar3RPRKinematics.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

namespace {
constexpr int base(int leg, int axis) { return Planar3RPRKinematics::base(leg, axis); }
constexpr int platform(int leg, int axis) { return Planar3RPRKinematics::platform(leg, axis); }
constexpr int tool(int axis) { return Planar3RPRKinematics::tool(axis); }
}  // namespace

RobotDescription Planar3RPRKinematics::description() {
  RobotDescription d;
  d.type = "planar3rpr";
  d.pose = {{"x", "m", false}, {"y", "m", false}, {"theta", "rad", true}};
  for (int i = 0; i < 3; ++i) d.joints.push_back({"leg_" + std::to_string(i), "m"});
  static const char* kAxis[2] = {"x", "y"};
  for (const char* group : {"base_anchors", "platform_anchors"})
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 2; ++k)
        d.geometry.push_back({std::string(group) + "[" + std::to_string(i) + "]." + kAxis[k]});
  for (int k = 0; k < 2; ++k) {
    GeometryValue c{std::string("tool_point.") + kAxis[k]};
    c.has_default = true;
    d.geometry.push_back(c);
  }
  return d;
}

std::unique_ptr<KinematicModel<Planar3RPRKinematics>> makePlanar3RPR(const Planar3RPRGeometry& geometry) {
  geometry.validate();
  RobotDescription d = Planar3RPRKinematics::description();
  d.sensor_error = geometry.sensor_error;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 2; ++k) {
      d.geometry[static_cast<std::size_t>(base(i, k))].nominal = geometry.base_anchors[static_cast<std::size_t>(i)][k];
      d.geometry[static_cast<std::size_t>(platform(i, k))].nominal =
          geometry.platform_anchors[static_cast<std::size_t>(i)][k];
    }
  }
  for (int k = 0; k < 2; ++k) d.geometry[static_cast<std::size_t>(tool(k))].nominal = geometry.tool_point[k];
  return std::make_unique<KinematicModel<Planar3RPRKinematics>>(Planar3RPRKinematics(), d);
}

}  // namespace model
}  // namespace pkm_accuracy
