#include "pkm_accuracy/ros/WorkspaceQuery.hpp"

#include <algorithm>

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

double TrajectorySpec::timeOf(double u) const {
  if (times.empty()) return 0.0;
  const double t0 = times.front(), t1 = times.back();
  return std::min(std::max(t0 + u * (t1 - t0), t0), t1);
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
