// Workspace of a planar robot (pose (x, y, theta), docs/planar3rpr.md). The search variables are the pose coordinates
// themselves (identity pose map). The position region is the x/y box of the ranges, or optionally a disc
// (x - cx)^2 + (y - cy)^2 <= r^2; the theta range is a box. A range may be a single value (fixed coordinate).
#pragma once

#include <array>

#include <Eigen/Core>

#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

class PlanarWorkspace final : public Domain {
 public:
  /// A box workspace from three ranges (x, y in m; theta in rad).
  /// @throws InvalidArgument naming the bad range ("theta: expected a finite range ...").
  static PlanarWorkspace fromRanges(const std::array<Interval, 3>& ranges);
  /// The disc of the given centre (m) and radius (m, > 0) times a theta range (rad); the x/y ranges of the search
  /// box are the disc's bounding box (rounded outward).
  /// @throws InvalidArgument naming the bad value.
  static PlanarWorkspace disc(const Eigen::Vector2d& centre, double radius, const Interval& theta);

  int variables() const override { return 3; }
  int poseDimension() const override { return 3; }
  std::string variableName(int i) const override;
  const IVec& initialBox() const override { return initial_; }
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  /// Box workspace: Inside when the box is within the ranges (Outside when it misses them). Disc: certified
  /// interval test of the disc inequality.
  Containment classify(const IVec& box) const override;
  IVec poseAt(const DVec& t) const override;

  bool isDisc() const { return disc_; }
  const Eigen::Vector2d& discCentre() const { return centre_; }
  double discRadius() const { return radius_; }

 private:
  PlanarWorkspace() = default;
  IVec initial_;
  bool disc_ = false;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double radius_ = 0.0;
};

}  // namespace domain
}  // namespace pkm_accuracy
