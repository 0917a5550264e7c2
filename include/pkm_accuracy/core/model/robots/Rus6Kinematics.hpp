// 6-RUS hexapod with rotary actuators, as templated kinematics (type `rus6`; docs/models.md).
//   pose X = (x, y, z, roll, pitch, yaw) of the platform frame: p its origin (base frame), R = Rz(yaw) Ry(pitch)
//   Rx(roll); errors as for the Gough platform: dX = displacement of the tool point c (platform frame) and small
//   rotation vector, both in the base frame (m, rad).
//   Leg i: a motor turns a crank of radius r_i about a horizontal axis through the pivot A_i (base frame) with
//   direction (cos beta_i, sin beta_i, 0); the crank moves in the vertical plane spanned by e1_i = (-sin beta_i,
//   cos beta_i, 0) and z, its end is C_i = A_i + r_i w_i(theta_i), w(theta) = cos(theta) e1 + sin(theta) z (joint i:
//   the crank angle theta_i, rad, 0 with the crank along e1_i, positive upwards). A rod of length l_i joins C_i by a
//   universal joint to the platform anchor B_i = p + R b_i by a spherical joint.
//   Inverse kinematics: with d_i = B_i - A_i, |d_i - r_i w_i|^2 = l_i^2 reads a cos(theta) + h sin(theta) = K with
//   a = d_i . e1_i, h = d_i . z, K = (|d_i|^2 + r_i^2 - l_i^2) / (2 r_i). Its solutions are cos(theta) = (a K +- h D)
//   / rho^2, sin(theta) = (h K -+ a D) / rho^2, rho^2 = a^2 + h^2, D = sqrt(rho^2 - K^2) (no solution where
//   rho^2 < K^2: the pose is out of reach). This model takes the upper signs: then s_i . w_i'(theta_i) = -a sin + h
//   cos = D >= 0 for the rod s_i = B_i - C_i and w'(theta) = -sin(theta) e1 + cos(theta) z: the rod makes an acute
//   angle with the direction in which the crank end moves as theta grows (a crank near horizontal has its rod going
//   up from its end: the reference robot's assembly). D = 0 is the leg's serial singularity (rod along the crank).
//   J^-1: differentiating |B_i - C_i|^2 = l_i^2, s_i . (dB_i - r_i w_i' dtheta_i) = 0 with dB_i = dt + omega x
//   R (b_i - c) (dt the tool point's displacement, omega the small rotation), so dtheta_i = (s_i . dt + ((R (b_i -
//   c)) x s_i) . omega) / (r_i s_i . w_i'): row i of J^-1 = [s_i^T, ((R (b_i - c)) x s_i)^T] / (r_i D_i).
// Geometry values (m, rad): base_pivots[i].{x,y,z} (A_i), crank_axis_angle[i] (beta_i), crank_radius[i] (r_i),
// rod_length[i] (l_i), platform_anchors[i].{x,y,z} (b_i, platform frame), tool_point.{x,y,z} (c, platform frame).
#pragma once

#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace model {

struct Rus6Kinematics {
  static constexpr int kDof = 6;
  /// Geometry value indices.
  static constexpr int basePivot(int leg, int axis) { return 3 * leg + axis; }
  static constexpr int crankAxisAngle(int leg) { return 18 + leg; }
  static constexpr int crankRadius(int leg) { return 24 + leg; }
  static constexpr int rodLength(int leg) { return 30 + leg; }
  static constexpr int platformAnchor(int leg, int axis) { return 36 + 3 * leg + axis; }
  static constexpr int tool(int axis) { return 54 + axis; }
  static constexpr int kGeometryValues = 57;

  /// The type's components, joints and geometry values, with the nominal values of the reference robot
  /// (config/rus6.yaml) and no sensor errors.
  static RobotDescription description();

  /// One leg at a pose: u = R (b - c), d = B - A, e1, the crank's a, h (coordinates of d in the crank plane), K,
  /// rho^2 and D; cos / sin of the crank angle times rho^2 (the positive factor left out where it does not matter).
  template <typename T>
  struct Leg {
    kin::Vec3<T> u, d, e1;
    T a, h, k, rho2, disc;
    T cosTimesRho2() const { return a * k + h * disc; }
    T sinTimesRho2() const { return h * k - a * disc; }
  };

  /// Leg i, given R and R c (B = p + R c + R (b - c): one rotation of b - c per leg serves both B and the moment arm).
  template <typename T>
  static Leg<T> leg(const T* pose, const T* g, const std::array<kin::Vec3<T>, 3>& r, const kin::Vec3<T>& rc, int i) {
    Leg<T> l;
    const kin::Vec3<T> bc{g[platformAnchor(i, 0)] - g[tool(0)], g[platformAnchor(i, 1)] - g[tool(1)],
                          g[platformAnchor(i, 2)] - g[tool(2)]};
    l.u = kin::rotate(r, bc);
    for (int k = 0; k < 3; ++k) l.d[k] = pose[k] + rc[k] + l.u[k] - g[basePivot(i, k)];
    const T& beta = g[crankAxisAngle(i)];
    l.e1 = {-kin::sin(beta), kin::cos(beta), T(0.0)};
    const T& crank = g[crankRadius(i)];
    l.a = l.d[0] * l.e1[0] + l.d[1] * l.e1[1];
    l.h = l.d[2];
    l.k = (kin::sqr(l.d[0]) + kin::sqr(l.d[1]) + kin::sqr(l.d[2]) + kin::sqr(crank) - kin::sqr(g[rodLength(i)])) /
          (crank * 2.0);
    l.rho2 = kin::sqr(l.a) + kin::sqr(l.h);
    l.disc = kin::sqrt(l.rho2 - kin::sqr(l.k));
    return l;
  }

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    const auto r = kin::rotationRpy(pose[3], pose[4], pose[5]);
    const kin::Vec3<T> rc = kin::rotate(r, kin::Vec3<T>{g[tool(0)], g[tool(1)], g[tool(2)]});
    for (int i = 0; i < 6; ++i) {
      const Leg<T> l = leg(pose, g, r, rc, i);
      const T& crank = g[crankRadius(i)];
      // The crank end relative to the pivot, r w = r (cos e1 + sin z), and the rod s = d - r w.
      const T f = crank / l.rho2;
      const T rcos = f * l.cosTimesRho2(), rsin = f * l.sinTimesRho2();
      const kin::Vec3<T> s{l.d[0] - rcos * l.e1[0], l.d[1] - rcos * l.e1[1], l.d[2] - rsin};
      const kin::Vec3<T> m = kin::cross(l.u, s);
      const T den = crank * l.disc;
      for (int k = 0; k < 3; ++k) {
        jinv[6 * i + k] = s[k] / den;
        jinv[6 * i + 3 + k] = m[k] / den;
      }
    }
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    const auto r = kin::rotationRpy(pose[3], pose[4], pose[5]);
    const kin::Vec3<T> rc = kin::rotate(r, kin::Vec3<T>{g[tool(0)], g[tool(1)], g[tool(2)]});
    for (int i = 0; i < 6; ++i) {
      const Leg<T> l = leg(pose, g, r, rc, i);
      joints[i] = kin::atan2(l.sinTimesRho2(), l.cosTimesRho2());
    }
  }
};

}  // namespace model
}  // namespace pkm_accuracy
