// "combined": second_order and symbolic_precond on the same box, keeping for every component the tighter upper
// bound and the larger lower bound (both are certified, so their intersection is). Symbolic preconditioning wins on
// large boxes, the second-order form on small ones (docs/enclosures.md); the bisection hints and internals are
// those of second_order.
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/SymbolicPreconditionedEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class CombinedEnclosure final : public ErrorEnclosure {
 public:
  std::string name() const override { return "combined"; }
  bool needsGradient() const override { return true; }
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;

 private:
  MeanValueEnclosure secondOrder_{MeanValueEnclosure::Bound::SecondOrderColumns};
  SymbolicPreconditionedEnclosure symbolic_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
