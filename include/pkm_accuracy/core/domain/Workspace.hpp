// A workspace: orientation ranges (roll, pitch, yaw) times a position region. The search variables are the pose
// coordinates themselves (x, y, z, roll, pitch, yaw); a range may be a single value (fixed coordinate).
#pragma once

#include <array>

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"

namespace pkm_accuracy {
namespace domain {

class Workspace final : public Domain {
 public:
  /// @param region the position region; its bounding box gives the x, y, z ranges.
  /// @param orientation roll, pitch, yaw ranges (rad).
  /// @throws InvalidArgument if an orientation range is empty, inverted or not finite.
  Workspace(PositionRegion region, const std::array<Interval, 3>& orientation);
  /// A box workspace from six ranges (x, y, z in m; roll, pitch, yaw in rad).
  /// @throws InvalidArgument naming the bad range.
  static Workspace fromRanges(const std::array<Interval, 6>& ranges);

  int variables() const override { return 6; }
  std::string variableName(int i) const override;
  const IVec& initialBox() const override { return initial_; }
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  Containment classify(const IVec& box) const override;
  IVec poseAt(const DVec& t) const override;

  const PositionRegion& region() const { return region_; }

 private:
  PositionRegion region_;
  IVec initial_;
};

}  // namespace domain
}  // namespace pkm_accuracy
