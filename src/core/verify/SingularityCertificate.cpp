#include "SingularityCertificate.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {

void SingularityCertificate::trySingular(const IVec& box, const IVec& poseBox) {
  DVec pos, neg;
  if (!oppositeSignsInDouble(box, pos, neg)) return;
  const IMat whole = c_.model.inverseJacobian(poseBox);
  for (int i = 0; i < whole.rows(); ++i)
    for (int j = 0; j < whole.cols(); ++j)
      if (!whole(i, j).isBounded()) return;
  const IVec posePos = c_.domain.poseAt(pos), poseNeg = c_.domain.poseAt(neg);
  std::vector<double> geometry;  // empty: every admissible geometry
  if (!oppositeCertified(c_.model, posePos, poseNeg)) {
    // Not for every admissible geometry: the nominal one (the parameters' centres) is tried. Max-error mode
    // maximises over the geometries too, so one admissible geometry with a singular pose in the domain makes the
    // maximum unbounded. In verify mode it rules SAFE out without proving UNSAFE (other geometries may have no
    // singular pose here): an uncertainty-sensitive pose is looked for near it, once per run.
    if (c_.params == 0) return;
    const model::RobotModel& nominal = nominalModel();
    if (!oppositeCertified(nominal, posePos, poseNeg)) return;
    geometry = nominalValues_;
    if (c_.options.mode == Mode::Verify) {
      if (!nominalSingular_.exchange(true)) sensitiveNearSingularity(pos, neg, box, nominal, geometry);
      return;
    }
  }
  if (!state_.recordSingular(geometry, pos, neg, posePos, poseNeg)) return;
  // (Max-error mode: the same evaluations raise the lower bounds.)
  if (!state_.haveWitness()) witnessNearSingularity(pos, neg, box);
  if (c_.options.mode == Mode::MaxError || c_.options.stop_at_first_witness) state_.requestStop(Stop::Singular);
}

bool SingularityCertificate::oppositeSignsInDouble(const IVec& box, DVec& pos, DVec& neg) const {
  std::vector<int> vars;
  for (int i = 0; i < c_.m; ++i)
    if (box[i].upper() > box[i].lower()) vars.push_back(i);
  // (At most 6 varying variables: the widest relative to the domain, 65 points.)
  if (vars.size() > 6) {
    const DVec& initWidth = c_.initWidth;
    std::sort(vars.begin(), vars.end(), [&](int a, int b) {
      return (box[a].upper() - box[a].lower()) / initWidth[a] > (box[b].upper() - box[b].lower()) / initWidth[b];
    });
    vars.resize(6);
  }
  const DVec c = domain::centreOf(box);
  double most = 0.0, least = 0.0;
  const unsigned count = 1u << vars.size();
  for (unsigned mask = 0; mask <= count; ++mask) {
    DVec t = c;
    if (mask < count) {
      for (std::size_t v = 0; v < vars.size(); ++v)
        t[vars[v]] = (mask >> v) & 1u ? box[vars[v]].upper() : box[vars[v]].lower();
    }
    const double d = determinantAt(t);
    if (d > most) {
      most = d;
      pos = t;
    } else if (d < least) {
      least = d;
      neg = t;
    }
  }
  return pos.size() == c_.m && neg.size() == c_.m;
}

bool SingularityCertificate::oppositeCertified(const model::RobotModel& model, const IVec& poseA, const IVec& poseB) {
  const int a = enclosure::determinantSign(model.inverseJacobian(poseA));
  const int b = enclosure::determinantSign(model.inverseJacobian(poseB));
  return a != 0 && b != 0 && a != b;
}

const model::RobotModel& SingularityCertificate::nominalModel() {
  std::call_once(nominalOnce_, [&] {
    std::vector<Interval> point(static_cast<std::size_t>(c_.params));
    nominalValues_.resize(static_cast<std::size_t>(c_.params));
    for (int p = 0; p < c_.params; ++p) {  // (the centre, within the admissible values: it is reported)
      nominalValues_[p] =
          std::min(std::max(c_.model.geometryParameterCentre(p), c_.admissible[p].lower()), c_.admissible[p].upper());
      point[p] = Interval(nominalValues_[p]);
    }
    nominal_ = c_.model.restrictGeometry(point);
  });
  return *nominal_;
}

double SingularityCertificate::determinantAt(const DVec& t) const {
  const IVec pose = c_.domain.poseAt(t);
  DVec p(pose.size());
  for (int i = 0; i < pose.size(); ++i) p[i] = pose[i].mid();
  const DMat a = c_.model.inverseJacobian(p);
  if (!a.allFinite()) return 0.0;
  const double d = a.determinant();
  return std::isfinite(d) ? d : 0.0;
}

void SingularityCertificate::witnessNearSingularity(const DVec& a, const DVec& b, const IVec& region) const {
  const std::vector<DVec> kept = towardsSignChange(a, b);
  for (auto it = kept.rbegin(); it != kept.rend() && !state_.haveWitness(); ++it) {
    points_.evaluatePoint(*it, c_.thinBox(*it), region, true, ~0u);
  }
}

std::vector<DVec> SingularityCertificate::towardsSignChange(DVec a, DVec b) const {
  const double signA = determinantAt(a) > 0.0 ? 1.0 : -1.0;
  std::vector<DVec> kept;
  for (int it = 0; it < 60; ++it) {
    const DVec mid = 0.5 * (a + b);
    const double d = determinantAt(mid);
    if (d == 0.0) break;
    if (d * signA > 0.0) {
      a = mid;
    } else {
      b = mid;
    }
    kept.push_back(mid);
  }
  return kept;
}

void SingularityCertificate::sensitiveNearSingularity(const DVec& a, const DVec& b, const IVec& region,
                                                      const model::RobotModel& model,
                                                      const std::vector<double>& values) const {
  const std::vector<DVec> kept = towardsSignChange(a, b);
  for (auto it = kept.rbegin(); it != kept.rend(); ++it) {
    const IVec pose = c_.domain.poseAt(*it);
    IVec f;
    if (c_.domain.classify(c_.thinBox(*it)) != domain::Containment::Inside || !enclosure::errorAtPose(model, pose, f)) {
      continue;
    }
    for (int k = 0; k < c_.n; ++k) {
      if (!(f[k].lower() > c_.options.thresholds[k])) continue;
      SensitivePose s;
      s.point = *it;
      s.pose = pose;
      s.region = region;
      s.component = k;
      s.failing_geometry = values;
      s.failing_lower = f[k].lower();
      state_.recordSensitive(std::move(s), true);
      return;
    }
  }
}

}  // namespace verify
}  // namespace pkm_accuracy
