#include "pkm_accuracy/core/verify/VerifierResult.hpp"

namespace pkm_accuracy {
namespace verify {

std::string toString(Verdict v) {
  switch (v) {
    case Verdict::Safe:
      return "SAFE";
    case Verdict::Unsafe:
      return "UNSAFE";
    case Verdict::Undecided:
      return "UNDECIDED";
  }
  return "UNDECIDED";
}

std::string toString(UndecidedReason r) {
  switch (r) {
    case UndecidedReason::None:
      return "none";
    case UndecidedReason::PrecisionLimit:
      return "precision_limit";
    case UndecidedReason::BoxBudget:
      return "box_budget";
    case UndecidedReason::TimeBudget:
      return "time_budget";
    case UndecidedReason::Cancelled:
      return "cancelled";
    case UndecidedReason::NoThresholds:
      return "no_thresholds";
    case UndecidedReason::UncertaintySensitive:
      return "uncertainty_sensitive";
  }
  return "none";
}

}  // namespace verify
}  // namespace pkm_accuracy
