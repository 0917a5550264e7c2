// The verifier's search over the domain's box (docs/algorithm.md): iterative deepening over a frontier of boxes,
// depth-first parallel search (oneTBB) below it; each box is bounded (BoxBounder), closed for the components it
// decides, checked at its centre (PointEvaluator) and split (SplitPolicy), or recorded undecided. Owns the run's
// units and its shared state (SearchState). One object per run. Internal to the core.
#pragma once

#include <mutex>
#include <vector>

#include "BoxBounder.hpp"
#include "PointEvaluator.hpp"
#include "Presampler.hpp"
#include "ResultAssembly.hpp"
#include "SearchContext.hpp"
#include "SearchPath.hpp"
#include "SearchState.hpp"
#include "SingularityCertificate.hpp"
#include "SplitPolicy.hpp"

namespace pkm_accuracy {
namespace verify {

class BranchAndBound {
 public:
  /// The options must have passed Verifier::validate().
  BranchAndBound(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& options);

  /// Presamples, searches and assembles the result (once). @throws InternalError from the self-check.
  VerifierResult run();

 private:
  /// A box of the next round's frontier, with what its search path carries.
  struct PendingBox {
    IVec box;
    int depth = 0;
    unsigned active = 0;
    SearchPath track;
  };

  /// Searches `box` (at level `depth`, components in `active` still to decide, on the path `track`) and its
  /// sub-boxes, down to the round's depth limit.
  void process(const IVec& box, int depth, unsigned active, const SearchPath& track);
  /// Closes the components the bounds decide (removed from `active`); returns true if the box needs no more work
  /// (every component closed, or verify mode: every pose exceeds, a witness). `vol`: the box's volume share.
  bool closeComponents(const IVec& box, domain::Containment where, double vol, const enclosure::ErrorBounds& bounds,
                       const SearchPath& track, unsigned& active);
  /// The certified centre evaluation (always at a `leaf`, else every SearchTuning::centre_check_period levels unless
  /// the centre is clearly below the thresholds). Returns true if it ended the path (verify mode: a witness or a
  /// sensitive pose stopped the search; the box is recorded undecided with the bounds `next.upper`).
  bool checkCentreEndsPath(const IVec& box, int depth, const enclosure::ErrorBounds& bounds, unsigned active,
                           const SearchPath& track, const SearchPath& next, bool leaf);
  /// A box no split is left for: bounded on the faces once more if it may be, else recorded undecided.
  void atPrecisionLimit(const IVec& box, int depth, unsigned active, const SearchPath& track, const SearchPath& next);
  /// Searches both halves of geometry parameter p of the path's geometry box.
  void splitGeometry(const IVec& box, int depth, unsigned active, const SearchPath& track, SearchPath next, int p);
  /// Searches both halves of box variable `split` (or their four quarters if both halves are hopeless).
  void splitBox(const IVec& box, int depth, domain::Containment where, const enclosure::ErrorBounds& bounds,
                unsigned active, const SearchPath& next, int split);
  /// Searches two sub-boxes at depth + 1 in parallel, or defers them to the next round at the depth limit.
  void descend(const IVec& left, const IVec& right, int depth, unsigned active, const SearchPath& first,
               const SearchPath& second);
  /// Stores both children for the next round unless the frontier is full (then the caller goes on depth-first).
  bool deferToNextRound(const IVec& left, const IVec& right, int depth, unsigned active, const SearchPath& first,
                        const SearchPath& second);
  /// The halves of a SplitPolicy::hopeless() split, each split again without being enclosed (along
  /// SplitPolicy::secondSplit()); the four quarters go to process(). Returns false (nothing done) near the round's
  /// depth limit or if no variable can be split.
  bool splitTwice(const IVec& left, const IVec& right, int split, int depth, const enclosure::ErrorBounds& bounds,
                  unsigned active, const SearchPath& next);

  const SearchContext context_;
  SearchState state_;
  const PointEvaluator points_;
  const Presampler presampler_;
  SingularityCertificate singularity_;
  const BoxBounder bounder_;
  const SplitPolicy policy_;

  static constexpr int kRoundDepth = 12;
  /// A PendingBox takes ~400 bytes with its heap parts (6 variables), a geometry sub-box ~0.6 KB (shared by the boxes
  /// of its path). With at most two frontiers alive (the one searched, released box by box, and the next one) the
  /// frontiers hold at most ~55 MB whatever the run's length; the paper workspace at +-2 mm runs at a flat 58 MB peak
  /// (bench/memory_bench).
  static constexpr std::size_t kMaxFrontier = 1u << 16;
  std::vector<PendingBox> next_;  ///< the next round's frontier (under frontierMutex_)
  std::mutex frontierMutex_;
  int depthLimit_ = kRoundDepth;  ///< the round's depth limit (set between rounds only)
};

}  // namespace verify
}  // namespace pkm_accuracy
