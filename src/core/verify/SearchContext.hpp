// The verifier's fixed inputs for one run, shared read-only by every unit of the search (thread-safe: nothing in it
// changes after construction): the model, the domain, the options, the enclosure method, the initial box and the
// derived widths, the geometry parameters' ranges, and the stall depth. Internal to the core.
#pragma once

#include <limits>
#include <memory>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"

namespace pkm_accuracy {
namespace verify {

constexpr double kInf = std::numeric_limits<double>::infinity();

class SearchContext {
 public:
  /// The options must have passed Verifier::validate().
  SearchContext(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& options);

  /// The degenerate box of a point of the variables.
  IVec thinBox(const DVec& t) const;
  /// The box's share of the initial box volume (over the variables of non-zero initial width).
  double relativeVolume(const IVec& box) const;
  /// Max-error mode: the tolerance alpha at a lower bound (absolute, or relative to it).
  double tolerance(double lowerBound) const;

  const model::RobotModel& model;
  const domain::Domain& domain;
  const VerifierOptions& options;
  const std::shared_ptr<const enclosure::ErrorEnclosure> method;  ///< options.enclosure, else options.method's
  const int n;                                                    ///< error components (model.dof())
  const int m;                                                    ///< box variables
  const IVec initial;                                             ///< the domain's initial box
  DVec initWidth;                                                 ///< its widths
  DVec minWidth;                        ///< the precision limit of each variable (options.min_width, else 1e-5 x width)
  bool hasThresholds = false;           ///< options.thresholds gives one value per component
  const int params;                     ///< uncertain geometry parameters of the model
  std::vector<Interval> geometryRange;  ///< their initial ranges
  std::vector<Interval> admissible;     ///< their admissible values (inside the ranges; reported points lie in them)
  int stallLevels = 2;                  ///< levels without progress before a path switches strategy (SplitPolicy)
};

}  // namespace verify
}  // namespace pkm_accuracy
