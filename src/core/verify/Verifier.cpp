#include "pkm_accuracy/core/verify/Verifier.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <Eigen/LU>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

#include "SelfCheck.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

class AtomicDouble {
 public:
  explicit AtomicDouble(double v = 0.0) : v_(v) {}
  double load() const { return v_.load(std::memory_order_relaxed); }
  void add(double x) {
    double cur = v_.load(std::memory_order_relaxed);
    while (!v_.compare_exchange_weak(cur, cur + x, std::memory_order_relaxed)) {
    }
  }
  /// Raises the value to x if x is larger; returns true if it did.
  bool raise(double x) {
    double cur = v_.load(std::memory_order_relaxed);
    while (x > cur) {
      if (v_.compare_exchange_weak(cur, x, std::memory_order_relaxed)) return true;
    }
    return false;
  }

 private:
  std::atomic<double> v_;
};

enum class Stop : int { None = 0, Witness, Sensitive, BoxBudget, TimeBudget, Cancelled, Singular };

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
struct Track {
  std::shared_ptr<const GeometryPart> geometry;
  double ref = kInf;
  int since = 0;
  enclosure::SignPattern signs;    ///< signs of J certified on the parent box (inherited by its sub-boxes)
  enclosure::GeometryFaces faces;  ///< geometry monotonicity certified on the parent box (for the track's model)
  bool useFaces = false;           ///< the path stalled: bound its components on their faces (BoxInput::useFaces)
  DVec upper;                      ///< the parent box's upper bounds (valid for its sub-boxes; empty at the root)
};

class Run {
 public:
  Run(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& options)
      : model_(model),
        domain_(domain),
        options_(options),
        method_(options.enclosure
                    ? options.enclosure
                    : std::shared_ptr<const enclosure::ErrorEnclosure>(enclosure::makeEnclosure(options.method))),
        selfCheck_(domain, method_->name()),
        n_(model.dof()),
        m_(domain.variables()),
        initial_(domain.initialBox()),
        lower_(static_cast<std::size_t>(n_)),
        discarded_(static_cast<std::size_t>(n_)),
        undecidedMax_(static_cast<std::size_t>(n_)),
        argmax_(static_cast<std::size_t>(n_)),
        argmaxGeometry_(static_cast<std::size_t>(n_)),
        params_(model.geometryParameterCount()) {
    minWidth_ = options.min_width.size() == m_ ? options.min_width : DVec(m_);
    initWidth_ = DVec(m_);
    for (int i = 0; i < m_; ++i) {
      initWidth_[i] = initial_[i].upper() - initial_[i].lower();
      if (options.min_width.size() != m_) minWidth_[i] = 1e-5 * initWidth_[i];
    }
    for (int k = 0; k < n_; ++k) {
      lower_[k] = std::make_unique<AtomicDouble>(0.0);
      discarded_[k] = std::make_unique<AtomicDouble>(0.0);
      undecidedMax_[k] = std::make_unique<AtomicDouble>(0.0);
    }
    hasThresholds_ = options.thresholds.size() == n_;
    for (int p = 0; p < params_; ++p) {
      geometryRange_.push_back(model.geometryParameterRange(p));
      admissible_.push_back(model.geometryParameterAdmissible(p));
    }
    int varying = 0;
    for (int i = 0; i < m_; ++i) varying += initWidth_[i] > 0.0 ? 1 : 0;
    // (Default: half the varying box variables, at least 2. Paper workspace at +-1 mm, 2 threads: with the halving
    // progress test 6 levels cost a stalled region 2^6 boxes before its faces: 0.5% above the maxima 1 337 649 boxes
    // in 90 s, against 118 799 in 8.1 s with 3 levels and 114 739 in 7.8 s with 2; 5% margins unchanged, 1-2%
    // margins within 1%; docs/design-notes.md.)
    stallLevels_ = options.tuning.stall_levels > 0 ? options.tuning.stall_levels : std::max(2, (varying + 1) / 2);
  }

