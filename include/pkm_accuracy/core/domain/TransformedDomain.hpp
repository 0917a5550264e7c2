// A domain (a workspace, a trajectory, any motion variety) whose poses are given in a frame F that is rigidly fixed to
// the robot's base frame. The search variables are the inner domain's own (for a workspace: x, y, z, roll, pitch, yaw
// of the platform frame in F, classified against the workspace's region in F; for a trajectory: its parameter); the
// poses handed to the model are in the base frame:
//   p_base = t + R_T p_F,   R_base = R_T R_F,   T = (R_T, t) = base_from_F (the pose of F in the base frame).
// The domain is exactly the image of the inner domain under T (no enclosing box of it): poseView() maps the inner
// domain's enclosures of the poses of a box of variables (and their gradient with respect to the variables, Dual) to
// base-frame poses in interval arithmetic.
//
// Two cases:
//   * R_T a rotation about z, R_T = Rz(a): Rz(a) Rz(yaw) Ry(pitch) Rx(roll) = Rz(a + yaw) Ry(pitch) Rx(roll)
//     exactly, so roll and pitch are unchanged and yaw_base = yaw + a (cheap and tight; the identity transform gives
//     the inner domain's own poses bit for bit);
//   * any other rotation: the base-frame roll, pitch, yaw are the principal RPY of N = R_T R_F through rigorous
//     interval atan2 (interval/InverseTrig.hpp): roll = atan2(N21, N22), pitch = atan2(-N20, sqrt(N00^2 + N10^2)),
//     yaw = atan2(N10, N00). Roll and yaw are measured from reference angles taken at the box's centre pose, so a box
//     whose base-frame roll or yaw crosses +-pi is not blown up to [-pi, pi] (the model only uses their sine and
//     cosine, so any representative modulo 2 pi is the same pose). Near base-frame pitch = +-pi/2 (gimbal lock) roll
//     and yaw are undefined and their enclosures and derivative enclosures blow up (sound; the verifier then needs many
//     boxes there or leaves them undecided).
//
// What "exactly" means in floating point: the translation is used as given; the rotation is the exact rotation
// Rz(c) Ry(b) Rx(a) of the double angles (a, b, c) = RPY of the given matrix R (roll = atan2(R21, R22), pitch =
// atan2(-R20, hypot(R00, R10)), yaw = atan2(R10, R00), evaluated in double; it is within a few 1e-16 of an
// orthonormal R, and must be within kOrthonormalityTolerance of R); its sines and cosines are certified enclosures.
// A rotation about z (R20 = R21 = 0 exactly, as for every tf2 quaternion with x = y = 0) has a = b = 0. Every pose of
// the domain is enclosed, every enclosure is certified.
#pragma once

#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

/// A rigid transform base_from_F: a point p_F of F is t + R p_F in the base frame; a rotation R_F of F is R R_F.
struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< R (orthonormal, determinant +1)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< t (m): the origin of F in the base frame

  /// (t, Rz(yaw)) with the rotation matrix computed in double (its off-z entries are exactly 0).
  static RigidTransform fromTranslationYaw(const Eigen::Vector3d& translation, double yaw);
  /// (t, Rz(yaw) Ry(pitch) Rx(roll)) with the rotation matrix computed in double.
  static RigidTransform fromTranslationRpy(const Eigen::Vector3d& translation, double roll, double pitch, double yaw);
};

class TransformedDomain : public Domain {
 public:
  /// Largest deviation of R^T R from the identity, and of the rotation used from R, accepted.
  static constexpr double kOrthonormalityTolerance = 1e-9;

  /// @param inner the domain in frame F (its variables, region and poses in F); not null, of rigid-body poses (6)
  /// @param base_from_frame the pose of F in the base frame
  /// @throws InvalidArgument if inner is null or its poses do not have 6 coordinates, the translation or rotation is
  ///         not finite or the rotation is not a rotation matrix (orthonormal within kOrthonormalityTolerance,
  ///         determinant +1); the message names which.
  TransformedDomain(std::shared_ptr<const Domain> inner, const RigidTransform& base_from_frame);

  /// The inner domain's variables, names and initial box (in frame F).
  int variables() const override { return inner_->variables(); }
  /// 6: the rigid-body pose (x, y, z, roll, pitch, yaw) in the base frame.
  int poseDimension() const override { return 6; }
  std::string variableName(int i) const override { return inner_->variableName(i); }
  const IVec& initialBox() const override { return inner_->initialBox(); }
  /// Base-frame poses of the box (pose, centrePose) and their gradient with respect to the variables.
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  /// The inner domain's classification (its region is in frame F).
  Containment classify(const IVec& box) const override { return inner_->classify(box); }
  /// Enclosure of the base-frame pose of a point of the variables.
  IVec poseAt(const DVec& t) const override;

  /// The domain in frame F.
  const Domain& inner() const { return *inner_; }
  /// Roll, pitch, yaw of the rotation R_T actually used (rad).
  const std::array<double, 3>& rotationRpy() const { return rpy_; }
  /// True when R_T is a rotation about z (roll = pitch = 0: the cheap exact case).
  bool aboutZ() const { return aboutZ_; }
  /// The rotation angle about z of the transform when aboutZ() (rad).
  double yawOffset() const { return rpy_[2]; }
  const Eigen::Vector3d& translation() const { return translation_; }
  /// "frame (translation [x, y, z] m, rpy [roll, pitch, yaw] rad)": the translation and the angles used (for reports).
  std::string frameDescription() const;

 private:
  /// Reference angles (roll, yaw) of the base-frame orientation, in double, for a frame-F orientation (roll, pitch,
  /// yaw).
  std::array<double, 2> referenceAngles(double roll, double pitch, double yaw) const;
  /// The reference angles for the frame-F poses `in` (at their midpoints; unused when aboutZ_).
  std::array<double, 2> referenceAnglesAt(const IVec& in) const;
  /// Maps frame-F poses (Interval or DualI) to base-frame poses in place.
  template <typename S>
  void map(S pose[6], const std::array<double, 2>& ref) const;

  std::shared_ptr<const Domain> inner_;  ///< (shared: a caller may keep using the domain in F, e.g. for its times)
  Eigen::Vector3d translation_;
  std::array<double, 3> rpy_{};
  bool aboutZ_ = true;
  bool rotate_ = false;  ///< aboutZ_ and yaw != 0 (otherwise x, y, yaw pass through unchanged)
  Interval cos_ = Interval(1.0), sin_ = Interval(0.0);  ///< aboutZ_: cos and sin of the yaw
  std::array<std::array<Interval, 3>, 3> r_;            ///< general case: enclosure of the entries of Rz(c) Ry(b) Rx(a)
  Eigen::Matrix3d rd_ = Eigen::Matrix3d::Identity();    ///< the same in double (reference angles only)
};

}  // namespace domain
}  // namespace pkm_accuracy
