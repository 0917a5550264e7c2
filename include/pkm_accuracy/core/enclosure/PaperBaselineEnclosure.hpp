// Method 1, "paper_baseline": the seed paper's starting point. Interval Gauss elimination (partial pivoting on the
// mignitude) directly on the raw interval matrix J^-1(box), with the 2^(n-1) sign vectors s of the sensor errors
// as right-hand sides (s and -s give opposite solutions): max_s |x_k(s)| = sum_j |J_kj| e_j. No preconditioning.
// Kept as the reference for benchmarks; it fails (returns +inf) on all but small boxes.
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class PaperBaselineEnclosure final : public ErrorEnclosure {
 public:
  std::string name() const override { return "paper_baseline"; }
  bool needsGradient() const override { return false; }
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
