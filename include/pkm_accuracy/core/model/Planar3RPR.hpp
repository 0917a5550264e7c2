// Planar 3-RPR parallel robot (conventions: docs/planar3rpr.md).
//   pose X = (x, y, theta), R = R(theta) the 2-D rotation, B_i = p + R b_i, n_i = (B_i - A_i) / |B_i - A_i|,
//   row i of J^-1 = [n_i^T, (R (b_i - c)) x n_i] with the scalar 2-D cross product u x v = u_x v_y - u_y v_x.
// Error components: displacement of the tool point along x and y (m) and rotation of the platform (rad).
#pragma once

#include <array>

#include "pkm_accuracy/core/model/Planar3RPRGeometry.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace model {

class Planar3RPR final : public RobotModel {
 public:
  /// @throws InvalidGeometry if geometry.validate() fails.
  explicit Planar3RPR(Planar3RPRGeometry geometry);

  int dof() const override { return 3; }
  std::string name() const override { return "planar3rpr"; }
  std::string componentName(int k) const override;
  bool isAngular(int k) const override { return k == 2; }
  const std::vector<double>& sensorError() const override { return geometry_.sensor_error; }
  /// The planar model has no geometric uncertainty (the geometry is known exactly).
  bool hasGeometryUncertainty() const override { return false; }
  const Planar3RPRGeometry& geometry() const { return geometry_; }

  DMat inverseJacobian(const DVec& pose) const override;
  DVec legLengths(const DVec& pose) const override;
  IMat inverseJacobian(const IVec& pose) const override;
  /// Value and derivatives of J^-1 (3x3) with respect to the box variables; out.d has kMaxDof matrices, the ones of
  /// variables the pose does not depend on are zero.
  void inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const override;

  /// Enclosure of the leg lengths over a pose box.
  IVec legLengths(const IVec& pose) const;

 private:
  Planar3RPRGeometry geometry_;
  // Anchors and tool point as (degenerate) intervals for the enclosures, and as doubles for point evaluation.
  std::array<std::array<Interval, 2>, 3> a_, b_;
  std::array<Interval, 2> c_;
  std::array<std::array<double, 2>, 3> ad_, bd_;
  std::array<double, 2> cd_;
};

}  // namespace model
}  // namespace pkm_accuracy
