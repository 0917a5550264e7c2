// Branch-and-bound over a domain: certifies SAFE / UNSAFE / UNDECIDED against thresholds, or brackets the maximal
// error of every component (seed paper's algorithms, parallel with oneTBB).
//
// Soundness: SAFE means every box of the domain got certified upper bounds below every threshold; UNSAFE comes with
// a witness point whose certified lower bound exceeds a threshold; anything else is UNDECIDED with its reason.
// Memory: the search is depth-first in every worker (pending boxes <= depth x threads), recorded boxes are capped.
#pragma once

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"

namespace pkm_accuracy {
namespace verify {

class Verifier {
 public:
  /// Runs one job. Algorithmic outcomes are in the result; bad input throws.
  /// @throws InvalidArgument for bad options (thresholds missing/non-positive/NaN in Verify mode, wrong sizes,
  ///         alpha <= 0, unknown method, negative budgets or widths), naming the field.
  /// @throws InternalError when the self-check (VerifierOptions::self_check) finds a point outside its box's bounds.
  static VerifierResult run(const model::RobotModel& model, const domain::Domain& domain,
                            const VerifierOptions& options);

  /// Checks the options against a model and a domain without running. @throws InvalidArgument as run().
  static void validate(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& options);
};

}  // namespace verify
}  // namespace pkm_accuracy
