#include "BoxBounder.hpp"

#include <algorithm>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {

BoxBounder::BoxBounder(const SearchContext& context, SearchState& state, const PointEvaluator& points)
    : c_(context), state_(state), points_(points), selfCheck_(context.domain, context.method->name()) {}

void BoxBounder::bound(const model::RobotModel& model, const IVec& box, domain::Containment where, unsigned active,
                       const SearchPath& track, enclosure::BoxInput& in, enclosure::ErrorBounds& bounds) const {
  c_.domain.poseView(box, c_.method->needsGradient(), in);
  in.knownSigns = track.signs;
  in.faces = track.faces;
  in.useFaces = track.useFaces;
  // (The decomposed form except on the paths bounded on their faces: the combined one certifies the monotone
  // directions the faces need. Geometry halves (strategy (b), Auto and Always) take the decomposed form about their
  // own centre: with the sign-coupled second-order terms it is the tighter one there too, and its
  // first-order coefficients give the geometry hints. The 1/32 corner box at +-1 mm, 0.4% above its sampled
  // maxima: Auto SAFE after 183 boxes (32 geometry splits), UNDECIDED after 2e4 with the combined form on the halves;
  // Always on the 1/128 corner box SAFE after 819 boxes, UNDECIDED after 2e4 with the combined form.)
  in.decomposeGeometry = c_.options.tuning.decompose_geometry && !track.useFaces;
  in.rows = active;  // components decided on a containing box need no bound here
  in.targets.resize(c_.n);
  for (int k = 0; k < c_.n; ++k) in.targets[k] = state_.target(k);
  c_.method->enclose(model, in, bounds);
  state_.counters.boxes.fetch_add(1, std::memory_order_relaxed);
  if (track.useFaces) state_.counters.faceBoxes.fetch_add(1, std::memory_order_relaxed);
  state_.maybeReportProgress();
  if (c_.options.monotonicity && where == domain::Containment::Inside)
    tightenByGradient(model, box, in, bounds, active);
  if (c_.options.self_check) selfCheck(model, box, active, bounds, track);
}

void BoxBounder::tightenByGradient(const model::RobotModel& model, const IVec& box, enclosure::BoxInput& in,
                                   enclosure::ErrorBounds& bounds, unsigned active) const {
  // The derivatives come from the interval form's internals (BoxInput::keepInternals), a second enclosure of the
  // box for the components the first one leaves open only: asking the first one for them would replace the affine
  // second-order form by that looser one everywhere (paper workspace, 5% margins: 2 319 -> 1.38e6 boxes).
  // (Exact geometry only: with an uncertain one, the second-order form that bounds the box keeps no internals.)
  if (model.hasGeometryUncertainty()) return;
  unsigned open = 0;
  for (int k = 0; k < c_.n; ++k)
    if ((active & (1u << k)) && !(bounds.upper[k] <= state_.target(k))) open |= 1u << k;
  if (open == 0) return;
  enclosure::ErrorBounds withInternals;
  const unsigned rows = in.rows;
  in.keepInternals = true;
  in.rows = open;
  c_.method->enclose(model, in, withInternals);
  in.keepInternals = false;
  in.rows = rows;
  if (!withInternals.internals.valid) return;
  for (int k = 0; k < c_.n; ++k) {
    if (!(open & (1u << k))) continue;
    if (withInternals.upper[k] < bounds.upper[k]) bounds.upper[k] = withInternals.upper[k];  // both are bounds
    if (bounds.upper[k] <= state_.target(k)) continue;
    IVec gradient;
    if (!enclosure::errorGradient(withInternals, model.sensorError(), k, gradient)) continue;
    const DVec point = monotonePoint(box, gradient);
    IVec f;
    if (!enclosure::errorAtPose(model, c_.domain.poseAt(point), f)) continue;
    Interval bound(f[k].upper());
    for (int i = 0; i < c_.m; ++i) {
      if (box[i].isPoint() || gradient[i].lower() >= 0.0 || gradient[i].upper() <= 0.0) continue;
      const double reach = std::max(interval::rounding::subUp(point[i], box[i].lower()),
                                    interval::rounding::subUp(box[i].upper(), point[i]));
      bound += Interval(gradient[i].mag()) * Interval(reach);
    }
    if (bound.upper() < bounds.upper[k]) {
      bounds.upper[k] = bound.upper();
      state_.counters.gradientHits.fetch_add(1, std::memory_order_relaxed);
    }
    points_.evaluatePoint(point, c_.thinBox(point), box);
  }
}

DVec BoxBounder::monotonePoint(const IVec& box, const IVec& gradient) const {
  DVec point(c_.m);
  for (int i = 0; i < c_.m; ++i) {
    if (box[i].isPoint()) {
      point[i] = box[i].lower();
    } else if (gradient[i].lower() >= 0.0) {
      point[i] = box[i].upper();
    } else if (gradient[i].upper() <= 0.0) {
      point[i] = box[i].lower();
    } else {
      point[i] = box[i].mid();
    }
  }
  return point;
}

void BoxBounder::selfCheck(const model::RobotModel& model, const IVec& box, unsigned active,
                           const enclosure::ErrorBounds& bounds, const SearchPath& track) const {
  const std::vector<Interval> none;
  const std::vector<Interval>& ranges = !model.hasGeometryUncertainty() || c_.params == 0
                                            ? none
                                            : (track.geometry ? track.geometry->ranges : c_.geometryRange);
  try {
    state_.counters.selfCheckPoints.fetch_add(
        static_cast<std::size_t>(selfCheck_.check(model, ranges, box, active, bounds)), std::memory_order_relaxed);
  } catch (const InternalError&) {
    state_.requestStop(Stop::Cancelled);
    throw;
  }
}

}  // namespace verify
}  // namespace pkm_accuracy
