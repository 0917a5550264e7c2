#include "pkm_accuracy/core/enclosure/PaperBaselineEnclosure.hpp"

#include <limits>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace enclosure {

void PaperBaselineEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  const int n = model.dof();
  const std::vector<double>& e = model.sensorError();
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.lower = DVec::Zero(n);
  out.splitScore.resize(0);
  const IMat m = model.inverseJacobian(box.pose);
  const int count = 1 << (n - 1);  // s_0 = +1; -s gives -x
  // Right-hand sides in chunks of kMaxDof columns (the fixed capacity of IMat).
  DVec best = DVec::Zero(n);
  for (int first = 0; first < count; first += kMaxDof) {
    const int cols = std::min(kMaxDof, count - first);
    IMat rhs(n, cols);
    for (int c = 0; c < cols; ++c) {
      const int s = first + c;
      for (int j = 0; j < n; ++j) {
        const bool negative = j > 0 && ((s >> (j - 1)) & 1);
        rhs(j, c) = Interval(negative ? -e[j] : e[j]);
      }
    }
    IMat x;
    if (!gaussSolve(m, rhs, x, true)) return;
    for (int c = 0; c < cols; ++c)
      for (int k = 0; k < n; ++k) best[k] = std::max(best[k], x(k, c).mag());
  }
  out.upper = best;
}

}  // namespace enclosure
}  // namespace pkm_accuracy
