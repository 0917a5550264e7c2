// What the workers of one verifier run share and change: stop requests, statistics counters, progress reports, the
// certified lower bounds (max-error mode) and the evidence that goes into the result (witness, sensitive poses,
// singular pose, undecided and safe boxes). Thread-safe: counters and bounds are atomics, the result's data is
// written under one mutex (the witness flag is published with release / acquire). Internal to the core.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include "AtomicDouble.hpp"
#include "SearchContext.hpp"
#include "SearchPath.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"

namespace pkm_accuracy {
namespace verify {

/// Why the search stops (the first request wins).
enum class Stop : int { None = 0, Witness, Sensitive, BoxBudget, TimeBudget, Cancelled, Singular };

/// The statistics counters (VerifierResult::Statistics), each updated atomically by the workers.
struct SearchCounters {
  std::atomic<std::size_t> boxes{0};
  std::atomic<std::size_t> unenclosed{0};
  std::atomic<std::size_t> selfCheckPoints{0};
  std::atomic<std::size_t> gradientHits{0};
  std::atomic<int> maxDepth{0};
  std::atomic<std::size_t> geometrySwitches{0}, geometrySplits{0}, faceSwitches{0}, faceBoxes{0};
  AtomicDouble safeVol, unsafeVol, undecidedVol, outsideVol;  ///< shares of the initial box volume
};

class SearchState {
 public:
  explicit SearchState(const SearchContext& context);

  // ---- time, stop, progress ----------------------------------------------------------------------------------------
  /// Starts the clock of the time budget; `threads` is reported in the statistics.
  void start(int threads);
  double elapsed() const;
  /// A stop was requested, or is now for the cancel flag or an exhausted box or time budget.
  bool stopRequested();
  void requestStop(Stop why);
  Stop stop() const { return static_cast<Stop>(stop_.load()); }
  /// Calls VerifierOptions::progress if its period has passed (one caller at a time).
  void maybeReportProgress();
  Statistics snapshot() const;

  SearchCounters counters;

  // ---- bounds ------------------------------------------------------------------------------------------------------
  /// The value component k's upper bound must reach for a box to be closed for it: the threshold (verify) or the
  /// current lower bound plus the tolerance (max-error).
  double target(int k) const;
  /// Max-error mode: the certified lower bound of component k's maximum so far.
  double lower(int k) const { return lower_[k]->load(); }
  /// Max-error mode: raises component k's lower bound to `value` (a certified value at point t, geometry `geometry`;
  /// empty: every geometry or exact) and records the point if it is the largest.
  void raiseLower(int k, double value, const DVec& t, const std::vector<double>& geometry);
  /// Max-error mode: a box closed for component k with upper bound `upper`.
  void discard(int k, double upper) { discarded_[k]->raise(upper); }
  double discardedMax(int k) const { return discarded_[k]->load(); }
  double undecidedMax(int k) const { return undecidedMax_[k]->load(); }
  const std::vector<DVec>& argmax() const { return argmax_; }
  const std::vector<std::vector<double>>& argmaxGeometry() const { return argmaxGeometry_; }

  // ---- evidence ----------------------------------------------------------------------------------------------------
  /// A certified witness has been recorded (its data in the result is complete and visible to the caller).
  bool haveWitness() const { return haveWitness_.load(std::memory_order_acquire); }
  /// Verify mode: records the certified witness t (pose enclosure `pose`; component k's worst error >= `lower` there
  /// for every admissible geometry, above its threshold) unless one is recorded already, and stops the search if asked
  /// to stop at the first witness. `f`: certified errors at t for the components in `active` (the others are
  /// evaluated here for the report).
  void recordWitness(const DVec& t, const IVec& pose, int k, double lower, const IVec& f, unsigned active);
  /// Counts an uncertainty-sensitive pose, keeps it among the first recorded, and ends the search if asked to stop
  /// at the first evidence (`mayStop`).
  void recordSensitive(SensitivePose&& s, bool mayStop);
  std::size_t sensitiveCount();
  /// The certified singular pose's data (VerifierResult::singular_*), unless one is recorded already (then false).
  bool recordSingular(const std::vector<double>& geometry, const DVec& from, const DVec& to, const IVec& poseFrom,
                      const IVec& poseTo);
  /// A singular pose is recorded (relaxed: a hint for the workers).
  bool singular() const { return singular_.load(std::memory_order_relaxed); }
  /// A box left undecided with upper bounds `upper` (for the components in `active`), on the path's geometry.
  void recordUndecided(const IVec& box, const DVec& upper, unsigned active = ~0u,
                       const SearchPath& track = SearchPath());
  void recordSafe(const IVec& box, const DVec& upper);
  /// The result's evidence, moved out once the workers are done.
  VerifierResult takeResult() { return std::move(result_); }

 private:
  using Clock = std::chrono::steady_clock;
  const SearchContext& c_;
  Clock::time_point start_;
  int threads_ = 1;
  std::atomic<int> stop_{0};
  std::atomic<Clock::rep> nextProgress_{0};
  std::vector<std::unique_ptr<AtomicDouble>> lower_, discarded_, undecidedMax_;
  std::vector<DVec> argmax_;
  std::vector<std::vector<double>> argmaxGeometry_;
  std::mutex mutex_, progressMutex_;
  /// A certified witness is in result_ (verify mode). Set once, under mutex_, after the witness data (release); read
  /// anywhere with haveWitness() (acquire), which then also sees that data.
  std::atomic<bool> haveWitness_{false};
  std::atomic<bool> singular_{false};  ///< result_.singular is set
  VerifierResult result_;
};

}  // namespace verify
}  // namespace pkm_accuracy
