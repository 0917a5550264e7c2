#include "BranchAndBound.hpp"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace pkm_accuracy {
namespace verify {

BranchAndBound::BranchAndBound(const model::RobotModel& model, const domain::Domain& domain,
                               const VerifierOptions& options)
    : context_(model, domain, options),
      state_(context_),
      points_(context_, state_),
      presampler_(context_, state_, points_),
      singularity_(context_, state_, points_),
      bounder_(context_, state_, points_),
      policy_(context_, state_) {}

VerifierResult BranchAndBound::run() {
  const VerifierOptions& o = context_.options;
  const int threads = o.threads > 0 ? o.threads : tbb::info::default_concurrency();
  state_.start(threads);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    presampler_.presample();
    if (state_.stop() != Stop::None) {
      state_.recordUndecided(context_.initial, DVec::Constant(context_.n, kInf));
      return;
    }
    // Iterative deepening: each round runs depth-first searches limited to kRoundDepth more levels from every
    // frontier box; boxes reaching the limit form the next round's frontier. So the whole domain is looked at
    // coarsely before any part of it is refined to the precision limit (a witness or a good lower bound found
    // anywhere ends or shortens the search), while memory stays bounded: once the next frontier holds
    // kMaxFrontier boxes, further boxes are searched depth-first without limit instead of being stored. A frontier
    // box's memory is released as soon as it has been searched.
    std::vector<PendingBox> frontier{{context_.initial, 0, (1u << context_.n) - 1u, SearchPath()}};
    for (int limit = kRoundDepth; !frontier.empty(); limit += kRoundDepth) {
      next_.clear();
      next_.shrink_to_fit();
      depthLimit_ = limit;
      tbb::parallel_for(std::size_t(0), frontier.size(), [&](std::size_t i) {
        PendingBox pending = std::move(frontier[i]);
        process(pending.box, pending.depth, pending.active, pending.track);
      });
      frontier.swap(next_);
    }
  });
  return ResultAssembly(context_).assemble(state_);
}

void BranchAndBound::process(const IVec& box, int depth, unsigned active, const SearchPath& track) {
  const SearchContext& c = context_;
  raiseAtomic(state_.counters.maxDepth, depth);
  if (state_.stopRequested()) {
    // A box left when the run stops keeps its parent's bounds (valid on the sub-box), so a stopped max-error run
    // still reports a finite upper bound where every box was enclosed at least once.
    state_.recordUndecided(box, track.upper.size() == c.n ? track.upper : DVec::Constant(c.n, kInf), ~0u, track);
    return;
  }
  const double vol = c.relativeVolume(box) * (track.geometry ? track.geometry->fraction : 1.0);
  std::unique_ptr<model::RobotModel> restricted;
  if (track.geometry) restricted = c.model.restrictGeometry(track.geometry->ranges);
  const model::RobotModel& model = track.geometry ? *restricted : c.model;
  const domain::Containment where = c.domain.classify(box);
  if (where == domain::Containment::Outside) {
    state_.counters.outsideVol.add(vol);
    return;
  }
  enclosure::BoxInput in;
  enclosure::ErrorBounds bounds;
  bounder_.bound(model, box, where, active, track, in, bounds);
  if (where == domain::Containment::Inside && !state_.singular()) {
    bool unbounded = false;
    for (int k = 0; k < c.n; ++k) unbounded = unbounded || ((active >> k) & 1u && !(bounds.upper[k] < kInf));
    if (unbounded) singularity_.trySingular(box, in.pose);
  }
  if (closeComponents(box, where, vol, bounds, track, active)) return;

  // The search path the sub-boxes inherit; the split policy updates its progress.
  SearchPath next = track;
  next.signs = bounds.signs;
  next.faces = bounds.faces;
  // (Components not enclosed here keep the bounds of the containing box that decided them.)
  next.upper = track.upper.size() == c.n ? DVec(bounds.upper.cwiseMin(track.upper)) : bounds.upper;
  const SplitChoice choice = policy_.choose(box, depth, where, bounds, active, track, next);
  if (choice.switchedToFaces) state_.counters.faceSwitches.fetch_add(1, std::memory_order_relaxed);
  const bool leaf = choice.variable < 0 && choice.geometry < 0;
  if (checkCentreEndsPath(box, depth, bounds, active, track, next, leaf)) return;
  if (leaf) {
    atPrecisionLimit(box, depth, active, track, next);
  } else if (choice.geometry >= 0) {
    splitGeometry(box, depth, active, track, next, choice.geometry);
  } else {
    splitBox(box, depth, where, bounds, active, next, choice.variable);
  }
}

bool BranchAndBound::closeComponents(const IVec& box, domain::Containment where, double vol,
                                     const enclosure::ErrorBounds& bounds, const SearchPath& track, unsigned& active) {
  const VerifierOptions& o = context_.options;
  const int n = context_.n;
  if (o.mode == Mode::Verify) {
    bool allSafe = true;
    for (int k = 0; k < n; ++k) {
      if (!(active & (1u << k))) continue;
      if (bounds.upper[k] <= o.thresholds[k]) {
        active &= ~(1u << k);
      } else {
        allSafe = false;
      }
    }
    if (allSafe) {
      state_.counters.safeVol.add(vol);
      if (o.max_recorded_safe_boxes > 0 && !track.geometry) state_.recordSafe(box, bounds.upper);
      return true;
    }
    // Every pose of the box exceeds for every geometry (only when the box covers every admissible geometry): its
    // centre is a witness, so the verdict is UNSAFE whatever else the search finds.
    if (!o.stop_at_first_witness && where == domain::Containment::Inside && !track.geometry) {
      for (int k = 0; k < n; ++k) {
        if ((active & (1u << k)) && bounds.lower[k] > o.thresholds[k]) {
          points_.witnessInBox(box, k, bounds.lower[k]);
          state_.counters.unsafeVol.add(vol);
          return true;
        }
      }
    }
    return false;
  }
  for (int k = 0; k < n; ++k) {
    if (!(active & (1u << k))) continue;
    if (bounds.upper[k] <= state_.target(k)) {
      state_.discard(k, bounds.upper[k]);
      active &= ~(1u << k);
    }
  }
  if (active == 0) {
    state_.counters.safeVol.add(vol);
    return true;
  }
  return false;
}

