// Clavel's Delta robot with three rotary actuators, as templated kinematics (type `delta3`; docs/models.md).
//   pose X = (x, y, z) of the travelling plate's centre p (base frame, z up, the plate below the base: z < 0); the
//   plate only translates. Leg i: motor axis at A_i = R_i u_i, u_i = (cos phi_i, sin phi_i, 0), horizontal and
//   perpendicular to u_i; crank (upper arm) of length L_i at angle theta_i below the horizontal plane (joint i, rad),
//   elbow C_i = A_i + L_i w_i, w_i = cos(theta_i) u_i - sin(theta_i) z; forearm (parallelogram) of length l_i from C_i
//   to P_i = p + r_i u_i.
//   Inverse kinematics: with d_i = P_i - A_i, a = d_i . u_i, b = -d_i . z, K = (|d_i|^2 + L_i^2 - l_i^2) / (2 L_i),
//   a cos(theta) + b sin(theta) = K; the elbow-out solution is cos(theta) = (a K + b D) / rho^2,
//   sin(theta) = (b K - a D) / rho^2, rho^2 = a^2 + b^2, D = sqrt(rho^2 - K^2) (unreachable where rho^2 < K^2).
//   J^-1: from |d_i - L_i w_i|^2 = l_i^2, d theta_i = s_i . dp / (L_i s_i . w_i'), s_i = P_i - C_i (the forearm),
//   w_i' = -sin(theta_i) u_i - cos(theta_i) z: row i of J^-1 = s_i^T / (L_i s_i . w_i').
// Error components dx, dy, dz (m); sensor errors in rad. Geometry values per leg i (m, rad): base_radius[i] (R_i),
// platform_radius[i] (r_i), upper_arm_length[i] (L_i), forearm_length[i] (l_i), motor_angle[i] (phi_i).
#pragma once

#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace model {

struct Delta3Kinematics {
  static constexpr int kDof = 3;
  static constexpr int baseRadius(int leg) { return leg; }
  static constexpr int platformRadius(int leg) { return 3 + leg; }
  static constexpr int upperArm(int leg) { return 6 + leg; }
  static constexpr int forearm(int leg) { return 9 + leg; }
  static constexpr int motorAngle(int leg) { return 12 + leg; }

  static RobotDescription description();

  /// The leg's quantities every function needs: u_i, d_i, and cos / sin of the crank angle.
  template <typename T>
  struct Leg {
    kin::Vec3<T> u, d;
    T cosTheta, sinTheta;
  };

  template <typename T>
  static Leg<T> leg(const T* pose, const T* g, int i) {
    Leg<T> out;
    const T& phi = g[motorAngle(i)];
    const T cphi = kin::cos(phi), sphi = kin::sin(phi);
    out.u = {cphi, sphi, T(0.0)};
    const T offset = g[platformRadius(i)] - g[baseRadius(i)];
    out.d = {pose[0] + offset * cphi, pose[1] + offset * sphi, pose[2]};
    const T& arm = g[upperArm(i)];
    const T a = offset + pose[0] * cphi + pose[1] * sphi;  // d . u
    const T b = -pose[2];                                  // -d . z
    const T rho2 = kin::sqr(a) + kin::sqr(b);
    const T k =
        (kin::sqr(out.d[0]) + kin::sqr(out.d[1]) + kin::sqr(out.d[2]) + kin::sqr(arm) - kin::sqr(g[forearm(i)])) /
        (arm * 2.0);
    const T disc = kin::sqrt(rho2 - kin::sqr(k));
    out.cosTheta = (a * k + b * disc) / rho2;
    out.sinTheta = (b * k - a * disc) / rho2;
    return out;
  }

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    for (int i = 0; i < 3; ++i) {
      const Leg<T> l = leg(pose, g, i);
      const T& arm = g[upperArm(i)];
      // s = d - L w (the forearm), w' = -sin u - cos z.
      const kin::Vec3<T> s{l.d[0] - arm * l.cosTheta * l.u[0], l.d[1] - arm * l.cosTheta * l.u[1],
                           l.d[2] + arm * l.sinTheta};
      const T sw = -(l.sinTheta * (s[0] * l.u[0] + s[1] * l.u[1])) - l.cosTheta * s[2];
      const T den = arm * sw;
      for (int k = 0; k < 3; ++k) jinv[3 * i + k] = s[k] / den;
    }
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    for (int i = 0; i < 3; ++i) {
      const Leg<T> l = leg(pose, g, i);
      joints[i] = kin::atan2(l.sinTheta, l.cosTheta);
    }
  }
};

}  // namespace model
}  // namespace pkm_accuracy
