#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

namespace pkm_accuracy {
namespace ros_layer {

void PositionRegion::boundingBox(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  switch (type) {
    case Type::Box:
    case Type::Polyhedron:
      lo = box_min;
      hi = box_max;
      return;
    case Type::Sphere:
      lo = center.array() - radius;
      hi = center.array() + radius;
      return;
    case Type::Cylinder:
      lo = Eigen::Vector3d(center.x() - radius, center.y() - radius, z_min);
      hi = Eigen::Vector3d(center.x() + radius, center.y() + radius, z_max);
      return;
  }
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