bool BranchAndBound::checkCentreEndsPath(const IVec& box, int depth, const enclosure::ErrorBounds& bounds,
                                         unsigned active, const SearchPath& track, const SearchPath& next, bool leaf) {
  // The certified centre evaluation looks for a witness or an uncertainty-sensitive pose: a box whose centre
  // estimates (not certified) are clearly below every threshold still to decide has neither there, so it is skipped
  // (at most delays the finding to a deeper box; never at the precision limit). Paper workspace, 5% margins: the
  // checks cost ~7% of the time without uncertainty and ~13% at +-0.5 mm with the enclosure's estimates alone, which
  // skipped 61-62% of them; with the point value in double as well, nearly all (bench/RESULTS.md).
  const VerifierOptions& o = context_.options;
  if (!leaf && !(depth % std::max(1, o.tuning.centre_check_period) == 0 &&
                 !points_.centreClearlyBelow(box, bounds, active, track.useFaces || track.geometry))) {
    return false;
  }
  points_.checkCentre(box, o.mode == Mode::Verify ? active : ~0u);
  const Stop stop = state_.stop();
  if (o.mode == Mode::Verify && (stop == Stop::Witness || stop == Stop::Sensitive)) {
    state_.recordUndecided(box, next.upper, ~0u, track);
    return true;
  }
  return false;
}

void BranchAndBound::atPrecisionLimit(const IVec& box, int depth, unsigned active, const SearchPath& track,
                                      const SearchPath& next) {
  // At the precision limit, the faces are the last resort (once per box) before giving up.
  if (context_.params > 0 && context_.options.tuning.faces && !track.useFaces) {
    SearchPath faced = next;
    faced.useFaces = true;
    state_.counters.faceSwitches.fetch_add(1, std::memory_order_relaxed);
    process(box, depth, active, faced);
    return;
  }
  state_.recordUndecided(box, next.upper, active, track);
}

void BranchAndBound::splitGeometry(const IVec& box, int depth, unsigned active, const SearchPath& track,
                                   SearchPath next, int p) {
  if (!track.geometry) state_.counters.geometrySwitches.fetch_add(1, std::memory_order_relaxed);
  state_.counters.geometrySplits.fetch_add(1, std::memory_order_relaxed);
  const std::vector<Interval>& ranges = track.geometry ? track.geometry->ranges : context_.geometryRange;
  const auto halves = ranges[p].bisect();
  next.since = 0;
  // (The faces are those of this box's geometry range: the halves start again from the whole of theirs.)
  next.faces = enclosure::GeometryFaces();
  SearchPath first = next, second = next;
  first.geometry = SplitPolicy::geometryPart(ranges, p, halves.first, track);
  second.geometry = SplitPolicy::geometryPart(ranges, p, halves.second, track);
  descend(box, box, depth, active, first, second);
}

void BranchAndBound::splitBox(const IVec& box, int depth, domain::Containment where,
                              const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& next,
                              int split) {
  const auto halves = box[split].bisect();
  IVec left = box, right = box;
  left[split] = halves.first;
  right[split] = halves.second;
  if (where == domain::Containment::Inside && !SplitPolicy::byWidth(where, depth) &&
      policy_.hopeless(bounds, split, active) && splitTwice(left, right, split, depth, bounds, active, next)) {
    return;
  }
  descend(left, right, depth, active, next, next);
}

void BranchAndBound::descend(const IVec& left, const IVec& right, int depth, unsigned active, const SearchPath& first,
                             const SearchPath& second) {
  if (depth + 1 >= depthLimit_ && deferToNextRound(left, right, depth + 1, active, first, second)) return;
  tbb::parallel_invoke([&] { process(left, depth + 1, active, first); },
                       [&] { process(right, depth + 1, active, second); });
}

bool BranchAndBound::deferToNextRound(const IVec& left, const IVec& right, int depth, unsigned active,
                                      const SearchPath& first, const SearchPath& second) {
  std::lock_guard<std::mutex> lock(frontierMutex_);
  if (next_.size() + 2 > kMaxFrontier) return false;
  next_.push_back({left, depth, active, first});
  next_.push_back({right, depth, active, second});
  return true;
}

bool BranchAndBound::splitTwice(const IVec& left, const IVec& right, int split, int depth,
                                const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& next) {
  if (depth + 2 >= depthLimit_) return false;
  const int second = policy_.secondSplit(left, depth + 1, bounds, split, active);
  if (second < 0) return false;
  state_.counters.unenclosed.fetch_add(2, std::memory_order_relaxed);
  raiseAtomic(state_.counters.maxDepth, depth + 1);
  const auto l = left[second].bisect(), r = right[second].bisect();
  IVec q[4] = {left, left, right, right};
  q[0][second] = l.first;
  q[1][second] = l.second;
  q[2][second] = r.first;
  q[3][second] = r.second;
  tbb::parallel_invoke([&] { process(q[0], depth + 2, active, next); }, [&] { process(q[1], depth + 2, active, next); },
                       [&] { process(q[2], depth + 2, active, next); },
                       [&] { process(q[3], depth + 2, active, next); });
  return true;
}

}  // namespace verify
}  // namespace pkm_accuracy
