// Planar 3-RPR parallel robot as templated kinematics (type `planar3rpr`; conventions: docs/models.md).
//   pose X = (x, y, theta), R(theta) the 2-D rotation, B_i = p + R b_i, d_i = B_i - A_i, joint i = |d_i| (m),
//   n_i = d_i / |d_i|, row i of J^-1 = [n_i^T, (R (b_i - c)) x n_i] (scalar 2-D cross product u_x v_y - u_y v_x).
// Geometry values: base_anchors[i].{x,y}, platform_anchors[i].{x,y}, tool_point.{x,y} (m).
#pragma once

#include <memory>

#include "pkm_accuracy/core/model/KinematicModel.hpp"
#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/Planar3RPRGeometry.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace model {

struct Planar3RPRKinematics {
  static constexpr int kDof = 3;
  static constexpr int base(int leg, int axis) { return 2 * leg + axis; }
  static constexpr int platform(int leg, int axis) { return 6 + 2 * leg + axis; }
  static constexpr int tool(int axis) { return 12 + axis; }

  static RobotDescription description();

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    const T st = kin::sin(pose[2]), ct = kin::cos(pose[2]);
    for (int i = 0; i < 3; ++i) {
      const T b0 = g[platform(i, 0)], b1 = g[platform(i, 1)];
      const T c0 = b0 - g[tool(0)], c1 = b1 - g[tool(1)];
      const T u0 = ct * c0 - st * c1, u1 = st * c0 + ct * c1;
      const T d0 = pose[0] + (ct * b0 - st * b1) - g[base(i, 0)];
      const T d1 = pose[1] + (st * b0 + ct * b1) - g[base(i, 1)];
      const T len = kin::sqrt(kin::sqr(d0) + kin::sqr(d1));
      jinv[3 * i + 0] = d0 / len;
      jinv[3 * i + 1] = d1 / len;
      jinv[3 * i + 2] = (u0 * d1 - u1 * d0) / len;
    }
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    const T st = kin::sin(pose[2]), ct = kin::cos(pose[2]);
    for (int i = 0; i < 3; ++i) {
      const T b0 = g[platform(i, 0)], b1 = g[platform(i, 1)];
      const T d0 = pose[0] + (ct * b0 - st * b1) - g[base(i, 0)];
      const T d1 = pose[1] + (st * b0 + ct * b1) - g[base(i, 1)];
      joints[i] = kin::sqrt(kin::sqr(d0) + kin::sqr(d1));
    }
  }
};

/// The planar 3-RPR robot of a Planar3RPRGeometry (known exactly).
/// @throws InvalidGeometry if geometry.validate() fails (the message names the field).
std::unique_ptr<KinematicModel<Planar3RPRKinematics>> makePlanar3RPR(const Planar3RPRGeometry& geometry);

}  // namespace model
}  // namespace pkm_accuracy
