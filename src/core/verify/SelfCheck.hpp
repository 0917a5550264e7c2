// The verifier's self-check (VerifierOptions::self_check): the certified bounds of each enclosed box against plain
// double evaluations of the worst error at a few points of the box and of its geometry ranges. Internal to the core.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace verify {

class SelfCheck {
 public:
  /// Points evaluated per box.
  static constexpr int kPoints = 4;
  /// Round-off margin of a point value against a bound: relative kRelative plus kPerCondition times the condition
  /// number of J^-1 at the point (the double inverse's relative error is a small multiple of eps times it).
  static constexpr double kRelative = 1e-9;
  static constexpr double kPerCondition = 1e-14;

  /// `method`: the enclosure method's name (for the messages).
  SelfCheck(const domain::Domain& domain, std::string method) : domain_(domain), method_(std::move(method)) {}

  /// Checks the bounds of the components in `rows` (bit k: component k; infinite bounds are skipped) that `bounds`
  /// certifies over `box` and the geometry ranges `ranges` of `model` (empty: its geometry is exact), at kPoints
  /// points. Thread-safe (the points come from a generator seeded by the box and the ranges). @return the number of
  /// points evaluated (those where J^-1 is invertible in double). @throws InternalError on a value outside a bound
  /// beyond the round-off margin, naming the method, the box, the point, the geometry and the values.
  int check(const model::RobotModel& model, const std::vector<Interval>& ranges, const IVec& box, unsigned rows,
            const enclosure::ErrorBounds& bounds) const;

 private:
  /// A seed that depends on every bit of the box's and the ranges' bounds.
  static std::uint64_t seedOf(const IVec& box, const std::vector<Interval>& ranges);
  /// Point i of the box: 0 its centre, 1 a random vertex, else uniformly random (degenerate variables: their value).
  static DVec boxPoint(const IVec& box, int i, std::mt19937_64& rng);
  /// Geometry point i of the ranges: 2 uniformly random inside, else a random vertex.
  static std::vector<double> geometryPoint(const std::vector<Interval>& ranges, int i, std::mt19937_64& rng);
  /// The worst error of every component at `pose` (double) and the infinity-norm condition number of J^-1 there.
  /// @return false if J^-1 is not invertible in double there.
  static bool errorAt(const model::RobotModel& model, const DVec& pose, DVec& f, double& condition);
  /// Throws the InternalError for component k at point t (geometry g, empty: exact) whose value lies outside the bound.
  [[noreturn]] void fail(const model::RobotModel& model, const IVec& box, const std::vector<Interval>& ranges, int k,
                         const char* which, double bound, double value, double condition, const DVec& t,
                         const DVec& pose, const std::vector<double>& g) const;

  const domain::Domain& domain_;
  const std::string method_;
};

}  // namespace verify
}  // namespace pkm_accuracy
