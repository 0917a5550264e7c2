// The bounds of one search box: the enclosure method's (ErrorEnclosure::enclose, with what the box's search path
// knows: signs, faces, targets, the components still to decide), tightened by the derivative where the box lies in
// the domain (VerifierOptions::monotonicity), and checked against point values (VerifierOptions::self_check).
// Thread-safe (counts boxes and records lower bounds or witnesses through the SearchState). Internal to the core.
#pragma once

#include "PointEvaluator.hpp"
#include "SearchContext.hpp"
#include "SearchPath.hpp"
#include "SearchState.hpp"
#include "SelfCheck.hpp"

namespace pkm_accuracy {
namespace verify {

class BoxBounder {
 public:
  BoxBounder(const SearchContext& context, SearchState& state, const PointEvaluator& points);

  /// Encloses the components in `active` over `box` (place in the domain `where`, on the path `track`) with `model`
  /// (the model restricted to the path's geometry). `in` receives the enclosure's input (its pose enclosure),
  /// `bounds` the bounds. @throws InternalError from the self-check, after asking the other workers to stop.
  void bound(const model::RobotModel& model, const IVec& box, domain::Containment where, unsigned active,
             const SearchPath& track, enclosure::BoxInput& in, enclosure::ErrorBounds& bounds) const;

 private:
  /// Derivative information for the components that their bound does not close (seed paper section 4.2 and the
  /// mean-value form of f_k itself). With G_i enclosing d f_k / d t_i over the box (which lies in the domain), let
  /// t* put every variable in which f_k is monotone at its maximising end and the others at the box centre. Then
  ///   max over the box of f_k <= f_k(t*) + sum over the non-monotone i of |G_i| max|t_i - t*_i|,
  /// with f_k(t*) from a certified point evaluation (exact when f_k is monotone in every variable). The point
  /// evaluation may also give a witness (verify) or a better lower bound (max-error).
  void tightenByGradient(const model::RobotModel& model, const IVec& box, enclosure::BoxInput& in,
                         enclosure::ErrorBounds& bounds, unsigned active) const;
  /// t* of tightenByGradient(): each variable at the end of the box where the gradient enclosure says f_k is
  /// largest, or at the centre where its sign is unknown.
  DVec monotonePoint(const IVec& box, const IVec& gradient) const;
  /// VerifierOptions::self_check: the box's final bounds (components in `active`) against point evaluations over the
  /// box and the geometry ranges its track was enclosed with. @throws InternalError (SelfCheck::check), after asking
  /// the other workers to stop.
  void selfCheck(const model::RobotModel& model, const IVec& box, unsigned active, const enclosure::ErrorBounds& bounds,
                 const SearchPath& track) const;

  const SearchContext& c_;
  SearchState& state_;
  const PointEvaluator& points_;
  const SelfCheck selfCheck_;
};

}  // namespace verify
}  // namespace pkm_accuracy
