#include "pkm_accuracy/core/model/robots/Prs3Kinematics.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

RobotDescription Prs3Kinematics::description() {
  // The reference robot (config/prs3.yaml): sliders on a circle of radius 0.2 m, rods 0.3 m, platform radius 0.1 m.
  RobotDescription d;
  d.type = "prs3";
  d.pose = {{"z", "m", false}, {"tilt_x", "rad", true}, {"tilt_y", "rad", true}};
  for (int i = 0; i < 3; ++i) d.joints.push_back({"slider_" + std::to_string(i), "m"});
  for (int i = 0; i < 3; ++i) d.geometry.push_back({"base_radius[" + std::to_string(i) + "]", "m", 0.2});
  for (int i = 0; i < 3; ++i) d.geometry.push_back({"rod_length[" + std::to_string(i) + "]", "m", 0.3});
  d.geometry.push_back({"platform_radius", "m", 0.1});
  return d;
}

}  // namespace model
}  // namespace pkm_accuracy
