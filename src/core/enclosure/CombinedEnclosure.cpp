#include "pkm_accuracy/core/enclosure/CombinedEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

void CombinedEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  secondOrder_.enclose(model, box, out);
  ErrorBounds other;
  symbolic_.enclose(model, box, other);
  for (int k = 0; k < out.upper.size(); ++k) {
    out.upper[k] = std::min(out.upper[k], other.upper[k]);
    out.lower[k] = std::max(out.lower[k], other.lower[k]);
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