  VerifierResult execute() {
    start_ = Clock::now();
    const int threads = options_.threads > 0 ? options_.threads : tbb::info::default_concurrency();
    result_.stats.threads = threads;
    tbb::task_arena arena(threads);
    arena.execute([&] {
      presample();
      if (stop_.load() != static_cast<int>(Stop::None)) {
        recordUndecided(initial_, DVec::Constant(n_, kInf));
        return;
      }
      // Iterative deepening: each round runs depth-first searches limited to kRoundDepth more levels from every
      // frontier box; boxes reaching the limit form the next round's frontier. So the whole domain is looked at
      // coarsely before any part of it is refined to the precision limit (a witness or a good lower bound found
      // anywhere ends or shortens the search), while memory stays bounded: once the next frontier holds
      // kMaxFrontier boxes, further boxes are searched depth-first without limit instead of being stored. A frontier
      // box's memory is released as soon as it has been searched.
      std::vector<PendingBox> frontier{{initial_, 0, (1u << n_) - 1u, Track()}};
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
    return finish();
  }

 private:
  // ---- the branch-and-bound ----------------------------------------------------------------------------------------
  void process(const IVec& box, int depth, unsigned active, const Track& track) {
    raiseInt(maxDepth_, depth);
    if (stopRequested()) {
      // A box left when the run stops keeps its parent's bounds (valid on the sub-box), so a stopped max-error run
      // still reports a finite upper bound where every box was enclosed at least once.
      recordUndecided(box, track.upper.size() == n_ ? track.upper : DVec::Constant(n_, kInf), ~0u, track);
      return;
    }
    const double vol = relativeVolume(box) * (track.geometry ? track.geometry->fraction : 1.0);
    std::unique_ptr<model::RobotModel> restricted;
    if (track.geometry) restricted = model_.restrictGeometry(track.geometry->ranges);
    const model::RobotModel& model = track.geometry ? *restricted : model_;
    const domain::Containment where = domain_.classify(box);
    if (where == domain::Containment::Outside) {
      outsideVol_.add(vol);
      return;
    }
    enclosure::BoxInput in;
    domain_.poseView(box, method_->needsGradient(), in);
    in.knownSigns = track.signs;
    in.faces = track.faces;
    in.useFaces = track.useFaces;
    // (The decomposed form except on the paths bounded on their faces: the combined one certifies the monotone
    // directions the faces need. Geometry halves (strategy (b), Auto and Always) take the decomposed form about their
    // own centre: with the sign-coupled second-order terms it is the tighter one there too, and its
    // first-order coefficients give the geometry hints. The 1/32 corner box at +-1 mm, 0.4% above its sampled
    // maxima: Auto SAFE after 183 boxes (32 geometry splits), UNDECIDED after 2e4 with the combined form on the halves;
    // Always on the 1/128 corner box SAFE after 819 boxes, UNDECIDED after 2e4 with the combined form.)
    in.decomposeGeometry = options_.tuning.decompose_geometry && !track.useFaces;
    in.rows = active;  // components decided on a containing box need no bound here
    in.targets.resize(n_);
    for (int k = 0; k < n_; ++k) in.targets[k] = target(k);
    enclosure::ErrorBounds bounds;
    method_->enclose(model, in, bounds);
    boxes_.fetch_add(1, std::memory_order_relaxed);
    if (track.useFaces) faceBoxes_.fetch_add(1, std::memory_order_relaxed);
    maybeReportProgress();
    if (options_.monotonicity && where == domain::Containment::Inside)
      tightenByGradient(model, box, in, bounds, active);
    if (options_.self_check) selfCheck(model, box, active, bounds, track);
    if (where == domain::Containment::Inside && !singular_.load(std::memory_order_relaxed)) {
      bool unbounded = false;
      for (int k = 0; k < n_; ++k) unbounded = unbounded || ((active >> k) & 1u && !(bounds.upper[k] < kInf));
      if (unbounded) trySingular(box, in.pose);
    }

    if (options_.mode == Mode::Verify) {
      bool allSafe = true;
      for (int k = 0; k < n_; ++k) {
        if (!(active & (1u << k))) continue;
        if (bounds.upper[k] <= options_.thresholds[k]) {
          active &= ~(1u << k);
        } else {
          allSafe = false;
        }
      }
      if (allSafe) {
        safeVol_.add(vol);
        if (options_.max_recorded_safe_boxes > 0 && !track.geometry) recordSafe(box, bounds.upper);
        return;
      }
      // Every pose of the box exceeds for every geometry (only when the box covers every admissible geometry): its
      // centre is a witness, so the verdict is UNSAFE whatever else the search finds.
      if (!options_.stop_at_first_witness && where == domain::Containment::Inside && !track.geometry) {
        for (int k = 0; k < n_; ++k) {
          if ((active & (1u << k)) && bounds.lower[k] > options_.thresholds[k]) {
            witnessInBox(box, k, bounds.lower[k]);
            unsafeVol_.add(vol);
            return;
          }
        }
      }
    } else {
      for (int k = 0; k < n_; ++k) {
        if (!(active & (1u << k))) continue;
        if (bounds.upper[k] <= target(k)) {
          discarded_[k]->raise(bounds.upper[k]);
          active &= ~(1u << k);
        }
      }
      if (active == 0) {
        safeVol_.add(vol);
        return;
      }
    }

    // A box that straddles the region boundary also needs its position variables split (the smear of the error
    // says nothing about the boundary, and centres outside the region can never be witnesses): every other level
    // such a box is split by relative width instead.
    const bool byWidth = where == domain::Containment::Partial && depth % 2 == 1;
    double poseScore = -1.0;
    const int split = chooseSplit(box, depth, bounds, byWidth, active, &poseScore);
    // Geometric uncertainty: follow the progress of the bound; a path that keeps splitting without progress first
    // bounds its components on their faces (still strategy (a)), then, if it stalls again, may bisect a geometry
    // parameter instead (strategy (b)) when that is where the bound's width comes from.
    Track next = track;
    next.signs = bounds.signs;
    next.faces = bounds.faces;
    // (Components not enclosed here keep the bounds of the containing box that decided them.)
    next.upper = track.upper.size() == n_ ? DVec(bounds.upper.cwiseMin(track.upper)) : bounds.upper;
    int geometrySplit = -1;
    if (params_ > 0 && (options_.tuning.faces || options_.geometry_splitting != GeometrySplitting::Never) && !byWidth) {
      const double excess = relativeExcess(bounds, active);
      // Progress: the excess at least halved (VerifierOptions::stall_levels). With a 10% step the decomposed form's
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
      const bool always = options_.geometry_splitting == GeometrySplitting::Always;
      const bool never = options_.geometry_splitting == GeometrySplitting::Never;
      double geometryScore = -1.0;
      if (options_.tuning.faces && !always && next.since >= stallLevels_ && !track.useFaces) {
        next.useFaces = true;
        next.since = 0;
        faceSwitches_.fetch_add(1, std::memory_order_relaxed);
      } else if (!never && (always || next.since >= stallLevels_)) {
        geometrySplit = chooseGeometrySplit(bounds, active, track, &geometryScore);
      }
      const bool comparable = options_.tuning.bisection == Bisection::Smear && bounds.componentSmear.rows() == n_;
      if (always && geometrySplit >= 0 && split >= 0 && comparable && geometryScore <= poseScore) geometrySplit = -1;
    }
    // The certified centre evaluation looks for a witness or an uncertainty-sensitive pose: a box whose centre
    // estimates (not certified) are clearly below every threshold still to decide has neither there, so it is skipped
    // (at most delays the finding to a deeper box; never at the precision limit). Paper workspace, 5% margins: the
    // checks cost ~7% of the time without uncertainty and ~13% at +-0.5 mm with the enclosure's estimates alone, which
    // skipped 61-62% of them; with the point value in double as well, nearly all (bench/RESULTS.md).
    const bool leaf = split < 0 && geometrySplit < 0;
    if (leaf || (depth % std::max(1, options_.tuning.centre_check_period) == 0 &&
                 !centreClearlyBelow(box, bounds, active, track.useFaces || track.geometry))) {
      checkCentre(box, options_.mode == Mode::Verify ? active : ~0u);
      const int stop = stop_.load();
      if (options_.mode == Mode::Verify &&
          (stop == static_cast<int>(Stop::Witness) || stop == static_cast<int>(Stop::Sensitive))) {
        recordUndecided(box, next.upper, ~0u, track);
        return;
      }
    }
    if (split < 0 && geometrySplit < 0) {
      // At the precision limit, the faces are the last resort (once per box) before giving up.
      if (params_ > 0 && options_.tuning.faces && !track.useFaces) {
        Track faced = next;
        faced.useFaces = true;
        faceSwitches_.fetch_add(1, std::memory_order_relaxed);
        process(box, depth, active, faced);
        return;
      }
      recordUndecided(box, next.upper, active, track);
      return;
    }
    if (geometrySplit >= 0) {
      if (!track.geometry) geometrySwitches_.fetch_add(1, std::memory_order_relaxed);
      geometrySplits_.fetch_add(1, std::memory_order_relaxed);
      const std::vector<Interval>& ranges = track.geometry ? track.geometry->ranges : geometryRange_;
      const auto halves = ranges[geometrySplit].bisect();
      next.since = 0;
      // (The faces are those of this box's geometry range: the halves start again from the whole of theirs.)
      next.faces = enclosure::GeometryFaces();
      Track first = next, second = next;
      first.geometry = geometryPart(ranges, geometrySplit, halves.first, track);
      second.geometry = geometryPart(ranges, geometrySplit, halves.second, track);
      descend(box, box, depth, active, first, second);
      return;
    }
    const auto halves = box[split].bisect();
    IVec left = box, right = box;
    left[split] = halves.first;
    right[split] = halves.second;
    if (where == domain::Containment::Inside && !byWidth && hopeless(bounds, split, active) &&
        splitTwice(left, right, split, depth, bounds, active, next)) {
      return;
    }
    descend(left, right, depth, active, next, next);
  }

  void descend(const IVec& left, const IVec& right, int depth, unsigned active, const Track& first,
               const Track& second) {
    if (depth + 1 >= depthLimit_ && deferToNextRound(left, right, depth + 1, active, first, second)) return;
    tbb::parallel_invoke([&] { process(left, depth + 1, active, first); },
                         [&] { process(right, depth + 1, active, second); });
  }

  /// The bound the search's heuristics read for component k: ErrorBounds::searchUpper where the enclosure gives one
  /// (a row whose geometry increase was bounded only coarsely, because the box is split anyway), else the bound;
  /// never above the bound (which the gradient refinement may lower after the enclosure).
  static double searchBound(const enclosure::ErrorBounds& bounds, int k) {
    return bounds.searchUpper.size() == bounds.upper.size() ? std::min(bounds.searchUpper[k], bounds.upper[k])
                                                            : bounds.upper[k];
  }

  /// Largest relative excess of a still-active component's bound over its target (progress measure).
  double relativeExcess(const enclosure::ErrorBounds& bounds, unsigned active) const {
    double worst = 0.0;
    for (int k = 0; k < n_; ++k) {
      if (!(active & (1u << k))) continue;
      const double goal = target(k);
      if (!std::isfinite(bounds.upper[k]) || !(goal > 0.0)) return kInf;
      worst = std::max(worst, (searchBound(bounds, k) - goal) / goal);
    }
    return worst;
  }

  /// The geometry parameter to bisect: the largest share of the width of a still-active component's bound (weighted
  /// like chooseSplit), among those wider than 1/kGeometryMinFraction of their initial range; -1 if none.
  int chooseGeometrySplit(const enclosure::ErrorBounds& bounds, unsigned active, const Track& track,
                          double* scoreOut) const {
    if (bounds.geometrySmear.rows() != n_ || bounds.geometrySmear.cols() != params_) return -1;
    if (track.geometry && track.geometry->splits >= kMaxGeometrySplits) return -1;
    const std::vector<Interval>& ranges = track.geometry ? track.geometry->ranges : geometryRange_;
    int best = -1;
    double bestScore = 0.0;
    for (int p = 0; p < params_; ++p) {
      const double width = ranges[p].upper() - ranges[p].lower();
      const double initial = geometryRange_[p].upper() - geometryRange_[p].lower();
      if (!(width > initial / kGeometryMinFraction)) continue;
      double score = 0.0;
      for (int k = 0; k < n_; ++k) {
        if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
        const double goal = target(k);
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

  std::shared_ptr<const GeometryPart> geometryPart(const std::vector<Interval>& ranges, int p, const Interval& half,
                                                   const Track& parent) const {
    auto part = std::make_shared<GeometryPart>();
    part->ranges = ranges;
    part->ranges[p] = half;
    part->splits = (parent.geometry ? parent.geometry->splits : 0) + 1;
    part->fraction = (parent.geometry ? parent.geometry->fraction : 1.0) * 0.5;
    return part;
  }

  /// Derivative information for the components that their bound does not close (seed paper section 4.2 and the
  /// mean-value form of f_k itself). With G_i enclosing d f_k / d t_i over the box (which lies in the domain), let
  /// t* put every variable in which f_k is monotone at its maximising end and the others at the box centre. Then
  ///   max over the box of f_k <= f_k(t*) + sum over the non-monotone i of |G_i| max|t_i - t*_i|,
  /// with f_k(t*) from a certified point evaluation (exact when f_k is monotone in every variable). The point
  /// evaluation may also give a witness (verify) or a better lower bound (max-error).
  void tightenByGradient(const model::RobotModel& model, const IVec& box, enclosure::BoxInput& in,
                         enclosure::ErrorBounds& bounds, unsigned active) {
    // The derivatives come from the interval form's internals (BoxInput::keepInternals), a second enclosure of the
    // box for the components the first one leaves open only: asking the first one for them would replace the affine
    // second-order form by that looser one everywhere (paper workspace, 5% margins: 2 319 -> 1.38e6 boxes).
    // (Exact geometry only: with an uncertain one, the second-order form that bounds the box keeps no internals.)
    if (model.hasGeometryUncertainty()) return;
    unsigned open = 0;
    for (int k = 0; k < n_; ++k)
      if ((active & (1u << k)) && !(bounds.upper[k] <= target(k))) open |= 1u << k;
    if (open == 0) return;
    enclosure::ErrorBounds withInternals;
    const unsigned rows = in.rows;
    in.keepInternals = true;
    in.rows = open;
    method_->enclose(model, in, withInternals);
    in.keepInternals = false;
    in.rows = rows;
    if (!withInternals.internals.valid) return;
    for (int k = 0; k < n_; ++k) {
      if (!(open & (1u << k))) continue;
      if (withInternals.upper[k] < bounds.upper[k]) bounds.upper[k] = withInternals.upper[k];  // both are bounds
      if (bounds.upper[k] <= target(k)) continue;
      IVec gradient;
      if (!enclosure::errorGradient(withInternals, model.sensorError(), k, gradient)) continue;
      DVec point(m_);
      for (int i = 0; i < m_; ++i) {
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
      IVec f;
      if (!enclosure::errorAtPose(model, domain_.poseAt(point), f)) continue;
      Interval bound(f[k].upper());
      for (int i = 0; i < m_; ++i) {
        if (box[i].isPoint() || gradient[i].lower() >= 0.0 || gradient[i].upper() <= 0.0) continue;
        const double reach = std::max(interval::rounding::subUp(point[i], box[i].lower()),
                                      interval::rounding::subUp(box[i].upper(), point[i]));
        bound += Interval(gradient[i].mag()) * Interval(reach);
      }
      if (bound.upper() < bounds.upper[k]) {
        bounds.upper[k] = bound.upper();
        gradientHits_.fetch_add(1, std::memory_order_relaxed);
      }
      evaluatePoint(point, thinBox(point), box);
    }
  }

  /// VerifierOptions::self_check: the box's final bounds (components in `active`) against point evaluations over the
  /// box and the geometry ranges its track was enclosed with. @throws InternalError (SelfCheck::check), after asking
  /// the other workers to stop.
  void selfCheck(const model::RobotModel& model, const IVec& box, unsigned active, const enclosure::ErrorBounds& bounds,
                 const Track& track) {
    const std::vector<Interval> none;
    const std::vector<Interval>& ranges = !model.hasGeometryUncertainty() || params_ == 0
                                              ? none
                                              : (track.geometry ? track.geometry->ranges : geometryRange_);
    try {
      selfCheckPoints_.fetch_add(static_cast<std::size_t>(selfCheck_.check(model, ranges, box, active, bounds)),
                                 std::memory_order_relaxed);
    } catch (const InternalError&) {
      requestStop(Stop::Cancelled);
      throw;
    }
  }

  /// Stores both children for the next round unless the frontier is full (then the caller goes on depth-first).
  bool deferToNextRound(const IVec& left, const IVec& right, int depth, unsigned active, const Track& first,
                        const Track& second) {
    std::lock_guard<std::mutex> lock(frontierMutex_);
    if (next_.size() + 2 > kMaxFrontier) return false;
    next_.push_back({left, depth, active, first});
    next_.push_back({right, depth, active, second});
    return true;
  }

  /// Both halves of a split along `split` certainly miss a target by the optimistic prediction: some component's bound
  /// minus the whole share of the split variable in it (ErrorBounds::componentSmear, the bisection hints) is still
  /// above kHopeless times its target. Their enclosures would decide nothing, so splitTwice() splits them again at
  /// once. (Only a heuristic about the search order: a wrong prediction costs boxes, never soundness.) Only for
  /// domains of at least 3 variables: with fewer, each split narrows a larger part of the box and the remainder drops
  /// faster than the first-order shares say (a 1-variable trajectory split more boxes with it: bench/RESULTS.md).
  bool hopeless(const enclosure::ErrorBounds& bounds, int split, unsigned active) const {
    constexpr double kHopeless = 1.1;
    if (!options_.tuning.skip_hopeless || m_ < 3 || bounds.componentSmear.rows() != n_ ||
        bounds.componentSmear.cols() != m_)
      return false;
    for (int k = 0; k < n_; ++k) {
      if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
      if (searchBound(bounds, k) * (1.0 - bounds.componentSmear(k, split)) > kHopeless * target(k)) return true;
    }
    return false;
  }

  /// The halves of a hopeless() split, each split again without being enclosed, along the variable chooseSplit()
  /// picks with the hints of the split variable halved (its share of the bound, to first order); the four quarters
  /// go to process(). Returns false (nothing done) near the round's depth limit or if no variable can be split.
  bool splitTwice(const IVec& left, const IVec& right, int split, int depth, const enclosure::ErrorBounds& bounds,
                  unsigned active, const Track& next) {
    if (depth + 2 >= depthLimit_) return false;
    enclosure::ErrorBounds halved;
    halved.upper = bounds.upper;
    halved.componentSmear = bounds.componentSmear;
    halved.componentSmear.col(split) *= 0.5;
    halved.splitScore = bounds.splitScore;
    if (halved.splitScore.size() == m_) halved.splitScore[split] *= 0.5;
    double unused = 0.0;
    const int second = chooseSplit(left, depth + 1, halved, false, active, &unused);
    if (second < 0) return false;
    unenclosed_.fetch_add(2, std::memory_order_relaxed);
    raiseInt(maxDepth_, depth + 1);
    const auto l = left[second].bisect(), r = right[second].bisect();
    IVec q[4] = {left, left, right, right};
    q[0][second] = l.first;
    q[1][second] = l.second;
    q[2][second] = r.first;
    q[3][second] = r.second;
    tbb::parallel_invoke(
        [&] { process(q[0], depth + 2, active, next); }, [&] { process(q[1], depth + 2, active, next); },
        [&] { process(q[2], depth + 2, active, next); }, [&] { process(q[3], depth + 2, active, next); });
    return true;
  }

  int chooseSplit(const IVec& box, int depth, const enclosure::ErrorBounds& bounds, bool byWidth, unsigned active,
                  double* scoreOut) const {
    int best = -1;
    double bestScore = -1.0;
    auto splittable = [&](int i) { return box[i].upper() - box[i].lower() > minWidth_[i] && initWidth_[i] > 0.0; };
    if (options_.tuning.bisection == Bisection::RoundRobin) {
      for (int j = 0; j < m_; ++j) {
        const int i = (depth + j) % m_;
        if (splittable(i)) return i;
      }
      return -1;
    }
    const bool smear = !byWidth && options_.tuning.bisection == Bisection::Smear && bounds.splitScore.size() == m_;
    // Per-component hints: only the components this box still has to decide count, each weighted by how far its
    // bound is from its target (threshold, or lower bound + tolerance in max-error mode).
    DVec score = smear ? DVec(bounds.splitScore) : DVec();
    if (smear && bounds.componentSmear.rows() == n_ && bounds.componentSmear.cols() == m_) {
      score = DVec::Zero(m_);
      for (int k = 0; k < n_; ++k) {
        if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
        const double goal = target(k);
        const double excess = goal > 0.0 ? searchBound(bounds, k) / goal : 1.0;
        for (int i = 0; i < m_; ++i) score[i] = std::max(score[i], excess * bounds.componentSmear(k, i));
      }
      if (!(score.maxCoeff() > 0.0)) score = bounds.splitScore;
    }
    // Scores that are not finite (an unbounded enclosure: a box that reaches a singularity or an unreachable pose)
    // say nothing about the variables: split by width then, so that every variable gets its turn.
    const bool scored = smear && score.allFinite();
    for (int i = 0; i < m_; ++i) {
      if (!splittable(i)) continue;
      const double scaled = (box[i].upper() - box[i].lower()) / initWidth_[i];
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

  /// Verify mode: every component still to decide has a centre estimate (not certified) below kCentreSkip times its
  /// threshold: the enclosure's (ErrorBounds::centreEstimate, from the worst column's affine form plus the entries
  /// bounded by magnitude, often far above the value on large boxes) or, sharper, the value at the box centre in
  /// double with the nominal geometry plus the first-order geometry terms there (sum over the parameters of
  /// |ErrorBounds::geometrySensitivity|, which are in units of the half-widths) and their square over the value, as
  /// encloseAffine() estimates the second-order ones. The geometry terms are taken only where they cover every
  /// parameter over its whole range (`partial` false): not on faces, whose sensitivities leave out the fixed
  /// parameters, nor on a part of the geometry box (strategy (b)), while the check is over every geometry.
  bool centreClearlyBelow(const IVec& box, const enclosure::ErrorBounds& bounds, unsigned active, bool partial) const {
    constexpr double kCentreSkip = 0.98;
    if (options_.mode != Mode::Verify) return false;
    const bool sensitivities = params_ == 0 || (!partial && bounds.geometrySensitivity.rows() == n_ &&
                                                bounds.geometrySensitivity.cols() == params_);
    DVec atCentre;  // (only once a component needs it)
    bool evaluated = false;
    const auto valueAtCentre = [&]() -> const DVec& {
      if (evaluated) return atCentre;
      evaluated = true;
      const DVec c = domain::centreOf(box);
      if (!sensitivities || domain_.classify(thinBox(c)) != domain::Containment::Inside) return atCentre;
      const IVec pose = domain_.poseAt(c);
      DVec mid(pose.size());
      for (int i = 0; i < static_cast<int>(pose.size()); ++i) mid[i] = pose[i].mid();
      atCentre = enclosure::errorAtPoseDouble(model_, mid);
      return atCentre;
    };
    for (int k = 0; k < n_; ++k) {
      if (!((active >> k) & 1u)) continue;
      const double limit = kCentreSkip * options_.thresholds[k];
      if (bounds.centreEstimate.size() == n_ && bounds.centreEstimate[k] < limit) continue;
      if (valueAtCentre().size() != n_ || !(atCentre[k] > 0.0)) return false;
      double first = 0.0;
      for (int p = 0; p < params_; ++p) first += std::abs(bounds.geometrySensitivity(k, p));
      const double second = atCentre[k] > first ? first * first / atCentre[k] : first;
      if (!(atCentre[k] + first + second < limit)) return false;
    }
    return true;
  }

  /// Certified evaluation at the box centre (if it certainly lies in the domain): witness or better lower bounds.
  /// When the centre is outside the domain (a box straddling the region boundary), points a quarter width away
  /// along each variable are tried instead, so that witnesses inside the region are found without descending the
  /// boundary to the precision limit.
  void checkCentre(const IVec& box, unsigned active) {
    const DVec c = domain::centreOf(box);
    const IVec thin = thinBox(c);
    if (domain_.classify(thin) == domain::Containment::Inside) {
      evaluatePoint(c, thin, box, true, active);
      return;
    }
    for (int i = 0; i < m_; ++i) {
      const double quarter = 0.25 * (box[i].upper() - box[i].lower());
      if (!(quarter > 0.0)) continue;
      for (const double sign : {-1.0, 1.0}) {
        DVec t = c;
        t[i] = std::min(std::max(c[i] + sign * quarter, box[i].lower()), box[i].upper());
        IVec p = thin;
        p[i] = Interval(t[i]);
        if (domain_.classify(p) == domain::Containment::Inside) {
          evaluatePoint(t, p, box, true, active);
          return;
        }
      }
    }
  }

  /// Certified evaluation at one point of the domain (`region`: the search box it belongs to). Verify mode: a
  /// witness (exceeds for every admissible geometry) or, with uncertain geometry, an uncertainty-sensitive pose
  /// (exceeds for some admissible geometry). Max-error mode: better lower bounds (with uncertain geometry, at the
  /// geometry that the first-order terms say maximises each component there). `mayStop`: allowed to end the search.
  void evaluatePoint(const DVec& t, const IVec& thin, const IVec& region, bool mayStop = true, unsigned active = ~0u) {
    if (domain_.classify(thin) != domain::Containment::Inside) return;
    IVec f;
    GMat sensitivity;
    const IVec pose = domain_.poseAt(t);
    // Verify mode: only the components still undecided where the point lies (`active`; the others are proven below
    // their thresholds on a box containing it, so they can give neither a witness nor a sensitive pose).
    if (!enclosure::errorAtPose(model_, pose, f, params_ > 0 ? &sensitivity : nullptr, active)) return;
    const bool bySensitivity = params_ > 0 && sensitivity.rows() == n_ && sensitivity.cols() == params_;
    if (options_.mode == Mode::Verify) {
      for (int k = 0; k < n_; ++k) {
        if (!((active >> k) & 1u)) continue;
        if (f[k].lower() > options_.thresholds[k]) {
          recordWitness(t, pose, k, f[k].lower(), f, active);
          return;
        }
      }
      if (!bySensitivity) return;
      for (int k = 0; k < n_; ++k) {
        if (!((active >> k) & 1u) || !(f[k].upper() > options_.thresholds[k])) continue;
        std::vector<double> failing;
        IVec fw;
        if (!enclosure::errorAtPose(*vertexModel(sensitivity, k, 1.0, failing), pose, fw)) continue;
        if (!(fw[k].lower() > options_.thresholds[k])) continue;
        SensitivePose s;
        s.point = t;
        s.pose = pose;
        s.region = region;
        s.component = k;
        s.failing_geometry = failing;
        s.failing_lower = fw[k].lower();
        std::vector<double> passing;
        IVec fp;
        if (enclosure::errorAtPose(*vertexModel(sensitivity, k, -1.0, passing), pose, fp) &&
            fp[k].upper() <= options_.thresholds[k]) {
          s.passing_geometry = passing;
          s.passing_upper = fp[k].upper();
          s.passes_all = true;
          for (int j = 0; j < n_; ++j) s.passes_all = s.passes_all && fp[j].upper() <= options_.thresholds[j];
        }
        recordSensitive(std::move(s), mayStop);
        return;
      }
    } else {
      for (int k = 0; k < n_; ++k) {
        raiseLower(k, f[k].lower(), t, {});
        // The worst vertex is worth a certified evaluation only if it may raise the lower bound noticeably (its
        // value is below f[k].upper()); skipping is always sound.
        const double current = lower_[k]->load();
        if (!bySensitivity || !(f[k].upper() > current + 0.25 * tolerance(current))) continue;
        std::vector<double> worst;
        IVec fw;
        if (enclosure::errorAtPose(*vertexModel(sensitivity, k, 1.0, worst), pose, fw)) {
          raiseLower(k, fw[k].lower(), t, worst);
        }
      }
    }
  }

  /// Verify mode: records the certified witness t (pose enclosure `pose`; component k's worst error >= `lower` there
  /// for every admissible geometry, above its threshold) unless one is recorded already, and stops the search if asked
  /// to stop at the first witness. `f`: certified errors at t for the components in `active` (the others are
  /// evaluated here for the report).
  void recordWitness(const DVec& t, const IVec& pose, int k, double lower, const IVec& f, unsigned active) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!haveWitness_.load(std::memory_order_relaxed)) {  // (under the lock: the writer's own flag)
        result_.witness = t;
        result_.witness_pose = pose;
        result_.witness_component = k;
        result_.witness_lower_bound = lower;
        result_.witness_error_lower = DVec(n_);
        IVec all = f;
        const unsigned every = (1u << n_) - 1u;
        if ((active & every) != every && !enclosure::errorAtPose(model_, pose, all)) all = f;
        for (int j = 0; j < n_; ++j) result_.witness_error_lower[j] = all[j].lower();
        result_.witness_error_lower[k] = std::max(result_.witness_error_lower[k], lower);
        haveWitness_.store(true, std::memory_order_release);  // (the witness data above is complete)
      }
    }
    if (options_.stop_at_first_witness) requestStop(Stop::Witness);
  }

  /// Verify mode: a box inside the domain, searched for every admissible geometry, whose enclosure certifies that
  /// component k's error exceeds its threshold at every pose (ErrorBounds::lower[k] = `lower`). Its centre becomes
  /// the witness (unless one is recorded already), with the larger of the box's bound (it holds at every pose of the
  /// box) and the certified point evaluation's there.
  void witnessInBox(const IVec& box, int k, double lower) {
    if (haveWitness()) return;
    const DVec c = domain::centreOf(box);
    const IVec pose = domain_.poseAt(c);
    IVec f;
    if (!enclosure::errorAtPose(model_, pose, f)) f = IVec::Constant(n_, Interval(0.0));
    recordWitness(c, pose, k, std::max(lower, f[k].lower()), f, ~0u);
  }

  /// A box whose enclosure is unbounded may contain a singular pose. det J^-1 is evaluated in double (at the
  /// nominal geometry) at the box's vertices and centre; if it takes both signs, its sign at the point where it is
  /// largest and at the one where it is smallest is certified over every admissible geometry (determinantSign()
  /// on the enclosure of J^-1 at the point's pose). Opposite certified signs, with J^-1 bounded over the whole box
  /// (so continuous there: RobotModel::inverseJacobian) and the box inside the domain, prove that for every
  /// admissible geometry the segment between the two points holds a pose of the domain where J^-1 is singular
  /// (VerifierResult::singular). Verify mode then looks for a certified witness near it, by bisecting the segment on
  /// the sign of the determinant. Either mode stops: the worst error is unbounded.
  void trySingular(const IVec& box, const IVec& poseBox) {
    std::vector<int> vars;
    for (int i = 0; i < m_; ++i)
      if (box[i].upper() > box[i].lower()) vars.push_back(i);
    // (At most 6 varying variables: the widest relative to the domain, 65 points.)
    if (vars.size() > 6) {
      std::sort(vars.begin(), vars.end(), [&](int a, int b) {
        return (box[a].upper() - box[a].lower()) / initWidth_[a] > (box[b].upper() - box[b].lower()) / initWidth_[b];
      });
      vars.resize(6);
    }
    const DVec c = domain::centreOf(box);
    DVec pos, neg;
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
    if (pos.size() != m_ || neg.size() != m_) return;
    const IMat whole = model_.inverseJacobian(poseBox);
    for (int i = 0; i < whole.rows(); ++i)
      for (int j = 0; j < whole.cols(); ++j)
        if (!whole(i, j).isBounded()) return;
    const IVec posePos = domain_.poseAt(pos), poseNeg = domain_.poseAt(neg);
    // (Certified opposite signs at the two points for every geometry of `model`.)
    auto opposite = [&](const model::RobotModel& model) {
      const int a = enclosure::determinantSign(model.inverseJacobian(posePos));
      const int b = enclosure::determinantSign(model.inverseJacobian(poseNeg));
      return a != 0 && b != 0 && a != b;
    };
    std::vector<double> geometry;  // empty: every admissible geometry
    if (!opposite(model_)) {
      // Not for every admissible geometry: the nominal one (the parameters' centres) is tried. Max-error mode
      // maximises over the geometries too, so one admissible geometry with a singular pose in the domain makes the
      // maximum unbounded. In verify mode it rules SAFE out without proving UNSAFE (other geometries may have no
      // singular pose here): an uncertainty-sensitive pose is looked for near it, once per run.
      if (params_ == 0) return;
      std::call_once(nominalOnce_, [&] {
        std::vector<Interval> point(static_cast<std::size_t>(params_));
        nominalValues_.resize(static_cast<std::size_t>(params_));
        for (int p = 0; p < params_; ++p) {  // (the centre, within the admissible values: it is reported)
          nominalValues_[p] =
              std::min(std::max(model_.geometryParameterCentre(p), admissible_[p].lower()), admissible_[p].upper());
          point[p] = Interval(nominalValues_[p]);
        }
        nominal_ = model_.restrictGeometry(point);
      });
      if (!opposite(*nominal_)) return;
      geometry = nominalValues_;
      if (options_.mode == Mode::Verify) {
        if (!nominalSingular_.exchange(true)) sensitiveNearSingularity(pos, neg, box, *nominal_, geometry);
        return;
      }
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (result_.singular) return;
      result_.singular = true;
      result_.singular_geometry = geometry;
      result_.singular_from = pos;
      result_.singular_to = neg;
      result_.singular_pose_from = posePos;
      result_.singular_pose_to = poseNeg;
    }
    singular_.store(true);
    // (Max-error mode: the same evaluations raise the lower bounds.)
    if (!haveWitness()) witnessNearSingularity(pos, neg, box);
    if (options_.mode == Mode::MaxError || options_.stop_at_first_witness) requestStop(Stop::Singular);
  }

  /// det J^-1 in double at the pose of domain point t, at the nominal geometry (0 where it cannot be evaluated).
  double determinantAt(const DVec& t) const {
    const IVec pose = domain_.poseAt(t);
    DVec p(pose.size());
    for (int i = 0; i < pose.size(); ++i) p[i] = pose[i].mid();
    const DMat a = model_.inverseJacobian(p);
    if (!a.allFinite()) return 0.0;
    const double d = a.determinant();
    return std::isfinite(d) ? d : 0.0;
  }

  /// Bisects the segment from `a` to `b` (det J^-1 of opposite signs there, in double) towards the sign change and
  /// evaluates the points it keeps, nearest first, until one is a certified witness (evaluatePoint(); in max-error
  /// mode they raise the lower bounds) or none is left. Near a singular pose the error exceeds any representable bound,
  /// so this succeeds unless the thresholds are beyond what double precision can certify.
  void witnessNearSingularity(DVec a, DVec b, const IVec& region) {
    const std::vector<DVec> kept = towardsSignChange(a, b);
    for (auto it = kept.rbegin(); it != kept.rend() && !haveWitness(); ++it) {
      evaluatePoint(*it, thinBox(*it), region, true, ~0u);
    }
  }

  /// The points of the bisection of the segment from `a` to `b` towards the sign change of det J^-1 (double, nominal
  /// geometry; opposite signs at a and b), in the order they were found (the last nearest to the sign change).
  std::vector<DVec> towardsSignChange(DVec a, DVec b) const {
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

  /// Verify mode: det J^-1 has certified opposite signs at `a` and `b` for the admissible geometry `model` (one
  /// value per parameter in `values`), not for every one. The segment is bisected on the sign of the determinant
  /// (nominal geometry, double), and the points kept are evaluated with that geometry, nearest first: the first
  /// where a component's certified error exceeds its threshold is recorded as an uncertainty-sensitive pose (that
  /// geometry fails there; no pose was shown to fail for every geometry).
  void sensitiveNearSingularity(DVec a, DVec b, const IVec& region, const model::RobotModel& model,
                                const std::vector<double>& values) {
    const std::vector<DVec> kept = towardsSignChange(a, b);
    for (auto it = kept.rbegin(); it != kept.rend(); ++it) {
      const IVec pose = domain_.poseAt(*it);
      IVec f;
      if (domain_.classify(thinBox(*it)) != domain::Containment::Inside || !enclosure::errorAtPose(model, pose, f)) {
        continue;
      }
      for (int k = 0; k < n_; ++k) {
        if (!(f[k].lower() > options_.thresholds[k])) continue;
        SensitivePose s;
        s.point = *it;
        s.pose = pose;
        s.region = region;
        s.component = k;
        s.failing_geometry = values;
        s.failing_lower = f[k].lower();
        recordSensitive(std::move(s), true);
        return;
      }
    }
  }

  /// Counts an uncertainty-sensitive pose, keeps it among the first recorded, and ends the search if asked to stop
  /// at the first evidence (`mayStop`).
  void recordSensitive(SensitivePose&& s, bool mayStop) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++result_.sensitive_count;
      if (result_.sensitive.size() < options_.max_recorded_boxes) result_.sensitive.push_back(std::move(s));
    }
    if (options_.stop_at_first_witness && mayStop) requestStop(Stop::Sensitive);
  }

  void raiseLower(int k, double value, const DVec& t, const std::vector<double>& geometry) {
    if (lower_[k]->raise(value)) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (value >= lower_[k]->load()) {
        argmax_[k] = t;
        argmaxGeometry_[k] = geometry;
      }
    }
  }

  /// The model at the vertex of the admissible geometry box (model::RobotModel::geometryParameterAdmissible, so that
  /// the geometry reported with what is certified there is one the user admits) that the sensitivities of component k
  /// point to (direction +1: raising its error, -1: lowering it); `values` receives the vertex.
  std::unique_ptr<model::RobotModel> vertexModel(const GMat& sensitivity, int k, double direction,
                                                 std::vector<double>& values) const {
    std::vector<Interval> point(static_cast<std::size_t>(params_));
    values.resize(static_cast<std::size_t>(params_));
    for (int p = 0; p < params_; ++p) {
      const Interval& r = admissible_[p];
      values[p] = sensitivity(k, p) * direction >= 0.0 ? r.upper() : r.lower();
      point[p] = Interval(values[p]);
    }
    return model_.restrictGeometry(point);
  }

  /// Grid sampling before the search: quick witnesses (e.g. singular corners) and first lower bounds.
  void presample() {
    const int g = options_.presample_points;
    if (g <= 0) return;
    std::vector<int> vars;
    for (int i = 0; i < m_; ++i)
      if (initWidth_[i] > 0.0) vars.push_back(i);
    std::size_t total = 1;
    for (std::size_t v = 0; v < vars.size() && total < 100000; ++v) total *= static_cast<std::size_t>(g);
    if (total >= 100000) return;
    // Double-precision screening, then certification of the promising points only.
    std::vector<double> best(n_, -1.0);
    std::vector<DVec> bestPoint(n_);
    for (std::size_t idx = 0; idx < total; ++idx) {
      DVec t = domain::centreOf(initial_);
      std::size_t rest = idx;
      for (int v : vars) {
        const int j = static_cast<int>(rest % g);
        rest /= g;
        t[v] = g == 1 ? initial_[v].mid()
                      : initial_[v].lower() + (initial_[v].upper() - initial_[v].lower()) * j / (g - 1);
        t[v] = std::min(std::max(t[v], initial_[v].lower()), initial_[v].upper());
      }
      const IVec thin = thinBox(t);
      if (domain_.classify(thin) != domain::Containment::Inside) continue;
      const IVec pose = domain_.poseAt(t);
      DVec p(pose.size());
      for (int i = 0; i < pose.size(); ++i) p[i] = pose[i].mid();
      const DVec f = enclosure::errorAtPoseDouble(model_, p);
      bool evaluated = false;
      if (options_.mode == Mode::Verify) {
        for (int k = 0; k < n_; ++k) {
          if (f[k] > options_.thresholds[k]) {
            evaluatePoint(t, thin, thin, false);
            if (haveWitness() && options_.stop_at_first_witness) return;
            evaluated = true;
            break;
          }
        }
      }
      for (int k = 0; k < n_ && !evaluated; ++k) {
        if (std::isfinite(f[k]) && f[k] > best[k]) {
          best[k] = f[k];
          bestPoint[k] = t;
        }
      }
    }
    // Uncertain geometry, verify mode: the screening above sees the centre geometry only, whose errors are below the
    // maxima over the geometries (by 5-8% at +-0.5 mm on the reference robot), so the grid's worst point of each
    // component is certified over every geometry as well (an uncertainty-sensitive pose there rules SAFE out at once).
    if (options_.mode == Mode::Verify && params_ > 0) {
      for (int k = 0; k < n_; ++k) {
        bool seen = best[k] < 0.0;  // (no point, or the same point as an earlier component's)
        for (int j = 0; j < k && !seen; ++j) seen = best[j] >= 0.0 && bestPoint[j] == bestPoint[k];
        if (seen) continue;
        evaluatePoint(bestPoint[k], thinBox(bestPoint[k]), thinBox(bestPoint[k]), false);
        if (haveWitness() && options_.stop_at_first_witness) return;
      }
    }
    if (options_.mode == Mode::MaxError) {
      for (int k = 0; k < n_; ++k) {
        if (best[k] < 0.0) continue;
        evaluatePoint(bestPoint[k], thinBox(bestPoint[k]), thinBox(bestPoint[k]));
      }
    }
    // An uncertainty-sensitive pose rules SAFE out; it ends the search (when asked to stop at the first evidence)
    // only now, so that every sampled point could first show a witness for every geometry.
    if (options_.mode == Mode::Verify && options_.stop_at_first_witness && result_.sensitive_count > 0) {
      requestStop(Stop::Sensitive);
    }
  }

  // ---- bookkeeping -------------------------------------------------------------------------------------------------
  /// A certified witness has been recorded (its data in result_ is complete and visible to the caller).
  bool haveWitness() const { return haveWitness_.load(std::memory_order_acquire); }

  /// The value component k's upper bound must reach for a box to be closed for it: the threshold (verify) or the
  /// current lower bound plus the tolerance (max-error).
  double target(int k) const {
    if (options_.mode == Mode::Verify) return options_.thresholds[k];
    const double lower = lower_[k]->load();
    return lower + tolerance(lower);
  }

  /// The degenerate box of a point of the variables.
  IVec thinBox(const DVec& t) const {
    IVec thin(m_);
    for (int i = 0; i < m_; ++i) thin[i] = Interval(t[i]);
    return thin;
  }

  double tolerance(double lowerBound) const {
    return options_.alpha_relative ? options_.alpha * lowerBound : options_.alpha;
  }

  double relativeVolume(const IVec& box) const {
    double v = 1.0;
    for (int i = 0; i < m_; ++i)
      if (initWidth_[i] > 0.0) v *= (box[i].upper() - box[i].lower()) / initWidth_[i];
    return v;
  }

  void recordUndecided(const IVec& box, const DVec& upper, unsigned active = ~0u, const Track& track = Track()) {
    undecidedVol_.add(relativeVolume(box) * (track.geometry ? track.geometry->fraction : 1.0));
    for (int k = 0; k < n_; ++k)
      if (active & (1u << k)) undecidedMax_[k]->raise(upper[k]);
    std::lock_guard<std::mutex> lock(mutex_);
    ++result_.undecided_box_count;
    if (result_.undecided_boxes.size() < options_.max_recorded_boxes) {
      result_.undecided_boxes.push_back(
          {box, upper, track.geometry ? track.geometry->ranges : std::vector<Interval>()});
    }
  }

  void recordSafe(const IVec& box, const DVec& upper) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++result_.safe_box_count;
    if (result_.safe_boxes.size() < options_.max_recorded_safe_boxes) result_.safe_boxes.push_back({box, upper, {}});
  }

  bool stopRequested() {
    if (stop_.load(std::memory_order_relaxed) != static_cast<int>(Stop::None)) return true;
    if (options_.cancel && options_.cancel->load()) {
      requestStop(Stop::Cancelled);
      return true;
    }
    if (options_.max_boxes > 0 && boxes_.load(std::memory_order_relaxed) >= options_.max_boxes) {
      requestStop(Stop::BoxBudget);
      return true;
    }
    if (options_.time_limit_s > 0.0 && elapsed() > options_.time_limit_s) {
      requestStop(Stop::TimeBudget);
      return true;
    }
    return false;
  }

  void requestStop(Stop why) {
    int expected = static_cast<int>(Stop::None);
    stop_.compare_exchange_strong(expected, static_cast<int>(why));
  }

  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  static void raiseInt(std::atomic<int>& a, int v) {
    int cur = a.load(std::memory_order_relaxed);
    while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
    }
  }

  Statistics snapshot() const {
    Statistics s;
    s.boxes = boxes_.load();
    s.max_depth = maxDepth_.load();
    s.seconds = elapsed();
    s.safe_fraction = safeVol_.load();
    s.unsafe_fraction = unsafeVol_.load();
    s.undecided_fraction = undecidedVol_.load();
    s.outside_fraction = outsideVol_.load();
    s.threads = result_.stats.threads;
    s.monotonicity_hits = gradientHits_.load();
    s.geometry_switches = geometrySwitches_.load();
    s.face_switches = faceSwitches_.load();
    s.face_boxes = faceBoxes_.load();
    s.unenclosed_boxes = unenclosed_.load();
    s.geometry_splits = geometrySplits_.load();
    s.self_check_points = selfCheckPoints_.load();
    return s;
  }

  void maybeReportProgress() {
    if (!options_.progress) return;
    const auto now = Clock::now().time_since_epoch().count();
    auto next = nextProgress_.load(std::memory_order_relaxed);
    if (now < next) return;
    const auto period = std::chrono::duration_cast<Clock::duration>(
                            std::chrono::duration<double>(std::max(0.01, options_.progress_period_s)))
                            .count();
    if (!nextProgress_.compare_exchange_strong(next, now + period)) return;
    Progress p;
    p.stats = snapshot();
    if (options_.mode == Mode::MaxError) {
      p.lower = DVec(n_);
      p.upper = DVec(n_);
      for (int k = 0; k < n_; ++k) {
        p.lower[k] = lower_[k]->load();
        p.upper[k] = std::max(p.lower[k], discarded_[k]->load());
      }
    }
    std::lock_guard<std::mutex> lock(progressMutex_);
    options_.progress(p);
  }

  VerifierResult finish() {
    VerifierResult r = std::move(result_);
    r.stats = snapshot();
    const Stop stop = static_cast<Stop>(stop_.load());
    UndecidedReason reason = UndecidedReason::PrecisionLimit;
    if (stop == Stop::BoxBudget) reason = UndecidedReason::BoxBudget;
    if (stop == Stop::TimeBudget) reason = UndecidedReason::TimeBudget;
    if (stop == Stop::Cancelled) reason = UndecidedReason::Cancelled;
    std::ostringstream msg;
    if (options_.mode == Mode::Verify) {
      if (haveWitness()) {
        r.verdict = Verdict::Unsafe;
        r.reason = UndecidedReason::None;
        msg << "UNSAFE: " << model_.componentName(r.witness_component) << " error >= " << r.witness_lower_bound
            << " > threshold " << options_.thresholds[r.witness_component] << " at a certified witness";
        if (r.singular) msg << ", near a certified singular pose (" << singularText(r) << ")";
      } else if (r.singular) {
        r.verdict = Verdict::Unsafe;
        r.reason = UndecidedReason::None;
        msg << "UNSAFE: the domain contains a singular pose (" << singularText(r)
            << "), near which the error exceeds any threshold";
      } else if (r.sensitive_count > 0) {
        const SensitivePose& s = r.sensitive.front();
        r.verdict = Verdict::Undecided;
        r.reason = UndecidedReason::UncertaintySensitive;
        msg << "UNDECIDED (uncertainty_sensitive): " << model_.componentName(s.component)
            << " exceeds its threshold for some admissible geometries (certified error >= " << s.failing_lower << " > "
            << options_.thresholds[s.component] << ")";
        if (!s.passing_geometry.empty()) {
          msg << " and stays below it for others (<= " << s.passing_upper << ")";
        }
        msg << " at " << r.sensitive_count << " certified pose(s), e.g. in the region";
        for (int i = 0; i < s.region.size(); ++i) {
          msg << (i == 0 ? " " : ", ") << domain_.variableName(i) << " [" << s.region[i].lower() << ", "
              << s.region[i].upper() << "]";
        }
        msg << "; no pose was found where it exceeds for every admissible geometry";
      } else if (r.undecided_box_count == 0) {
        r.verdict = Verdict::Safe;
        r.reason = UndecidedReason::None;
        msg << "SAFE: every pose is within every threshold (" << r.stats.boxes << " boxes)";
      } else {
        r.verdict = Verdict::Undecided;
        r.reason = reason;
        msg << "UNDECIDED (" << toString(reason) << "): " << r.undecided_box_count << " boxes could not be decided, "
            << r.stats.undecided_fraction * 100.0 << "% of the volume";
      }
    } else {
      r.max_lower = DVec(n_);
      r.max_upper = DVec(n_);
      r.max_argmax = argmax_;
      r.max_argmax_pose.assign(argmax_.size(), IVec());
      for (std::size_t k = 0; k < argmax_.size(); ++k)
        if (argmax_[k].size() == m_) r.max_argmax_pose[k] = domain_.poseAt(argmax_[k]);
      if (params_ > 0) r.max_argmax_geometry = argmaxGeometry_;
      r.converged = r.undecided_box_count == 0;
      for (int k = 0; k < n_; ++k) {
        r.max_lower[k] = lower_[k]->load();
        r.max_upper[k] = std::max({r.max_lower[k], discarded_[k]->load(), undecidedMax_[k]->load()});
        // (Singular: some component is unbounded, and which is not known: none keeps a finite upper bound.)
        if (r.singular) r.max_upper[k] = kInf;
        if (r.max_upper[k] - r.max_lower[k] > tolerance(r.max_lower[k]) * (1.0 + 1e-12) + 1e-300) r.converged = false;
      }
      if (r.singular) reason = UndecidedReason::NoThresholds;  // (the bracket is final: [lower, +inf])
      if (!hasThresholds_) {
        r.verdict = Verdict::Undecided;
        r.reason = r.converged ? UndecidedReason::NoThresholds : reason;
      } else {
        int exceeded = -1;
        bool allBelow = true;
        for (int k = 0; k < n_; ++k) {
          if (r.max_lower[k] > options_.thresholds[k] && exceeded < 0) exceeded = k;
          if (!(r.max_upper[k] <= options_.thresholds[k])) allBelow = false;
        }
        if (exceeded >= 0 && r.max_argmax[exceeded].size() == m_) {
          r.verdict = Verdict::Unsafe;
          r.witness = r.max_argmax[exceeded];
          r.witness_pose = domain_.poseAt(r.witness);
          r.witness_component = exceeded;
          r.witness_lower_bound = r.max_lower[exceeded];
        } else if (r.singular) {
          r.verdict = Verdict::Unsafe;
          r.reason = UndecidedReason::None;
        } else if (allBelow) {
          r.verdict = Verdict::Safe;
        } else {
          r.verdict = Verdict::Undecided;
          r.reason = r.converged ? UndecidedReason::PrecisionLimit : reason;
        }
      }
      if (r.singular) {
        msg << "the maximal error is unbounded: the domain contains a singular pose (" << singularText(r) << "); after "
            << r.stats.boxes << " boxes";
      } else {
        msg << (r.converged ? "maximal errors bracketed to alpha" : "maximal errors NOT bracketed to alpha (")
            << (r.converged ? "" : toString(reason) + ")") << " after " << r.stats.boxes << " boxes";
      }
    }
    r.message = msg.str();
    return r;
  }

  /// "det J^-1 changes sign between <point> and <point>" in the domain's variables.
  std::string singularText(const VerifierResult& r) const {
    std::ostringstream os;
    os << "det J^-1 has certified opposite signs, for "
       << (r.singular_geometry.empty() ? "every admissible geometry" : "the nominal geometry") << ", at";
    for (const DVec* t : {&r.singular_from, &r.singular_to}) {
      os << (t == &r.singular_from ? " " : " and at ");
      for (int i = 0; i < t->size(); ++i) os << (i == 0 ? "" : ", ") << domain_.variableName(i) << " = " << (*t)[i];
    }
    return os.str();
  }

  const model::RobotModel& model_;
  const domain::Domain& domain_;
  const VerifierOptions& options_;
  std::shared_ptr<const enclosure::ErrorEnclosure> method_;
  const SelfCheck selfCheck_;
  const int n_, m_;
  const IVec initial_;
  DVec minWidth_, initWidth_;
  bool hasThresholds_ = false;
  Clock::time_point start_;

  struct PendingBox {
    IVec box;
    int depth;
    unsigned active;
    Track track;
  };
  static constexpr int kRoundDepth = 12;
  /// A PendingBox takes ~400 bytes with its heap parts (6 variables), a geometry sub-box ~0.6 KB (shared by the boxes
  /// of its path). With at most two frontiers alive (the one searched, released box by box, and the next one) the
  /// frontiers hold at most ~55 MB whatever the run's length; the paper workspace at +-2 mm runs at a flat 58 MB peak
  /// (bench/memory_bench).
  static constexpr std::size_t kMaxFrontier = 1u << 16;
  std::vector<PendingBox> next_;
  std::mutex frontierMutex_;
  int depthLimit_ = kRoundDepth;

  std::atomic<int> stop_{0};
  std::atomic<std::size_t> boxes_{0};
  std::atomic<std::size_t> unenclosed_{0};
  std::atomic<std::size_t> selfCheckPoints_{0};
  std::atomic<std::size_t> gradientHits_{0};
  std::atomic<int> maxDepth_{0};
  std::atomic<Clock::rep> nextProgress_{0};
  AtomicDouble safeVol_, unsafeVol_, undecidedVol_, outsideVol_;
  std::vector<std::unique_ptr<AtomicDouble>> lower_, discarded_, undecidedMax_;
  std::vector<DVec> argmax_;
  std::vector<std::vector<double>> argmaxGeometry_;
  const int params_;                     ///< uncertain geometry parameters of the model
  std::vector<Interval> geometryRange_;  ///< their initial ranges
  std::vector<Interval> admissible_;     ///< their admissible values (inside the ranges; reported points lie in them)
  int stallLevels_ = 2;
  static constexpr double kProgress = 0.5;            ///< the excess must drop below this share of its reference
  static constexpr int kMaxGeometrySplits = 12;       ///< geometry bisections per search path at most
  static constexpr double kGeometryMinFraction = 64;  ///< geometry ranges are not split below 1/64 of the initial
  std::atomic<std::size_t> geometrySwitches_{0}, geometrySplits_{0}, faceSwitches_{0}, faceBoxes_{0};
  std::mutex mutex_, progressMutex_;
  /// A certified witness is in result_ (verify mode). Set once, under mutex_, after the witness data (release); read
  /// anywhere with haveWitness() (acquire), which then also sees that data.
  std::atomic<bool> haveWitness_{false};
  std::atomic<bool> singular_{false};         ///< result_.singular is set
  std::atomic<bool> nominalSingular_{false};  ///< verify mode: sensitiveNearSingularity() was tried
  /// The model at the nominal geometry (every parameter at its centre; built by trySingular() when first needed).
  std::once_flag nominalOnce_;
  std::unique_ptr<model::RobotModel> nominal_;
  std::vector<double> nominalValues_;
  VerifierResult result_;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidArgument(message);
}

}  // namespace

