// Outcome of a verification or max-error run, and the progress snapshots sent while it runs.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace verify {

enum class Verdict { Safe, Unsafe, Undecided };
enum class UndecidedReason { None, PrecisionLimit, BoxBudget, TimeBudget, Cancelled, NoThresholds };

std::string toString(Verdict v);          ///< "SAFE", "UNSAFE", "UNDECIDED"
std::string toString(UndecidedReason r);  ///< "none", "precision_limit", "box_budget", "time_budget", ...

struct Statistics {
  std::size_t boxes = 0;  ///< boxes processed (enclosures computed)
  int max_depth = 0;      ///< deepest bisection level reached
  double seconds = 0.0;   ///< wall time
  /// Fractions of the initial box volume (over variables of non-zero width) proven safe, proven unsafe (every
  /// point exceeds a threshold), left undecided, and outside the region.
  double safe_fraction = 0.0;
  double unsafe_fraction = 0.0;
  double undecided_fraction = 0.0;
  double outside_fraction = 0.0;
  int threads = 1;
  std::size_t monotonicity_hits = 0;  ///< component bounds tightened by the derivative (monotonicity) step
};

struct Progress {
  Statistics stats;
  DVec lower;  ///< MaxError: current certified lower bounds
  DVec upper;  ///< MaxError: current upper bound over the boxes closed so far
};

/// A box of the search that could not be decided, with the upper bounds the enclosure gave on it.
struct BoxRecord {
  IVec box;    ///< in the domain's variables
  DVec upper;  ///< per component (+inf if unbounded)
};

struct VerifierResult {
  Verdict verdict = Verdict::Undecided;
  UndecidedReason reason = UndecidedReason::None;
  std::string message;  ///< one human sentence

  // Verify mode, UNSAFE: a certified witness.
  DVec witness;       ///< the witness in the domain's variables (for a workspace: the pose)
  IVec witness_pose;  ///< enclosure of the witness pose (x, y, z, roll, pitch, yaw)
  int witness_component = -1;
  double witness_lower_bound = 0.0;  ///< certified: worst error of that component at the witness >= this
  DVec witness_error_lower;          ///< certified lower bounds of every component at the witness

  // MaxError mode (also filled where known in Verify mode): certified bounds of max f_k over the domain.
  DVec max_lower;                ///< attained: f_k(max_argmax[k]) >= max_lower[k]
  DVec max_upper;                ///< max over the domain of f_k <= max_upper[k] (+inf if unbounded)
  std::vector<DVec> max_argmax;  ///< per component: the variables of a point attaining max_lower
  bool converged = false;        ///< MaxError: upper - lower <= alpha for every component

  std::vector<BoxRecord> undecided_boxes;  ///< at most options.max_recorded_boxes
  std::size_t undecided_box_count = 0;     ///< all of them
  Statistics stats;
};

}  // namespace verify
}  // namespace pkm_accuracy
