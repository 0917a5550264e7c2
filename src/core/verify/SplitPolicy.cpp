#include "SplitPolicy.hpp"

#include <algorithm>
#include <cmath>

namespace pkm_accuracy {
namespace verify {

SplitChoice SplitPolicy::choose(const IVec& box, int depth, domain::Containment where,
                                const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& track,
                                SearchPath& next) const {
  const VerifierOptions& o = c_.options;
  const bool widthOnly = byWidth(where, depth);
  SplitChoice choice;
  double poseScore = -1.0;
  choice.variable = chooseSplit(box, depth, bounds, widthOnly, active, &poseScore);
  // Geometric uncertainty: follow the progress of the bound; a path that keeps splitting without progress first
  // bounds its components on their faces (still strategy (a)), then, if it stalls again, may bisect a geometry
  // parameter instead (strategy (b)) when that is where the bound's width comes from.
  if (c_.params > 0 && (o.tuning.faces || o.geometry_splitting != GeometrySplitting::Never) && !widthOnly) {
    choice.geometry = followProgress(bounds, active, track, choice.variable, poseScore, next, choice.switchedToFaces);
  }
  return choice;
}

int SplitPolicy::followProgress(const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& track,
                                int split, double poseScore, SearchPath& next, bool& switchedToFaces) const {
  const VerifierOptions& o = c_.options;
  const double excess = relativeExcess(bounds, active);
  // Progress: the excess at least halved (SearchTuning::stall_levels). With a 10% step the decomposed form's
  // paths keep "progressing" towards its floor at single poses (a +0.5% case UNDECIDED after 200 001 boxes), and
  // the combined form's reach the faces later (2 439 boxes there against 255 with a halving, both at 6 stall
  // levels); the paper workspace at 5% margins never stalls either way (docs/design-notes.md).
  if (excess <= kProgress * track.ref) {
    next.ref = excess;
    next.since = 0;
  } else {
    next.since = track.since + 1;
  }
  // Auto: a stalled box bisects its most influential geometry parameter (then gets pose splits again: its
  // progress count restarts). Always: geometry parameters compete with the box variables by their scores.
  const bool always = o.geometry_splitting == GeometrySplitting::Always;
  const bool never = o.geometry_splitting == GeometrySplitting::Never;
  double geometryScore = -1.0;
  int geometrySplit = -1;
  if (o.tuning.faces && !always && next.since >= c_.stallLevels && !track.useFaces) {
    next.useFaces = true;
    next.since = 0;
    switchedToFaces = true;
  } else if (!never && (always || next.since >= c_.stallLevels)) {
    geometrySplit = chooseGeometrySplit(bounds, active, track, &geometryScore);
  }
  const bool comparable = o.tuning.bisection == Bisection::Smear && bounds.componentSmear.rows() == c_.n;
  if (always && geometrySplit >= 0 && split >= 0 && comparable && geometryScore <= poseScore) geometrySplit = -1;
  return geometrySplit;
}

double SplitPolicy::searchBound(const enclosure::ErrorBounds& bounds, int k) {
  return bounds.searchUpper.size() == bounds.upper.size() ? std::min(bounds.searchUpper[k], bounds.upper[k])
                                                          : bounds.upper[k];
}

double SplitPolicy::relativeExcess(const enclosure::ErrorBounds& bounds, unsigned active) const {
  double worst = 0.0;
  for (int k = 0; k < c_.n; ++k) {
    if (!(active & (1u << k))) continue;
    const double goal = state_.target(k);
    if (!std::isfinite(bounds.upper[k]) || !(goal > 0.0)) return kInf;
    worst = std::max(worst, (searchBound(bounds, k) - goal) / goal);
  }
  return worst;
}

int SplitPolicy::chooseGeometrySplit(const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& track,
                                     double* scoreOut) const {
  const int n = c_.n, params = c_.params;
  if (bounds.geometrySmear.rows() != n || bounds.geometrySmear.cols() != params) return -1;
  if (track.geometry && track.geometry->splits >= kMaxGeometrySplits) return -1;
  const std::vector<Interval>& ranges = track.geometry ? track.geometry->ranges : c_.geometryRange;
  int best = -1;
  double bestScore = 0.0;
  for (int p = 0; p < params; ++p) {
    const double width = ranges[p].upper() - ranges[p].lower();
    const double initial = c_.geometryRange[p].upper() - c_.geometryRange[p].lower();
    if (!(width > initial / kGeometryMinFraction)) continue;
    double score = 0.0;
    for (int k = 0; k < n; ++k) {
      if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
      const double goal = state_.target(k);
      const double excess = goal > 0.0 ? searchBound(bounds, k) / goal : 1.0;
      score = std::max(score, excess * bounds.geometrySmear(k, p));
    }
    if (score > bestScore) {
      bestScore = score;
      best = p;
    }
  }
  *scoreOut = bestScore;
  return best;
}

std::shared_ptr<const GeometryPart> SplitPolicy::geometryPart(const std::vector<Interval>& ranges, int p,
                                                              const Interval& half, const SearchPath& parent) {
  auto part = std::make_shared<GeometryPart>();
  part->ranges = ranges;
  part->ranges[p] = half;
  part->splits = (parent.geometry ? parent.geometry->splits : 0) + 1;
  part->fraction = (parent.geometry ? parent.geometry->fraction : 1.0) * 0.5;
  return part;
}

bool SplitPolicy::hopeless(const enclosure::ErrorBounds& bounds, int split, unsigned active) const {
  constexpr double kHopeless = 1.1;
  if (!c_.options.tuning.skip_hopeless || c_.m < 3 || bounds.componentSmear.rows() != c_.n ||
      bounds.componentSmear.cols() != c_.m)
    return false;
  for (int k = 0; k < c_.n; ++k) {
    if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
    if (searchBound(bounds, k) * (1.0 - bounds.componentSmear(k, split)) > kHopeless * state_.target(k)) return true;
  }
  return false;
}

int SplitPolicy::secondSplit(const IVec& left, int depth, const enclosure::ErrorBounds& bounds, int split,
                             unsigned active) const {
  enclosure::ErrorBounds halved;
  halved.upper = bounds.upper;
  halved.componentSmear = bounds.componentSmear;
  halved.componentSmear.col(split) *= 0.5;
  halved.splitScore = bounds.splitScore;
  if (halved.splitScore.size() == c_.m) halved.splitScore[split] *= 0.5;
  double unused = 0.0;
  return chooseSplit(left, depth, halved, false, active, &unused);
}

int SplitPolicy::chooseSplit(const IVec& box, int depth, const enclosure::ErrorBounds& bounds, bool byWidth,
                             unsigned active, double* scoreOut) const {
  const int n = c_.n, m = c_.m;
  const DVec &minWidth = c_.minWidth, &initWidth = c_.initWidth;
  int best = -1;
  double bestScore = -1.0;
  auto splittable = [&](int i) { return box[i].upper() - box[i].lower() > minWidth[i] && initWidth[i] > 0.0; };
  if (c_.options.tuning.bisection == Bisection::RoundRobin) {
    for (int j = 0; j < m; ++j) {
      const int i = (depth + j) % m;
      if (splittable(i)) return i;
    }
    return -1;
  }
  const bool smear = !byWidth && c_.options.tuning.bisection == Bisection::Smear && bounds.splitScore.size() == m;
  // Per-component hints: only the components this box still has to decide count, each weighted by how far its
  // bound is from its target (threshold, or lower bound + tolerance in max-error mode).
  DVec score = smear ? DVec(bounds.splitScore) : DVec();
  if (smear && bounds.componentSmear.rows() == n && bounds.componentSmear.cols() == m) {
    score = DVec::Zero(m);
    for (int k = 0; k < n; ++k) {
      if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
      const double goal = state_.target(k);
      const double excess = goal > 0.0 ? searchBound(bounds, k) / goal : 1.0;
      for (int i = 0; i < m; ++i) score[i] = std::max(score[i], excess * bounds.componentSmear(k, i));
    }
    if (!(score.maxCoeff() > 0.0)) score = bounds.splitScore;
  }
  // Scores that are not finite (an unbounded enclosure: a box that reaches a singularity or an unreachable pose)
  // say nothing about the variables: split by width then, so that every variable gets its turn.
  const bool scored = smear && score.allFinite();
  for (int i = 0; i < m; ++i) {
    if (!splittable(i)) continue;
    const double scaled = (box[i].upper() - box[i].lower()) / initWidth[i];
    // Smear scores of 0 (a variable that does not matter) still allow splitting by width as a last resort.
    const double value = scored ? score[i] + 1e-12 * scaled : scaled;
    if (value > bestScore) {
      bestScore = value;
      best = i;
    }
  }
  *scoreOut = bestScore;
  return best;
}

}  // namespace verify
}  // namespace pkm_accuracy
