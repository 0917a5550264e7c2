// The workspace of any model as a box of its pose coordinates (identity pose map): each coordinate ranges over an
// interval (a single value fixes it). The search variables are the pose coordinates, named after the model's.
#pragma once

#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

class PoseBox final : public Domain {
 public:
  /// @param names one per coordinate, with its unit, e.g. "x [m]" (RobotModel::componentName).
  /// @throws InvalidArgument naming the bad range ("z [m]: expected a finite range ...") or a size mismatch.
  PoseBox(std::vector<std::string> names, const IVec& ranges);

  int variables() const override { return static_cast<int>(names_.size()); }
  int poseDimension() const override { return variables(); }
  std::string variableName(int i) const override;
  const IVec& initialBox() const override { return initial_; }
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  /// Inside when the box lies within the ranges, Outside when it misses them (exact comparisons).
  Containment classify(const IVec& box) const override;
  IVec poseAt(const DVec& t) const override;

 private:
  std::vector<std::string> names_;
  IVec initial_;
};

}  // namespace domain
}  // namespace pkm_accuracy
