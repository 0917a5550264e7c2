#include "pkm_accuracy/core/model/robots/Delta3Kinematics.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

RobotDescription Delta3Kinematics::description() {
  RobotDescription d;
  d.type = "delta3";
  d.pose = {{"x", "m", false}, {"y", "m", false}, {"z", "m", false}};
  for (int i = 0; i < 3; ++i) d.joints.push_back({"crank_" + std::to_string(i), "rad"});
  for (const char* group : {"base_radius", "platform_radius", "upper_arm_length", "forearm_length"})
    for (int i = 0; i < 3; ++i) d.geometry.push_back({std::string(group) + "[" + std::to_string(i) + "]", "m"});
  for (int i = 0; i < 3; ++i) d.geometry.push_back({"motor_angle[" + std::to_string(i) + "]", "rad"});
  return d;
}

}  // namespace model
}  // namespace pkm_accuracy
