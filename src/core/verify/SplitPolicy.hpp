// Where the search splits a box: which box variable to bisect (smear / relative width / round robin,
// SearchTuning::bisection), when both halves are hopeless and are split again at once, and, along a search path, the
// stall rule: a path whose bound stops progressing is switched to its faces, then to bisecting a geometry parameter
// (VerifierOptions::geometry_splitting). Only heuristics about the search order: a wrong choice costs boxes, never
// soundness. Thread-safe (const; reads the targets from the SearchState). Internal to the core.
#pragma once

#include <memory>
#include <vector>

#include "SearchContext.hpp"
#include "SearchPath.hpp"
#include "SearchState.hpp"

namespace pkm_accuracy {
namespace verify {

/// The split chosen for a box: a box variable (`variable`), a geometry parameter (`geometry`), or none (-1 both: the
/// box is at the precision limit), and whether its path just switched to bounding on the faces.
struct SplitChoice {
  int variable = -1;
  int geometry = -1;
  bool switchedToFaces = false;
};

class SplitPolicy {
 public:
  SplitPolicy(const SearchContext& context, const SearchState& state) : c_(context), state_(state) {}

  /// The split of a box (`where`: its place in the domain, `depth`: its level) enclosed with `bounds`, whose
  /// components in `active` are still to decide, on the path `track`. `next` holds the path its sub-boxes inherit
  /// (signs, faces, upper bounds); the stall rule updates its progress and faces switch.
  SplitChoice choose(const IVec& box, int depth, domain::Containment where, const enclosure::ErrorBounds& bounds,
                     unsigned active, const SearchPath& track, SearchPath& next) const;

  /// A box straddling the region boundary is split by relative width every other level (the smear of the error says
  /// nothing about the boundary, and centres outside the region can never be witnesses).
  static bool byWidth(domain::Containment where, int depth) {
    return where == domain::Containment::Partial && depth % 2 == 1;
  }

  /// The box variable to bisect (-1: none is wider than its precision limit); `scoreOut` receives its score.
  int chooseSplit(const IVec& box, int depth, const enclosure::ErrorBounds& bounds, bool byWidth, unsigned active,
                  double* scoreOut) const;

  /// Both halves of a split along `split` certainly miss a target by the optimistic prediction: some component's
  /// bound minus the whole share of the split variable in it (ErrorBounds::componentSmear, the bisection hints) is
  /// still above kHopeless times its target. Their enclosures would decide nothing, so the search splits them again
  /// at once. Only for domains of at least 3 variables: with fewer, each split narrows a larger part of the box and
  /// the remainder drops faster than the first-order shares say (a 1-variable trajectory split more boxes with it:
  /// bench/RESULTS.md).
  bool hopeless(const enclosure::ErrorBounds& bounds, int split, unsigned active) const;

  /// The second split of a hopeless() split's halves (`left` one of them, at `depth`): the variable chooseSplit()
  /// picks with the hints of the split variable halved (its share of the bound, to first order); -1 if none.
  int secondSplit(const IVec& left, int depth, const enclosure::ErrorBounds& bounds, int split, unsigned active) const;

  /// The half `half` of geometry parameter p of `ranges` (the path `parent`'s geometry box) as a geometry sub-box.
  static std::shared_ptr<const GeometryPart> geometryPart(const std::vector<Interval>& ranges, int p,
                                                          const Interval& half, const SearchPath& parent);

 private:
  /// The stall rule on a path that may split its geometry: updates `next`'s progress, switches it to the faces or
  /// picks a geometry parameter to bisect (-1: none) competing with the box variable `split` (score `poseScore`).
  int followProgress(const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& track, int split,
                     double poseScore, SearchPath& next, bool& switchedToFaces) const;
  /// The geometry parameter to bisect: the largest share of the width of a still-active component's bound (weighted
  /// like chooseSplit), among those wider than 1/kGeometryMinFraction of their initial range; -1 if none.
  int chooseGeometrySplit(const enclosure::ErrorBounds& bounds, unsigned active, const SearchPath& track,
                          double* scoreOut) const;
  /// Largest relative excess of a still-active component's bound over its target (progress measure).
  double relativeExcess(const enclosure::ErrorBounds& bounds, unsigned active) const;
  /// The bound the search's heuristics read for component k: ErrorBounds::searchUpper where the enclosure gives one
  /// (a row whose geometry increase was bounded only coarsely, because the box is split anyway), else the bound;
  /// never above the bound (which the gradient refinement may lower after the enclosure).
  static double searchBound(const enclosure::ErrorBounds& bounds, int k);

  static constexpr double kProgress = 0.5;            ///< the excess must drop below this share of its reference
  static constexpr int kMaxGeometrySplits = 12;       ///< geometry bisections per search path at most
  static constexpr double kGeometryMinFraction = 64;  ///< geometry ranges are not split below 1/64 of the initial

  const SearchContext& c_;
  const SearchState& state_;
};

}  // namespace verify
}  // namespace pkm_accuracy
