// What a search path of the verifier carries from a box to its sub-boxes besides the box itself: the geometry sub-box
// it searches and the progress of its bound (the input of SplitPolicy's stall rule). Internal to the core.
#pragma once

#include <limits>
#include <memory>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace verify {

/// A sub-box of the geometry parameters (strategy (b)). The model restricted to it is built for each box searched
/// with it (RobotModel::restrictGeometry: a copy of the model, cheap next to an enclosure), not kept: frontier boxes
/// carry only the ranges.
struct GeometryPart {
  std::vector<Interval> ranges;
  int splits = 0;         ///< geometry bisections on the path to it
  double fraction = 1.0;  ///< its share of the initial geometry box volume
};

/// What a search path carries besides its box: the geometry sub-box (null: every admissible geometry) and the
/// progress of its bound (the excess over the target at the last improvement, and levels since).
struct SearchPath {
  std::shared_ptr<const GeometryPart> geometry;
  double ref = std::numeric_limits<double>::infinity();
  int since = 0;
  enclosure::SignPattern signs;    ///< signs of J certified on the parent box (inherited by its sub-boxes)
  enclosure::GeometryFaces faces;  ///< geometry monotonicity certified on the parent box (for the path's model)
  bool useFaces = false;           ///< the path stalled: bound its components on their faces (BoxInput::useFaces)
  DVec upper;                      ///< the parent box's upper bounds (valid for its sub-boxes; empty at the root)
};

}  // namespace verify
}  // namespace pkm_accuracy
