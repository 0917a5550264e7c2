// The VerifierResult of a finished search: the evidence the SearchState collected, the statistics, the verdict and
// its reason (verify mode: witness, singular pose, sensitive poses, undecided boxes; max-error mode: the bracket of
// each component's maximum against the tolerance and the thresholds), and the one-line message. Runs once the
// workers are done. Internal to the core.
#pragma once

#include <sstream>
#include <string>

#include "SearchContext.hpp"
#include "SearchState.hpp"

namespace pkm_accuracy {
namespace verify {

class ResultAssembly {
 public:
  explicit ResultAssembly(const SearchContext& context) : c_(context) {}

  /// The result; moves the evidence out of `state`.
  VerifierResult assemble(SearchState& state) const;

 private:
  /// Verify mode: the verdict, its reason and the message (`reason`: why the search stopped, for UNDECIDED).
  void verifyVerdict(VerifierResult& r, UndecidedReason reason, bool haveWitness, std::ostringstream& msg) const;
  /// "UNDECIDED (uncertainty_sensitive): ..." for the first recorded sensitive pose.
  void sensitiveText(const VerifierResult& r, std::ostringstream& msg) const;
  /// Max-error mode: each component's bracket [lower, upper] of its maximum, where it is reached, and whether every
  /// bracket is within the tolerance (`converged`).
  void bracket(VerifierResult& r, const SearchState& state) const;
  /// Max-error mode: the verdict against the thresholds (if given), its reason and the message.
  void maxErrorVerdict(VerifierResult& r, UndecidedReason reason, std::ostringstream& msg) const;
  /// "det J^-1 has certified opposite signs, for ..., at <point> and at <point>" in the domain's variables.
  std::string singularText(const VerifierResult& r) const;

  const SearchContext& c_;
};

}  // namespace verify
}  // namespace pkm_accuracy
