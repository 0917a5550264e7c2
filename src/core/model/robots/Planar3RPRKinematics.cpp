#include "pkm_accuracy/core/model/robots/Planar3RPRKinematics.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

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

}  // namespace model
}  // namespace pkm_accuracy
