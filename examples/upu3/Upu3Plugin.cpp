// A user's own robot without touching the core: a translational 3-UPU parallel robot, registered as type `upu3`
// from a shared library that pkm_verify loads with --plugin (docs/models.md, "Your own robot").
//
//   pose X = (x, y, z) of the platform's centre p (base frame); the platform only translates.
//   Leg i: a prismatic actuator between base anchor A_i and platform anchor b_i (platform frame), length
//   L_i = |p + b_i - A_i| (joint i, m). Differentiating L_i^2 = d_i . d_i with d_i = p + b_i - A_i gives
//   L_i dL_i = d_i . dp: row i of J^-1 = n_i^T with n_i = d_i / L_i.
#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"

namespace {

namespace kin = pkm_accuracy::model::kin;

struct Upu3Kinematics {
  static constexpr int kDof = 3;

  // Geometry values, in the order of description(): base_anchors[i].{x,y,z}, then platform_anchors[i].{x,y,z}.
  template <typename T>
  static kin::Vec3<T> leg(const T* pose, const T* g, int i) {
    const T* a = g + 3 * i;
    const T* b = g + 9 + 3 * i;
    return {pose[0] + b[0] - a[0], pose[1] + b[1] - a[1], pose[2] + b[2] - a[2]};
  }

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    for (int i = 0; i < 3; ++i) {
      const kin::Vec3<T> d = leg(pose, g, i);
      const T length = kin::sqrt(kin::dot(d, d));
      for (int k = 0; k < 3; ++k) jinv[3 * i + k] = d[k] / length;
    }
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    for (int i = 0; i < 3; ++i) {
      const kin::Vec3<T> d = leg(pose, g, i);
      joints[i] = kin::sqrt(kin::dot(d, d));
    }
  }

  static pkm_accuracy::model::RobotDescription description() {
    pkm_accuracy::model::RobotDescription d;
    d.type = "upu3";
    d.pose = {{"x", "m", false}, {"y", "m", false}, {"z", "m", false}};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) d.joints.push_back({"leg_" + std::to_string(i), "m"});
    for (const char* group : {"base_anchors", "platform_anchors"})
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          d.geometry.push_back({std::string(group) + "[" + std::to_string(i) + "]." + axis[k], "m"});
    return d;
  }
};

}  // namespace

extern "C" void pkm_accuracy_register_models(pkm_accuracy::model::ModelRegistry& registry) {
  registry.addKinematics<Upu3Kinematics>("translational 3-UPU robot, 3 prismatic legs, pose x y z (example plugin)",
                                         Upu3Kinematics::description());
}
