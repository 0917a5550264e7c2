// The certificate that the domain holds a singular pose (VerifierResult::singular): opposite certified signs of
// det J^-1 at two points of a box inside the domain over which J^-1 is bounded (so continuous), for every admissible
// geometry (or, in max-error mode, for the nominal one). Then the points nearest the sign change are evaluated
// (PointEvaluator) for a witness or an uncertainty-sensitive pose. Thread-safe: the nominal model is built once
// (std::call_once), the singular pose is recorded once (SearchState). Internal to the core.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "PointEvaluator.hpp"
#include "SearchContext.hpp"
#include "SearchState.hpp"

namespace pkm_accuracy {
namespace verify {

class SingularityCertificate {
 public:
  SingularityCertificate(const SearchContext& context, SearchState& state, const PointEvaluator& points)
      : c_(context), state_(state), points_(points) {}

  /// A box whose enclosure is unbounded (pose enclosure `poseBox`) may contain a singular pose. det J^-1 is evaluated
  /// in double (at the nominal geometry) at the box's vertices and centre; if it takes both signs, its sign at the
  /// point where it is largest and at the one where it is smallest is certified over every admissible geometry
  /// (determinantSign() on the enclosure of J^-1 at the point's pose). Opposite certified signs, with J^-1 bounded
  /// over the whole box (so continuous there: RobotModel::inverseJacobian) and the box inside the domain, prove that
  /// for every admissible geometry the segment between the two points holds a pose of the domain where J^-1 is
  /// singular (VerifierResult::singular). Verify mode then looks for a certified witness near it, by bisecting the
  /// segment on the sign of the determinant. Either mode stops: the worst error is unbounded.
  void trySingular(const IVec& box, const IVec& poseBox);

 private:
  /// The points of the box (vertices over its at most 6 widest varying variables, and its centre) where det J^-1 in
  /// double is largest (`pos`, > 0) and smallest (`neg`, < 0). Returns false unless it takes both signs.
  bool oppositeSignsInDouble(const IVec& box, DVec& pos, DVec& neg) const;
  /// J^-1 of `model` has certified opposite determinant signs at the two poses, for every geometry of `model`.
  static bool oppositeCertified(const model::RobotModel& model, const IVec& poseA, const IVec& poseB);
  /// The model at the nominal geometry (every parameter at its centre, within its admissible values), built once.
  const model::RobotModel& nominalModel();
  /// det J^-1 in double at the pose of domain point t, at the nominal geometry (0 where it cannot be evaluated).
  double determinantAt(const DVec& t) const;
  /// Bisects the segment from `a` to `b` (det J^-1 of opposite signs there, in double) towards the sign change and
  /// evaluates the points it keeps, nearest first, until one is a certified witness (evaluatePoint(); in max-error
  /// mode they raise the lower bounds) or none is left. Near a singular pose the error exceeds any representable
  /// bound, so this succeeds unless the thresholds are beyond what double precision can certify.
  void witnessNearSingularity(const DVec& a, const DVec& b, const IVec& region) const;
  /// The points of the bisection of the segment from `a` to `b` towards the sign change of det J^-1 (double, nominal
  /// geometry; opposite signs at a and b), in the order they were found (the last nearest to the sign change).
  std::vector<DVec> towardsSignChange(DVec a, DVec b) const;
  /// Verify mode: det J^-1 has certified opposite signs at `a` and `b` for the admissible geometry `model` (one
  /// value per parameter in `values`), not for every one. The segment is bisected on the sign of the determinant
  /// (nominal geometry, double), and the points kept are evaluated with that geometry, nearest first: the first
  /// where a component's certified error exceeds its threshold is recorded as an uncertainty-sensitive pose (that
  /// geometry fails there; no pose was shown to fail for every geometry).
  void sensitiveNearSingularity(const DVec& a, const DVec& b, const IVec& region, const model::RobotModel& model,
                                const std::vector<double>& values) const;

  const SearchContext& c_;
  SearchState& state_;
  const PointEvaluator& points_;
  std::atomic<bool> nominalSingular_{false};  ///< verify mode: sensitiveNearSingularity() was tried
  /// The model at the nominal geometry (built by nominalModel() when first needed) and its parameter values.
  std::once_flag nominalOnce_;
  std::unique_ptr<model::RobotModel> nominal_;
  std::vector<double> nominalValues_;
};

}  // namespace verify
}  // namespace pkm_accuracy
