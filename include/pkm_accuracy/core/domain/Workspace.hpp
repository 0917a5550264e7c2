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
  /// Largest |bound| of an orientation range (rad): 2 pi. Angles are periodic, so a range within [-2 pi, 2 pi]
  /// covers any set of orientations (also ranges written in [0, 2 pi]); a bound beyond it is a unit mistake
  /// (degrees) more often than an intent.
  static constexpr double kMaxAngle = 6.283185307179586;
  /// @param region the position region; its bounding box gives the x, y, z ranges.
  /// @param orientation roll, pitch, yaw ranges (rad).
  /// @throws InvalidArgument if an orientation range is empty, inverted or not finite, or reaches beyond +-kMaxAngle.
  Workspace(PositionRegion region, const std::array<Interval, 3>& orientation);
  /// A box workspace from six ranges (x, y, z in m; roll, pitch, yaw in rad).
  /// @throws InvalidArgument naming the bad range.
  static Workspace fromRanges(const std::array<Interval, 6>& ranges);

  int variables() const override { return 6; }
  int poseDimension() const override { return 6; }
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
