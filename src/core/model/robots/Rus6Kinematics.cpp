#include "pkm_accuracy/core/model/robots/Rus6Kinematics.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

RobotDescription Rus6Kinematics::description() {
  // The reference robot (config/rus6.yaml): three pairs of motors on a circle of radius 0.2 m, at 90 +- 20, 210 +- 20
  // and 330 +- 20 deg, crank axes radial (cranks pointing tangentially away from the pair's centre at zero crank
  // angle), cranks 0.1 m, rods 0.35 m, platform anchors on a circle of radius 0.1 m at 90 -+ 5, 210 -+ 5, 330 -+ 5 deg.
  static const double kBase[6][3] = {
      {0.06840402866513377, 0.18793852415718168, 0.0},   {-0.06840402866513375, 0.1879385241571817, 0.0},
      {-0.1969615506024416, -0.034729635533386094, 0.0}, {-0.1285575219373079, -0.15320888862379559, 0.0},
      {0.12855752193730785, -0.15320888862379564, 0.0},  {0.1969615506024416, -0.03472963553338608, 0.0}};
  static const double kAxisAngle[6] = {-1.9198621771937625, 1.9198621771937625, 0.17453292519943295,
                                       -2.2689280275926285, 2.2689280275926285, -0.17453292519943295};
  static const double kPlatform[6][3] = {
      {0.008715574274765815, 0.09961946980917456, 0.0},  {-0.008715574274765823, 0.09961946980917456, 0.0},
      {-0.09063077870366501, -0.04226182617406993, 0.0}, {-0.08191520442889919, -0.05735764363510462, 0.0},
      {0.08191520442889916, -0.05735764363510465, 0.0},  {0.09063077870366501, -0.04226182617406993, 0.0}};
  RobotDescription d;
  d.type = "rus6";
  d.pose = rigidBodyPose();
  for (int i = 0; i < 6; ++i) d.joints.push_back({"crank_" + std::to_string(i), "rad"});
  static const char* kAxis[3] = {"x", "y", "z"};
  auto index = [](const char* group, int i) { return std::string(group) + "[" + std::to_string(i) + "]"; };
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) d.geometry.push_back({index("base_pivots", i) + "." + kAxis[k], "m", kBase[i][k]});
  for (int i = 0; i < 6; ++i) d.geometry.push_back({index("crank_axis_angle", i), "rad", kAxisAngle[i]});
  for (int i = 0; i < 6; ++i) d.geometry.push_back({index("crank_radius", i), "m", 0.1});
  for (int i = 0; i < 6; ++i) d.geometry.push_back({index("rod_length", i), "m", 0.35});
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k)
      d.geometry.push_back({index("platform_anchors", i) + "." + kAxis[k], "m", kPlatform[i][k]});
  for (int k = 0; k < 3; ++k) {
    GeometryValue c{std::string("tool_point.") + kAxis[k], "m", 0.0};
    c.tool_point_coordinate = k;
    c.has_default = true;
    d.geometry.push_back(c);
  }
  return d;
}

}  // namespace model
}  // namespace pkm_accuracy
