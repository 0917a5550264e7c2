// 6-UPS Gough-Stewart platform as templated kinematics (type `gough`; conventions: docs/conventions.md).
//   pose X = (x, y, z, roll, pitch, yaw), R = Rz(yaw) Ry(pitch) Rx(roll), B_i = p + R b_i, d_i = B_i - A_i,
//   joint i = |d_i| (m), n_i = d_i / |d_i|, row i of J^-1 = [n_i^T, ((R (b_i - c)) x n_i)^T].
// Geometry values: base_anchors[i].{x,y,z} (A_i, base frame), platform_anchors[i].{x,y,z} (b_i, platform frame),
// tool_point.{x,y,z} (c, platform frame), all in m.
#pragma once

#include <memory>

#include "pkm_accuracy/core/model/GoughGeometry.hpp"
#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace model {

struct GoughKinematics {
  static constexpr int kDof = 6;
  /// Geometry value indices.
  static constexpr int base(int leg, int axis) { return 3 * leg + axis; }
  static constexpr int platform(int leg, int axis) { return 18 + 3 * leg + axis; }
  static constexpr int tool(int axis) { return 36 + axis; }

  /// The type's components, joints and geometry values (nominal values 0, sensor errors unset).
  static RobotDescription description();

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    const auto r = kin::rotationRpy(pose[3], pose[4], pose[5]);
    for (int i = 0; i < 6; ++i) {
      const kin::Vec3<T> b{g[platform(i, 0)], g[platform(i, 1)], g[platform(i, 2)]};
      const kin::Vec3<T> bc{b[0] - g[tool(0)], b[1] - g[tool(1)], b[2] - g[tool(2)]};
      const kin::Vec3<T> rb = kin::rotate(r, b), u = kin::rotate(r, bc);
      const kin::Vec3<T> d{pose[0] + rb[0] - g[base(i, 0)], pose[1] + rb[1] - g[base(i, 1)],
                           pose[2] + rb[2] - g[base(i, 2)]};
      const T len = kin::sqrt(kin::sqr(d[0]) + kin::sqr(d[1]) + kin::sqr(d[2]));
      const kin::Vec3<T> n{d[0] / len, d[1] / len, d[2] / len};
      const kin::Vec3<T> m = kin::cross(u, n);
      for (int k = 0; k < 3; ++k) {
        jinv[6 * i + k] = n[k];
        jinv[6 * i + 3 + k] = m[k];
      }
    }
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    const auto r = kin::rotationRpy(pose[3], pose[4], pose[5]);
    for (int i = 0; i < 6; ++i) {
      const kin::Vec3<T> b{g[platform(i, 0)], g[platform(i, 1)], g[platform(i, 2)]};
      const kin::Vec3<T> rb = kin::rotate(r, b);
      const kin::Vec3<T> d{pose[0] + rb[0] - g[base(i, 0)], pose[1] + rb[1] - g[base(i, 1)],
                           pose[2] + rb[2] - g[base(i, 2)]};
      joints[i] = kin::sqrt(kin::sqr(d[0]) + kin::sqr(d[1]) + kin::sqr(d[2]));
    }
  }
};

/// The description of a Gough platform given as a GoughGeometry (nominal values, half-widths as [-h, h], sensor
/// errors). @throws InvalidGeometry if geometry.validate() fails.
RobotDescription goughDescription(const GoughGeometry& geometry);
/// The GoughGeometry of a `gough` description (an asymmetric range [lo, hi] becomes its centre +- a covering
/// half-width, as model::applyCoordinateBound does). @throws InvalidGeometry if the result is invalid.
GoughGeometry goughGeometry(const RobotDescription& description);
/// The Gough platform through the generic path, KinematicModel<GoughKinematics> (the `gough` type uses the
/// hand-written GoughPlatform; the two are checked against each other in the tests and compared in the benches).
std::unique_ptr<RobotModel> makeGenericGough(const GoughGeometry& geometry);

}  // namespace model
}  // namespace pkm_accuracy
