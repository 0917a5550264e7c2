#include "SearchState.hpp"

#include <algorithm>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {

SearchState::SearchState(const SearchContext& context)
    : c_(context),
      lower_(static_cast<std::size_t>(context.n)),
      discarded_(static_cast<std::size_t>(context.n)),
      undecidedMax_(static_cast<std::size_t>(context.n)),
      argmax_(static_cast<std::size_t>(context.n)),
      argmaxGeometry_(static_cast<std::size_t>(context.n)) {
  for (int k = 0; k < c_.n; ++k) {
    lower_[k] = std::make_unique<AtomicDouble>(0.0);
    discarded_[k] = std::make_unique<AtomicDouble>(0.0);
    undecidedMax_[k] = std::make_unique<AtomicDouble>(0.0);
  }
}

void SearchState::start(int threads) {
  start_ = Clock::now();
  threads_ = threads;
  result_.stats.threads = threads;
}

double SearchState::elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

bool SearchState::stopRequested() {
  const VerifierOptions& o = c_.options;
  if (stop_.load(std::memory_order_relaxed) != static_cast<int>(Stop::None)) return true;
  if (o.cancel && o.cancel->load()) {
    requestStop(Stop::Cancelled);
    return true;
  }
  if (o.max_boxes > 0 && counters.boxes.load(std::memory_order_relaxed) >= o.max_boxes) {
    requestStop(Stop::BoxBudget);
    return true;
  }
  if (o.time_limit_s > 0.0 && elapsed() > o.time_limit_s) {
    requestStop(Stop::TimeBudget);
    return true;
  }
  return false;
}

void SearchState::requestStop(Stop why) {
  int expected = static_cast<int>(Stop::None);
  stop_.compare_exchange_strong(expected, static_cast<int>(why));
}

void SearchState::maybeReportProgress() {
  const VerifierOptions& o = c_.options;
  if (!o.progress) return;
  const auto now = Clock::now().time_since_epoch().count();
  auto next = nextProgress_.load(std::memory_order_relaxed);
  if (now < next) return;
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::max(0.01, o.progress_period_s)))
          .count();
  if (!nextProgress_.compare_exchange_strong(next, now + period)) return;
  Progress p;
  p.stats = snapshot();
  if (o.mode == Mode::MaxError) {
    p.lower = DVec(c_.n);
    p.upper = DVec(c_.n);
    for (int k = 0; k < c_.n; ++k) {
      p.lower[k] = lower_[k]->load();
      p.upper[k] = std::max(p.lower[k], discarded_[k]->load());
    }
  }
  std::lock_guard<std::mutex> lock(progressMutex_);
  o.progress(p);
}

Statistics SearchState::snapshot() const {
  Statistics s;
  s.boxes = counters.boxes.load();
  s.max_depth = counters.maxDepth.load();
  s.seconds = elapsed();
  s.safe_fraction = counters.safeVol.load();
  s.unsafe_fraction = counters.unsafeVol.load();
  s.undecided_fraction = counters.undecidedVol.load();
  s.outside_fraction = counters.outsideVol.load();
  s.threads = threads_;
  s.monotonicity_hits = counters.gradientHits.load();
  s.geometry_switches = counters.geometrySwitches.load();
  s.face_switches = counters.faceSwitches.load();
  s.face_boxes = counters.faceBoxes.load();
  s.unenclosed_boxes = counters.unenclosed.load();
  s.geometry_splits = counters.geometrySplits.load();
  s.self_check_points = counters.selfCheckPoints.load();
  return s;
}

double SearchState::target(int k) const {
  if (c_.options.mode == Mode::Verify) return c_.options.thresholds[k];
  const double lower = lower_[k]->load();
  return lower + c_.tolerance(lower);
}

void SearchState::raiseLower(int k, double value, const DVec& t, const std::vector<double>& geometry) {
  if (lower_[k]->raise(value)) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (value >= lower_[k]->load()) {
      argmax_[k] = t;
      argmaxGeometry_[k] = geometry;
    }
  }
}

void SearchState::recordWitness(const DVec& t, const IVec& pose, int k, double lower, const IVec& f, unsigned active) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!haveWitness_.load(std::memory_order_relaxed)) {  // (under the lock: the writer's own flag)
      const int n = c_.n;
      result_.witness = t;
      result_.witness_pose = pose;
      result_.witness_component = k;
      result_.witness_lower_bound = lower;
      result_.witness_error_lower = DVec(n);
      IVec all = f;
      const unsigned every = (1u << n) - 1u;
      if ((active & every) != every && !enclosure::errorAtPose(c_.model, pose, all)) all = f;
      for (int j = 0; j < n; ++j) result_.witness_error_lower[j] = all[j].lower();
      result_.witness_error_lower[k] = std::max(result_.witness_error_lower[k], lower);
      haveWitness_.store(true, std::memory_order_release);  // (the witness data above is complete)
    }
  }
  if (c_.options.stop_at_first_witness) requestStop(Stop::Witness);
}

void SearchState::recordSensitive(SensitivePose&& s, bool mayStop) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++result_.sensitive_count;
    if (result_.sensitive.size() < c_.options.max_recorded_boxes) result_.sensitive.push_back(std::move(s));
  }
  if (c_.options.stop_at_first_witness && mayStop) requestStop(Stop::Sensitive);
}

std::size_t SearchState::sensitiveCount() {
  std::lock_guard<std::mutex> lock(mutex_);
  return result_.sensitive_count;
}

bool SearchState::recordSingular(const std::vector<double>& geometry, const DVec& from, const DVec& to,
                                 const IVec& poseFrom, const IVec& poseTo) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result_.singular) return false;
    result_.singular = true;
    result_.singular_geometry = geometry;
    result_.singular_from = from;
    result_.singular_to = to;
    result_.singular_pose_from = poseFrom;
    result_.singular_pose_to = poseTo;
  }
  singular_.store(true);
  return true;
}

void SearchState::recordUndecided(const IVec& box, const DVec& upper, unsigned active, const SearchPath& track) {
  counters.undecidedVol.add(c_.relativeVolume(box) * (track.geometry ? track.geometry->fraction : 1.0));
  for (int k = 0; k < c_.n; ++k)
    if (active & (1u << k)) undecidedMax_[k]->raise(upper[k]);
  std::lock_guard<std::mutex> lock(mutex_);
  ++result_.undecided_box_count;
  if (result_.undecided_boxes.size() < c_.options.max_recorded_boxes) {
    result_.undecided_boxes.push_back({box, upper, track.geometry ? track.geometry->ranges : std::vector<Interval>()});
  }
}

void SearchState::recordSafe(const IVec& box, const DVec& upper) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++result_.safe_box_count;
  if (result_.safe_boxes.size() < c_.options.max_recorded_safe_boxes) result_.safe_boxes.push_back({box, upper, {}});
}

}  // namespace verify
}  // namespace pkm_accuracy
