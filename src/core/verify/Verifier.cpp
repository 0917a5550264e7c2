#include "pkm_accuracy/core/verify/Verifier.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

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

enum class Stop : int { None = 0, Witness, BoxBudget, TimeBudget, Cancelled };

class Run {
 public:
  Run(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& options)
      : model_(model),
        domain_(domain),
        options_(options),
        method_(enclosure::makeEnclosure(options.method)),
        n_(model.dof()),
        m_(domain.variables()),
        initial_(domain.initialBox()),
        lower_(static_cast<std::size_t>(n_)),
        discarded_(static_cast<std::size_t>(n_)),
        undecidedMax_(static_cast<std::size_t>(n_)),
        argmax_(static_cast<std::size_t>(n_)) {
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
      // kMaxFrontier boxes, further boxes are searched depth-first without limit instead of being stored.
      std::vector<PendingBox> frontier{{initial_, 0, (1u << n_) - 1u}};
      for (int limit = kRoundDepth; !frontier.empty(); limit += kRoundDepth) {
        next_.clear();
        depthLimit_ = limit;
        tbb::parallel_for(std::size_t(0), frontier.size(),
                          [&](std::size_t i) { process(frontier[i].box, frontier[i].depth, frontier[i].active); });
        frontier.swap(next_);
      }
    });
    return finish();
  }

 private:
  // ---- the branch-and-bound ----------------------------------------------------------------------------------------
  void process(const IVec& box, int depth, unsigned active) {
    raiseInt(maxDepth_, depth);
    if (stopRequested()) {
      recordUndecided(box, DVec::Constant(n_, kInf));
      return;
    }
    const double vol = relativeVolume(box);
    const domain::Containment where = domain_.classify(box);
    if (where == domain::Containment::Outside) {
      outsideVol_.add(vol);
      return;
    }
    enclosure::BoxInput in;
    domain_.poseView(box, method_->needsGradient(), in);
    in.keepInternals = options_.monotonicity;
    enclosure::ErrorBounds bounds;
    method_->enclose(model_, in, bounds);
    boxes_.fetch_add(1, std::memory_order_relaxed);
    maybeReportProgress();
    if (options_.monotonicity && where == domain::Containment::Inside) tightenByGradient(box, bounds, active);

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
        return;
      }
      if (!options_.stop_at_first_witness && where == domain::Containment::Inside) {
        for (int k = 0; k < n_; ++k) {
          if ((active & (1u << k)) && bounds.lower[k] > options_.thresholds[k]) {
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
    const int split = chooseSplit(box, depth, bounds, byWidth, active);
    if (split < 0 || depth % std::max(1, options_.centre_check_period) == 0) {
      checkCentre(box);
      if (options_.mode == Mode::Verify && stop_.load() == static_cast<int>(Stop::Witness)) {
        recordUndecided(box, bounds.upper);
        return;
      }
    }
    if (split < 0) {
      recordUndecided(box, bounds.upper, active);
      return;
    }
    const auto halves = box[split].bisect();
    IVec left = box, right = box;
    left[split] = halves.first;
    right[split] = halves.second;
    if (depth + 1 >= depthLimit_ && deferToNextRound(left, right, depth + 1, active)) return;
    tbb::parallel_invoke([&] { process(left, depth + 1, active); }, [&] { process(right, depth + 1, active); });
  }

  /// Derivative information for the components that their bound does not close (seed paper section 4.2 and the
  /// mean-value form of f_k itself). With G_i enclosing d f_k / d t_i over the box (which lies in the domain), let
  /// t* put every variable in which f_k is monotone at its maximising end and the others at the box centre. Then
  ///   max over the box of f_k <= f_k(t*) + sum over the non-monotone i of |G_i| max|t_i - t*_i|,
  /// with f_k(t*) from a certified point evaluation (exact when f_k is monotone in every variable). The point
  /// evaluation may also give a witness (verify) or a better lower bound (max-error).
  void tightenByGradient(const IVec& box, enclosure::ErrorBounds& bounds, unsigned active) {
    if (!bounds.internals.valid) return;
    for (int k = 0; k < n_; ++k) {
      if (!(active & (1u << k))) continue;
      if (bounds.upper[k] <= target(k)) continue;
      IVec gradient;
      if (!enclosure::errorGradient(bounds, model_.sensorError(), k, gradient)) continue;
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
      if (!enclosure::errorAtPose(model_, domain_.poseAt(point), f)) continue;
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
      evaluatePoint(point, thinBox(point));
    }
  }

  /// Stores both children for the next round unless the frontier is full (then the caller goes on depth-first).
  bool deferToNextRound(const IVec& left, const IVec& right, int depth, unsigned active) {
    std::lock_guard<std::mutex> lock(frontierMutex_);
    if (next_.size() + 2 > kMaxFrontier) return false;
    next_.push_back({left, depth, active});
    next_.push_back({right, depth, active});
    return true;
  }

  int chooseSplit(const IVec& box, int depth, const enclosure::ErrorBounds& bounds, bool byWidth,
                  unsigned active) const {
    int best = -1;
    double bestScore = -1.0;
    auto splittable = [&](int i) { return box[i].upper() - box[i].lower() > minWidth_[i] && initWidth_[i] > 0.0; };
    if (options_.bisection == Bisection::RoundRobin) {
      for (int j = 0; j < m_; ++j) {
        const int i = (depth + j) % m_;
        if (splittable(i)) return i;
      }
      return -1;
    }
    const bool smear = !byWidth && options_.bisection == Bisection::Smear && bounds.splitScore.size() == m_;
    // Per-component hints: only the components this box still has to decide count, each weighted by how far its
    // bound is from its target (threshold, or lower bound + tolerance in max-error mode).
    DVec score = smear ? DVec(bounds.splitScore) : DVec();
    if (smear && bounds.componentSmear.rows() == n_ && bounds.componentSmear.cols() == m_) {
      score = DVec::Zero(m_);
      for (int k = 0; k < n_; ++k) {
        if (!(active & (1u << k)) || !std::isfinite(bounds.upper[k])) continue;
        const double goal = target(k);
        const double excess = goal > 0.0 ? bounds.upper[k] / goal : 1.0;
        for (int i = 0; i < m_; ++i) score[i] = std::max(score[i], excess * bounds.componentSmear(k, i));
      }
      if (!(score.maxCoeff() > 0.0)) score = bounds.splitScore;
    }
    for (int i = 0; i < m_; ++i) {
      if (!splittable(i)) continue;
      const double scaled = (box[i].upper() - box[i].lower()) / initWidth_[i];
      // Smear scores of 0 (a variable that does not matter) still allow splitting by width as a last resort.
      const double value = smear ? score[i] + 1e-12 * scaled : scaled;
      if (value > bestScore) {
        bestScore = value;
        best = i;
      }
    }
    return best;
  }

  /// Certified evaluation at the box centre (if it certainly lies in the domain): witness or better lower bounds.
  /// When the centre is outside the domain (a box straddling the region boundary), points a quarter width away
  /// along each variable are tried instead, so that witnesses inside the region are found without descending the
  /// boundary to the precision limit.
  void checkCentre(const IVec& box) {
    const DVec c = domain::centreOf(box);
    const IVec thin = thinBox(c);
    if (domain_.classify(thin) == domain::Containment::Inside) {
      evaluatePoint(c, thin);
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
          evaluatePoint(t, p);
          return;
        }
      }
    }
  }

  void evaluatePoint(const DVec& t, const IVec& thin) {
    if (domain_.classify(thin) != domain::Containment::Inside) return;
    IVec f;
    const IVec pose = domain_.poseAt(t);
    if (!enclosure::errorAtPose(model_, pose, f)) return;
    if (options_.mode == Mode::Verify) {
      for (int k = 0; k < n_; ++k) {
        if (f[k].lower() > options_.thresholds[k]) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (!haveWitness_) {
            haveWitness_ = true;
            result_.witness = t;
            result_.witness_pose = pose;
            result_.witness_component = k;
            result_.witness_lower_bound = f[k].lower();
            result_.witness_error_lower = DVec(n_);
            for (int j = 0; j < n_; ++j) result_.witness_error_lower[j] = f[j].lower();
          }
          if (options_.stop_at_first_witness) requestStop(Stop::Witness);
          return;
        }
      }
    } else {
      for (int k = 0; k < n_; ++k) {
        if (lower_[k]->raise(f[k].lower())) {
          std::lock_guard<std::mutex> lock(mutex_);
          if (f[k].lower() >= lower_[k]->load()) argmax_[k] = t;
        }
      }
    }
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
      if (options_.mode == Mode::Verify) {
        for (int k = 0; k < n_; ++k) {
          if (f[k] > options_.thresholds[k]) {
            evaluatePoint(t, thin);
            if (haveWitness_ && options_.stop_at_first_witness) return;
            break;
          }
        }
      } else {
        for (int k = 0; k < n_; ++k) {
          if (std::isfinite(f[k]) && f[k] > best[k]) {
            best[k] = f[k];
            bestPoint[k] = t;
          }
        }
      }
    }
    if (options_.mode == Mode::MaxError) {
      for (int k = 0; k < n_; ++k) {
        if (best[k] < 0.0) continue;
        evaluatePoint(bestPoint[k], thinBox(bestPoint[k]));
      }
    }
  }

  // ---- bookkeeping -------------------------------------------------------------------------------------------------
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

  void recordUndecided(const IVec& box, const DVec& upper, unsigned active = ~0u) {
    undecidedVol_.add(relativeVolume(box));
    for (int k = 0; k < n_; ++k)
      if (active & (1u << k)) undecidedMax_[k]->raise(upper[k]);
    std::lock_guard<std::mutex> lock(mutex_);
    ++result_.undecided_box_count;
    if (result_.undecided_boxes.size() < options_.max_recorded_boxes) result_.undecided_boxes.push_back({box, upper});
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
      if (haveWitness_) {
        r.verdict = Verdict::Unsafe;
        r.reason = UndecidedReason::None;
        msg << "UNSAFE: " << model_.componentName(r.witness_component) << " error >= " << r.witness_lower_bound
            << " > threshold " << options_.thresholds[r.witness_component] << " at a certified witness";
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
      r.converged = r.undecided_box_count == 0;
      for (int k = 0; k < n_; ++k) {
        r.max_lower[k] = lower_[k]->load();
        r.max_upper[k] = std::max({r.max_lower[k], discarded_[k]->load(), undecidedMax_[k]->load()});
        if (r.max_upper[k] - r.max_lower[k] > tolerance(r.max_lower[k]) * (1.0 + 1e-12) + 1e-300) r.converged = false;
      }
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
        } else if (allBelow) {
          r.verdict = Verdict::Safe;
        } else {
          r.verdict = Verdict::Undecided;
          r.reason = r.converged ? UndecidedReason::PrecisionLimit : reason;
        }
      }
      msg << (r.converged ? "maximal errors bracketed to alpha" : "maximal errors NOT bracketed to alpha (")
          << (r.converged ? "" : toString(reason) + ")") << " after " << r.stats.boxes << " boxes";
    }
    r.message = msg.str();
    return r;
  }

  const model::RobotModel& model_;
  const domain::Domain& domain_;
  const VerifierOptions& options_;
  std::unique_ptr<enclosure::ErrorEnclosure> method_;
  const int n_, m_;
  const IVec initial_;
  DVec minWidth_, initWidth_;
  bool hasThresholds_ = false;
  Clock::time_point start_;

  struct PendingBox {
    IVec box;
    int depth;
    unsigned active;
  };
  static constexpr int kRoundDepth = 12;
  static constexpr std::size_t kMaxFrontier = 1u << 17;  // ~130k boxes, ~25 MB
  std::vector<PendingBox> next_;
  std::mutex frontierMutex_;
  int depthLimit_ = kRoundDepth;

  std::atomic<int> stop_{0};
  std::atomic<std::size_t> boxes_{0};
  std::atomic<std::size_t> gradientHits_{0};
  std::atomic<int> maxDepth_{0};
  std::atomic<Clock::rep> nextProgress_{0};
  AtomicDouble safeVol_, unsafeVol_, undecidedVol_, outsideVol_;
  std::vector<std::unique_ptr<AtomicDouble>> lower_, discarded_, undecidedMax_;
  std::vector<DVec> argmax_;
  std::mutex mutex_, progressMutex_;
  bool haveWitness_ = false;
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
