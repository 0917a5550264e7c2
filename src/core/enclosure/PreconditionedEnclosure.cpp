#include "pkm_accuracy/core/enclosure/PreconditionedEnclosure.hpp"

#include <limits>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace enclosure {

void PreconditionedEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  const int n = model.dof();
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.lower = DVec::Zero(n);
  out.splitScore.resize(0);
  const IMat m = model.inverseJacobian(box.pose);
  DMat c;
  if (!approximateInverse(midpoint(m), c)) return;
  IMat inv;
  if (!gaussInverse(multiply(c, m), inv, true)) return;
  const IVec f = errorFromJacobian(multiply(inv, c), model.sensorError());
  for (int k = 0; k < n; ++k) {
    out.upper[k] = f[k].upper();
    out.lower[k] = f[k].lower();
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
