#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"

#include <string>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/model/KinematicModel.hpp"

namespace pkm_accuracy {
namespace model {

RobotDescription GoughKinematics::description() {
  RobotDescription d;
  d.type = "gough";
  d.pose = rigidBodyPose();
  for (int i = 0; i < 6; ++i) d.joints.push_back({"leg_" + std::to_string(i), "m"});
  static const char* kAxis[3] = {"x", "y", "z"};
  for (const char* group : {"base_anchors", "platform_anchors"})
    for (int i = 0; i < 6; ++i)
      for (int k = 0; k < 3; ++k)
        d.geometry.push_back({std::string(group) + "[" + std::to_string(i) + "]." + kAxis[k]});
  for (int k = 0; k < 3; ++k) {
    GeometryValue c{std::string("tool_point.") + kAxis[k]};
    c.tool_point_coordinate = k;
    c.has_default = true;
    d.geometry.push_back(c);
  }
  return d;
}

RobotDescription goughDescription(const GoughGeometry& geometry) {
  geometry.validate();
  RobotDescription d = GoughKinematics::description();
  d.sensor_error = geometry.sensor_error;
  auto set = [&d](int index, double value, double half) {
    d.geometry[static_cast<std::size_t>(index)].nominal = value;
    d.geometry[static_cast<std::size_t>(index)].lo = -half;
    d.geometry[static_cast<std::size_t>(index)].hi = half;
  };
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t leg = static_cast<std::size_t>(i);
      set(GoughKinematics::base(i, k), geometry.base_anchors[leg][k],
          geometry.base_anchor_halfwidth.empty() ? 0.0 : geometry.base_anchor_halfwidth[leg][k]);
      set(GoughKinematics::platform(i, k), geometry.platform_anchors[leg][k],
          geometry.platform_anchor_halfwidth.empty() ? 0.0 : geometry.platform_anchor_halfwidth[leg][k]);
    }
  }
  for (int k = 0; k < 3; ++k) set(GoughKinematics::tool(k), geometry.tool_point[k], geometry.tool_point_halfwidth[k]);
  return d;
}

GoughGeometry goughGeometry(const RobotDescription& description) {
  description.validate();
  if (description.geometry.size() != 39 || description.pose.size() != 6) {
    throw InvalidGeometry("gough: expected the 39 geometry values of GoughKinematics::description(), got " +
                          std::to_string(description.geometry.size()));
  }
  GoughGeometry g;
  g.sensor_error = description.sensor_error;
  g.base_anchors.assign(6, Eigen::Vector3d::Zero());
  g.platform_anchors.assign(6, Eigen::Vector3d::Zero());
  g.base_anchor_halfwidth.assign(6, Eigen::Vector3d::Zero());
  g.platform_anchor_halfwidth.assign(6, Eigen::Vector3d::Zero());
  auto get = [&description](int index, double& value, double& half) {
    const GeometryValue& v = description.geometry[static_cast<std::size_t>(index)];
    value = v.nominal;
    half = 0.0;
    if (v.lo == -v.hi) {
      half = v.hi;
    } else {
      applyCoordinateBound(CoordinateBound::offsets(v.lo, v.hi), value, half);
    }
  };
  for (int i = 0; i < 6; ++i) {
    const std::size_t leg = static_cast<std::size_t>(i);
    for (int k = 0; k < 3; ++k) {
      get(GoughKinematics::base(i, k), g.base_anchors[leg][k], g.base_anchor_halfwidth[leg][k]);
      get(GoughKinematics::platform(i, k), g.platform_anchors[leg][k], g.platform_anchor_halfwidth[leg][k]);
    }
  }
  for (int k = 0; k < 3; ++k) get(GoughKinematics::tool(k), g.tool_point[k], g.tool_point_halfwidth[k]);
  if (!g.hasUncertainty()) {
    g.base_anchor_halfwidth.clear();
    g.platform_anchor_halfwidth.clear();
  }
  g.validate();
  return g;
}

std::unique_ptr<RobotModel> makeGenericGough(const GoughGeometry& geometry) {
  return std::make_unique<KinematicModel<GoughKinematics>>(GoughKinematics(), goughDescription(geometry));
}

}  // namespace model
}  // namespace pkm_accuracy
