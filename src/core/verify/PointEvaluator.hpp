// Certified evaluations of the worst error at single points of the domain, and what they prove: a witness or an
// uncertainty-sensitive pose (verify mode) or better lower bounds (max-error mode), recorded in the SearchState.
// Also the cheap double estimate that lets the search skip a box centre's evaluation. Thread-safe (const apart from
// the SearchState's recorders). Internal to the core.
#pragma once

#include <memory>
#include <vector>

#include "SearchContext.hpp"
#include "SearchState.hpp"

namespace pkm_accuracy {
namespace verify {

class PointEvaluator {
 public:
  PointEvaluator(const SearchContext& context, SearchState& state) : c_(context), state_(state) {}

  /// Certified evaluation at one point t of the domain (`thin`: its degenerate box; `region`: the search box it
  /// belongs to). Verify mode: a witness (exceeds for every admissible geometry) or, with uncertain geometry, an
  /// uncertainty-sensitive pose (exceeds for some admissible geometry), only for the components in `active`.
  /// Max-error mode: better lower bounds (with uncertain geometry, at the geometry that the first-order terms say
  /// maximises each component there). `mayStop`: allowed to end the search. Points outside the domain are ignored.
  void evaluatePoint(const DVec& t, const IVec& thin, const IVec& region, bool mayStop = true,
                     unsigned active = ~0u) const;

  /// Certified evaluation at the box centre (if it certainly lies in the domain): witness or better lower bounds.
  /// When the centre is outside the domain (a box straddling the region boundary), points a quarter width away
  /// along each variable are tried instead, so that witnesses inside the region are found without descending the
  /// boundary to the precision limit.
  void checkCentre(const IVec& box, unsigned active) const;

  /// Verify mode: every component in `active` has a centre estimate (not certified) below kCentreSkip times its
  /// threshold: the enclosure's (ErrorBounds::centreEstimate, from the worst column's affine form plus the entries
  /// bounded by magnitude, often far above the value on large boxes) or, sharper, the value at the box centre in
  /// double with the nominal geometry plus the first-order geometry terms there (sum over the parameters of
  /// |ErrorBounds::geometrySensitivity|, which are in units of the half-widths) and their square over the value, as
  /// encloseAffine() estimates the second-order ones. The geometry terms are taken only where they cover every
  /// parameter over its whole range (`partial` false): not on faces, whose sensitivities leave out the fixed
  /// parameters, nor on a part of the geometry box (strategy (b)), while the check is over every geometry.
  bool centreClearlyBelow(const IVec& box, const enclosure::ErrorBounds& bounds, unsigned active, bool partial) const;

  /// Verify mode: a box inside the domain, searched for every admissible geometry, whose enclosure certifies that
  /// component k's error exceeds its threshold at every pose (ErrorBounds::lower[k] = `lower`). Its centre becomes
  /// the witness (unless one is recorded already), with the larger of the box's bound (it holds at every pose of the
  /// box) and the certified point evaluation's there.
  void witnessInBox(const IVec& box, int k, double lower) const;

 private:
  /// Verify mode, at the point t with certified errors f (components in `active`): a witness, else (`sensitivity`
  /// given) an uncertainty-sensitive pose.
  void witnessAt(const DVec& t, const IVec& pose, const IVec& region, const IVec& f, const GMat* sensitivity,
                 bool mayStop, unsigned active) const;
  /// Max-error mode, at the point t with certified errors f: raises the lower bounds, also (`sensitivity` given) with
  /// the worst geometry vertex of each component.
  void lowerBoundsAt(const DVec& t, const IVec& pose, const IVec& f, const GMat* sensitivity) const;
  /// The model at the vertex of the admissible geometry box (model::RobotModel::geometryParameterAdmissible, so that
  /// the geometry reported with what is certified there is one the user admits) that the sensitivities of component
  /// k point to (direction +1: raising its error, -1: lowering it); `values` receives the vertex.
  std::unique_ptr<model::RobotModel> vertexModel(const GMat& sensitivity, int k, double direction,
                                                 std::vector<double>& values) const;

  const SearchContext& c_;
  SearchState& state_;
};

}  // namespace verify
}  // namespace pkm_accuracy
