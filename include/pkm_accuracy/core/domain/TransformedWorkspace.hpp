// A workspace given in a frame F that is rigidly fixed to the robot's base frame. The search variables are the
// workspace's own (x, y, z, roll, pitch, yaw of the platform frame in F, classified against the workspace's region in
// F); the poses handed to the model are in the base frame:
//   p_base = t + R_T p_F,   R_base = R_T R_F,   T = (R_T, t) = base_from_F (the pose of F in the base frame).
// The domain is exactly the image of the workspace under T (no enclosing box of it): poseView() maps every box of
// variables to base-frame poses in interval arithmetic, with the gradient with respect to the variables (Dual).
//
// Supported transforms: any translation combined with a rotation about the z axis, R_T = Rz(a). Then
// Rz(a) Rz(yaw) Ry(pitch) Rx(roll) = Rz(a + yaw) Ry(pitch) Rx(roll) exactly, so roll and pitch are unchanged and
// yaw_base = yaw + a. Any other rotation is refused (InvalidArgument): the roll/pitch/yaw of R_T R_F need rigorous
// interval atan2/asin, which the core does not have yet.
//
// What "exactly" means in floating point: the translation is used as given; the rotation is the exact rotation by
// the double angle a = atan2(R(1,0), R(0,0)) (the given matrix, an orthonormal double matrix whose off-z entries
// R(0,2), R(1,2), R(2,0), R(2,1) are exactly 0, is within a few 1e-16 of it); cos a and sin a are certified
// enclosures. Every pose of the domain is enclosed, every enclosure is certified.
#pragma once

#include <string>

#include <Eigen/Core>

#include "pkm_accuracy/core/domain/Workspace.hpp"

namespace pkm_accuracy {
namespace domain {

/// A rigid transform base_from_F: a point p_F of F is t + R p_F in the base frame; a rotation R_F of F is R R_F.
struct RigidTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< R (orthonormal, determinant +1)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< t (m): the origin of F in the base frame

  /// (t, Rz(yaw)) with the rotation matrix computed in double (its off-z entries are exactly 0).
  static RigidTransform fromTranslationYaw(const Eigen::Vector3d& translation, double yaw);
};

class TransformedWorkspace final : public Domain {
 public:
  /// Largest deviation of R^T R from the identity accepted as "orthonormal".
  static constexpr double kOrthonormalityTolerance = 1e-9;

  /// @param workspace the workspace in frame F (region and angle ranges)
  /// @param base_from_frame the pose of F in the base frame
  /// @throws InvalidArgument if the translation or rotation is not finite, the rotation is not a rotation matrix
  ///         (orthonormal within kOrthonormalityTolerance, determinant +1), or it is not a rotation about the z axis
  ///         (the message says which and by how much the z axis is tilted).
  TransformedWorkspace(Workspace workspace, const RigidTransform& base_from_frame);

  int variables() const override { return 6; }
  /// The workspace's names ("x [m]", ..., "yaw [rad]"): coordinates in frame F.
  std::string variableName(int i) const override { return workspace_.variableName(i); }
  /// The workspace's initial box (in frame F).
  const IVec& initialBox() const override { return workspace_.initialBox(); }
  /// Base-frame poses of the box (pose, centrePose) and their gradient with respect to the frame-F variables.
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  /// The workspace's classification (the region is in frame F).
  Containment classify(const IVec& box) const override { return workspace_.classify(box); }
  /// Enclosure of the base-frame pose of a point of the variables.
  IVec poseAt(const DVec& t) const override;

  const Workspace& workspace() const { return workspace_; }
  /// The rotation angle a about z of the transform actually used (rad).
  double yawOffset() const { return yaw_; }
  const Eigen::Vector3d& translation() const { return translation_; }

 private:
  template <typename S>
  void map(const S in[6], S out[6]) const;

  Workspace workspace_;
  Eigen::Vector3d translation_;
  double yaw_ = 0.0;
  bool rotate_ = false;  ///< yaw_ != 0 (otherwise x, y, yaw pass through unchanged)
  Interval cos_ = Interval(1.0), sin_ = Interval(0.0);
};

}  // namespace domain
}  // namespace pkm_accuracy
