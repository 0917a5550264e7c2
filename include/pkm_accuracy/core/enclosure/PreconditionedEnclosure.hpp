// Method 2, "precond": C = (mid J^-1(box))^-1 in double, A = C J^-1(box) (close to I), N = A^-1 by interval Gauss
// elimination, J = N C. Certified because J = (C J^-1)^-1 C holds exactly for any invertible C.
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class PreconditionedEnclosure final : public ErrorEnclosure {
 public:
  std::string name() const override { return "precond"; }
  bool needsGradient() const override { return false; }
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
