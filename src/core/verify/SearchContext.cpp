#include "SearchContext.hpp"

#include <algorithm>

namespace pkm_accuracy {
namespace verify {

SearchContext::SearchContext(const model::RobotModel& model_, const domain::Domain& domain_,
                             const VerifierOptions& options_)
    : model(model_),
      domain(domain_),
      options(options_),
      method(options_.enclosure
                 ? options_.enclosure
                 : std::shared_ptr<const enclosure::ErrorEnclosure>(enclosure::makeEnclosure(options_.method))),
      n(model_.dof()),
      m(domain_.variables()),
      initial(domain_.initialBox()),
      params(model_.geometryParameterCount()) {
  minWidth = options.min_width.size() == m ? options.min_width : DVec(m);
  initWidth = DVec(m);
  for (int i = 0; i < m; ++i) {
    initWidth[i] = initial[i].upper() - initial[i].lower();
    if (options.min_width.size() != m) minWidth[i] = 1e-5 * initWidth[i];
  }
  hasThresholds = options.thresholds.size() == n;
  for (int p = 0; p < params; ++p) {
    geometryRange.push_back(model.geometryParameterRange(p));
    admissible.push_back(model.geometryParameterAdmissible(p));
  }
  int varying = 0;
  for (int i = 0; i < m; ++i) varying += initWidth[i] > 0.0 ? 1 : 0;
  // (Default: half the varying box variables, at least 2. Paper workspace at +-1 mm, 2 threads: with the halving
  // progress test 6 levels cost a stalled region 2^6 boxes before its faces: 0.5% above the maxima 1 337 649 boxes
  // in 90 s, against 118 799 in 8.1 s with 3 levels and 114 739 in 7.8 s with 2; 5% margins unchanged, 1-2%
  // margins within 1%; docs/design-notes.md.)
  stallLevels = options.tuning.stall_levels > 0 ? options.tuning.stall_levels : std::max(2, (varying + 1) / 2);
}

IVec SearchContext::thinBox(const DVec& t) const {
  IVec thin(m);
  for (int i = 0; i < m; ++i) thin[i] = Interval(t[i]);
  return thin;
}

double SearchContext::relativeVolume(const IVec& box) const {
  double v = 1.0;
  for (int i = 0; i < m; ++i)
    if (initWidth[i] > 0.0) v *= (box[i].upper() - box[i].lower()) / initWidth[i];
  return v;
}

double SearchContext::tolerance(double lowerBound) const {
  return options.alpha_relative ? options.alpha * lowerBound : options.alpha;
}

}  // namespace verify
}  // namespace pkm_accuracy