void Verifier::validate(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& o) {
  const int n = model.dof();
  const int m = domain.variables();
  require(m >= 1 && m <= kMaxDof, "domain: expected 1 to 6 variables, got " + std::to_string(m));
  require(domain.poseDimension() == n, "domain: expected poses of " + std::to_string(n) + " coordinates (the dof of " +
                                           model.name() + "), got " + std::to_string(domain.poseDimension()));
  if (o.mode == Mode::Verify || o.thresholds.size() > 0) {
    require(o.thresholds.size() == n, "thresholds: expected " + std::to_string(n) +
                                          " values (one per component), got " + std::to_string(o.thresholds.size()));
    for (int k = 0; k < n; ++k) {
      std::ostringstream os;
      os << "thresholds[" << k << "] (" << model.componentName(k) << "): expected a finite value > 0, got "
         << o.thresholds[k];
      require(o.thresholds[k] > 0.0 && std::isfinite(o.thresholds[k]), os.str());
    }
  }
  if (o.mode == Mode::MaxError) {
    std::ostringstream os;
    os << "alpha: expected a finite value > 0, got " << o.alpha;
    require(o.alpha > 0.0 && std::isfinite(o.alpha), os.str());
  }
  if (o.min_width.size() > 0) {
    require(o.min_width.size() == m, "min_width: expected " + std::to_string(m) + " values (one per variable), got " +
                                         std::to_string(o.min_width.size()));
    for (int i = 0; i < m; ++i) {
      std::ostringstream os;
      os << "min_width[" << i << "]: expected a finite value >= 0, got " << o.min_width[i];
      require(o.min_width[i] >= 0.0 && std::isfinite(o.min_width[i]), os.str());
    }
  }
  {
    std::ostringstream os;
    os << "time_limit: expected a finite value >= 0 s, got " << o.time_limit_s;
    require(o.time_limit_s >= 0.0 && std::isfinite(o.time_limit_s), os.str());
  }
  require(o.threads >= 0, "threads: expected >= 0 (0 = all cores), got " + std::to_string(o.threads));
  require(o.tuning.stall_levels >= 0,
          "stall_levels: expected >= 0 (0 = half the number of box variables, at least 2), got " +
              std::to_string(o.tuning.stall_levels));
  require(o.presample_points >= 0 && o.presample_points <= 50,
          "presample_points: expected 0 to 50, got " + std::to_string(o.presample_points));
  enclosure::makeEnclosure(o.method);  // throws on an unknown name
  const IVec& box = domain.initialBox();
  for (int i = 0; i < m; ++i) {
    std::ostringstream os;
    os << domain.variableName(i) << ": expected a finite non-empty range, got " << box[i];
    require(!box[i].isEmpty() && box[i].isBounded(), os.str());
  }
}

VerifierResult Verifier::run(const model::RobotModel& model, const domain::Domain& domain,
                             const VerifierOptions& options) {
  validate(model, domain, options);
  Run run(model, domain, options);
  return run.execute();
}

}  // namespace verify
}  // namespace pkm_accuracy
