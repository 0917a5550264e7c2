// 3-PRS parallel robot with vertical prismatic actuators, as templated kinematics (type `prs3`; docs/models.md).
//   Leg i (phi_i = 90, 210, 330 deg, u_i = (cos phi_i, sin phi_i, 0), t_i = (-sin phi_i, cos phi_i, 0)): a slider
//   moves along the vertical line through R_i u_i (base frame, z up); its height q_i is joint i (m). A revolute joint
//   on the slider, with horizontal axis t_i, carries a rod of length l_i to a spherical joint at the platform point
//   B_i = p + R b_i, b_i = r_p u_i (platform frame). The rod stays in the vertical plane through the slider line
//   that contains u_i, so B_i . t_i = 0 for i = 0, 1, 2: three constraints that leave three degrees of freedom.
//   pose X = (z, tilt_x, tilt_y): the height z of the platform centre p and the tilt of the platform, given by its
//   normal n = R z = Ry(tilt_y) Rx(tilt_x) z = (cos(tilt_x) sin(tilt_y), -sin(tilt_x), cos(tilt_x) cos(tilt_y)),
//   and R the rotation about a horizontal axis taking z to n (zero torsion): with k = z x n = (-n_y, n_x, 0),
//   R = I + [k]x + [k]x^2 / (1 + n_z) (Rodrigues' formula with sin = |k| and 1 - cos = |k|^2 / (1 + n_z): smooth
//   at zero tilt, no division by the tilt angle). For small tilts, tilt_x and tilt_y are rotations about x and y.
//   Parasitic motion: with this R, (R u_i) . t_i = (k . u_i)(k . t_i) / (1 + n_z), and the constraints p . t_i =
//   -r_p (k . u_i)(k . t_i) / (1 + n_z) hold for the three legs with p_x = -r_p k_x k_y / (1 + n_z), p_y = r_p (k_y^2
//   - k_x^2) / (2 (1 + n_z)) (for phi_i = 90 + 120 i deg, sin 2 phi_i = -cos phi_i and cos 2 phi_i = -sin phi_i, so
//   both sides are first harmonics in phi_i; three legs, two unknowns: the symmetric layout with one platform
//   radius is what makes the zero torsion consistent, and this type has exactly that layout).
//   Inverse kinematics: B_i . u_i = p . u_i + r_p (n_z + (k . u_i)^2 / (1 + n_z)), B_i,z = z + r_p (k_x u_i,y - k_y
//   u_i,x); rho_i = B_i . u_i - R_i (radial offset of B_i from the slider line), q_i = B_i,z - sqrt(l_i^2 - rho_i^2)
//   (the slider below the platform joint; unreachable where |rho_i| > l_i).
//   J^-1 = dq / d(z, tilt_x, tilt_y), the derivatives of the inverse kinematics (forward-mode, Dual<T, 3> over the
//   scalar type T the core instantiates the model with). Its first column is (1, 1, 1). Error components dz (m),
//   dtilt_x, dtilt_y (rad): the errors of the pose coordinates; sensor errors in m.
// Geometry values (m): base_radius[i] (R_i), rod_length[i] (l_i), platform_radius (r_p, one value for the three legs).
#pragma once

#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/model/KinematicsMath.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"

namespace pkm_accuracy {
namespace model {

struct Prs3Kinematics {
  static constexpr int kDof = 3;
  /// Geometry value indices.
  static constexpr int baseRadius(int leg) { return leg; }
  static constexpr int rodLength(int leg) { return 3 + leg; }
  static constexpr int kPlatformRadius = 6;
  static constexpr int kGeometryValues = 7;

  /// The type's components, joints and geometry values, with the nominal values of the reference robot
  /// (config/prs3.yaml) and no sensor errors.
  static RobotDescription description();

  /// The horizontal unit vectors u_i = (cos phi_i, sin phi_i), phi_i = 90, 210, 330 deg (cos 30 deg = sqrt(3/4),
  /// enclosed in the interval types).
  template <typename T>
  static void directions(T* ux, T* uy) {
    const T c30 = kin::sqrt(T(0.75));
    ux[0] = T(0.0);
    uy[0] = T(1.0);
    ux[1] = -c30;
    uy[1] = T(-0.5);
    ux[2] = c30;
    uy[2] = T(-0.5);
  }

  /// The platform centre p (base frame) at a pose: the parasitic motion (p_x, p_y) and z.
  template <typename T>
  static kin::Vec3<T> platformCentre(const T* pose, const T* g) {
    const T ca = kin::cos(pose[1]), sa = kin::sin(pose[1]), sb = kin::sin(pose[2]);
    const T kx = sa, ky = ca * sb, nz = ca * kin::cos(pose[2]);
    const T& rp = g[kPlatformRadius];
    const T f = rp / (nz + 1.0);
    return {-(f * kx * ky), f * (kin::sqr(ky) - kin::sqr(kx)) * 0.5, pose[0]};
  }

  template <typename T>
  void jointCoordinates(const T* pose, const T* g, T* joints) const {
    const T ca = kin::cos(pose[1]), sa = kin::sin(pose[1]), sb = kin::sin(pose[2]);
    const T kx = sa, ky = ca * sb, nz = ca * kin::cos(pose[2]);  // k = z x n, n_z
    const T& rp = g[kPlatformRadius];
    const T f = rp / (nz + 1.0);
    const T px = -(f * kx * ky), py = f * (kin::sqr(ky) - kin::sqr(kx)) * 0.5;
    T ux[3], uy[3];
    directions(ux, uy);
    for (int i = 0; i < 3; ++i) {
      const T ku = kx * ux[i] + ky * uy[i];
      const T rho = px * ux[i] + py * uy[i] + rp * nz + f * kin::sqr(ku) - g[baseRadius(i)];
      const T bz = pose[0] + rp * (kx * uy[i] - ky * ux[i]);
      joints[i] = bz - kin::sqrt(kin::sqr(g[rodLength(i)]) - kin::sqr(rho));
    }
  }

  template <typename T>
  void inverseJacobian(const T* pose, const T* g, T* jinv) const {
    using D = interval::Dual<T, 3>;
    D x[3], geometry[kGeometryValues], q[3];
    for (int a = 0; a < 3; ++a) x[a] = D::variable(pose[a], a);
    for (int v = 0; v < kGeometryValues; ++v) geometry[v] = D(g[v]);
    jointCoordinates(x, geometry, q);
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a) jinv[3 * i + a] = q[i].d(a);
  }
};

}  // namespace model
}  // namespace pkm_accuracy
