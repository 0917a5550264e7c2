#include "PointEvaluator.hpp"

#include <algorithm>
#include <cmath>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {

void PointEvaluator::evaluatePoint(const DVec& t, const IVec& thin, const IVec& region, bool mayStop,
                                   unsigned active) const {
  if (c_.domain.classify(thin) != domain::Containment::Inside) return;
  IVec f;
  GMat sensitivity;
  const IVec pose = c_.domain.poseAt(t);
  // Verify mode: only the components still undecided where the point lies (`active`; the others are proven below
  // their thresholds on a box containing it, so they can give neither a witness nor a sensitive pose).
  if (!enclosure::errorAtPose(c_.model, pose, f, c_.params > 0 ? &sensitivity : nullptr, active)) return;
  const bool bySensitivity = c_.params > 0 && sensitivity.rows() == c_.n && sensitivity.cols() == c_.params;
  if (c_.options.mode == Mode::Verify) {
    witnessAt(t, pose, region, f, bySensitivity ? &sensitivity : nullptr, mayStop, active);
  } else {
    lowerBoundsAt(t, pose, f, bySensitivity ? &sensitivity : nullptr);
  }
}

void PointEvaluator::witnessAt(const DVec& t, const IVec& pose, const IVec& region, const IVec& f,
                               const GMat* sensitivity, bool mayStop, unsigned active) const {
  const DVec& thresholds = c_.options.thresholds;
  for (int k = 0; k < c_.n; ++k) {
    if (!((active >> k) & 1u)) continue;
    if (f[k].lower() > thresholds[k]) {
      state_.recordWitness(t, pose, k, f[k].lower(), f, active);
      return;
    }
  }
  if (!sensitivity) return;
  for (int k = 0; k < c_.n; ++k) {
    if (!((active >> k) & 1u) || !(f[k].upper() > thresholds[k])) continue;
    std::vector<double> failing;
    IVec fw;
    if (!enclosure::errorAtPose(*vertexModel(*sensitivity, k, 1.0, failing), pose, fw)) continue;
    if (!(fw[k].lower() > thresholds[k])) continue;
    SensitivePose s;
    s.point = t;
    s.pose = pose;
    s.region = region;
    s.component = k;
    s.failing_geometry = failing;
    s.failing_lower = fw[k].lower();
    std::vector<double> passing;
    IVec fp;
    if (enclosure::errorAtPose(*vertexModel(*sensitivity, k, -1.0, passing), pose, fp) &&
        fp[k].upper() <= thresholds[k]) {
      s.passing_geometry = passing;
      s.passing_upper = fp[k].upper();
      s.passes_all = true;
      for (int j = 0; j < c_.n; ++j) s.passes_all = s.passes_all && fp[j].upper() <= thresholds[j];
    }
    state_.recordSensitive(std::move(s), mayStop);
    return;
  }
}

void PointEvaluator::lowerBoundsAt(const DVec& t, const IVec& pose, const IVec& f, const GMat* sensitivity) const {
  for (int k = 0; k < c_.n; ++k) {
    state_.raiseLower(k, f[k].lower(), t, {});
    // The worst vertex is worth a certified evaluation only if it may raise the lower bound noticeably (its
    // value is below f[k].upper()); skipping is always sound.
    const double current = state_.lower(k);
    if (!sensitivity || !(f[k].upper() > current + 0.25 * c_.tolerance(current))) continue;
    std::vector<double> worst;
    IVec fw;
    if (enclosure::errorAtPose(*vertexModel(*sensitivity, k, 1.0, worst), pose, fw)) {
      state_.raiseLower(k, fw[k].lower(), t, worst);
    }
  }
}

void PointEvaluator::checkCentre(const IVec& box, unsigned active) const {
  const DVec c = domain::centreOf(box);
  const IVec thin = c_.thinBox(c);
  if (c_.domain.classify(thin) == domain::Containment::Inside) {
    evaluatePoint(c, thin, box, true, active);
    return;
  }
  for (int i = 0; i < c_.m; ++i) {
    const double quarter = 0.25 * (box[i].upper() - box[i].lower());
    if (!(quarter > 0.0)) continue;
    for (const double sign : {-1.0, 1.0}) {
      DVec t = c;
      t[i] = std::min(std::max(c[i] + sign * quarter, box[i].lower()), box[i].upper());
      IVec p = thin;
      p[i] = Interval(t[i]);
      if (c_.domain.classify(p) == domain::Containment::Inside) {
        evaluatePoint(t, p, box, true, active);
        return;
      }
    }
  }
}

bool PointEvaluator::centreClearlyBelow(const IVec& box, const enclosure::ErrorBounds& bounds, unsigned active,
                                        bool partial) const {
  constexpr double kCentreSkip = 0.98;
  if (c_.options.mode != Mode::Verify) return false;
  const int n = c_.n, params = c_.params;
  const bool sensitivities = params == 0 || (!partial && bounds.geometrySensitivity.rows() == n &&
                                             bounds.geometrySensitivity.cols() == params);
  DVec atCentre;  // (only once a component needs it)
  bool evaluated = false;
  const auto valueAtCentre = [&]() -> const DVec& {
    if (evaluated) return atCentre;
    evaluated = true;
    const DVec c = domain::centreOf(box);
    if (!sensitivities || c_.domain.classify(c_.thinBox(c)) != domain::Containment::Inside) return atCentre;
    const IVec pose = c_.domain.poseAt(c);
    DVec mid(pose.size());
    for (int i = 0; i < static_cast<int>(pose.size()); ++i) mid[i] = pose[i].mid();
    atCentre = enclosure::errorAtPoseDouble(c_.model, mid);
    return atCentre;
  };
  for (int k = 0; k < n; ++k) {
    if (!((active >> k) & 1u)) continue;
    const double limit = kCentreSkip * c_.options.thresholds[k];
    if (bounds.centreEstimate.size() == n && bounds.centreEstimate[k] < limit) continue;
    if (valueAtCentre().size() != n || !(atCentre[k] > 0.0)) return false;
    double first = 0.0;
    for (int p = 0; p < params; ++p) first += std::abs(bounds.geometrySensitivity(k, p));
    const double second = atCentre[k] > first ? first * first / atCentre[k] : first;
    if (!(atCentre[k] + first + second < limit)) return false;
  }
  return true;
}

void PointEvaluator::witnessInBox(const IVec& box, int k, double lower) const {
  if (state_.haveWitness()) return;
  const DVec c = domain::centreOf(box);
  const IVec pose = c_.domain.poseAt(c);
  IVec f;
  if (!enclosure::errorAtPose(c_.model, pose, f)) f = IVec::Constant(c_.n, Interval(0.0));
  state_.recordWitness(c, pose, k, std::max(lower, f[k].lower()), f, ~0u);
}

std::unique_ptr<model::RobotModel> PointEvaluator::vertexModel(const GMat& sensitivity, int k, double direction,
                                                               std::vector<double>& values) const {
  std::vector<Interval> point(static_cast<std::size_t>(c_.params));
  values.resize(static_cast<std::size_t>(c_.params));
  for (int p = 0; p < c_.params; ++p) {
    const Interval& r = c_.admissible[p];
    values[p] = sensitivity(k, p) * direction >= 0.0 ? r.upper() : r.lower();
    point[p] = Interval(values[p]);
  }
  return c_.model.restrictGeometry(point);
}

}  // namespace verify
}  // namespace pkm_accuracy
