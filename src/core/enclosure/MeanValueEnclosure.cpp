#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"

#include <limits>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace enclosure {

void MeanValueEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  const int n = model.dof();
  const int vars = box.variables;
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.lower = DVec::Zero(n);
  out.splitScore = DVec::Constant(vars, 1.0);

  MatrixWithGradient mg;
  model.inverseJacobian(box.dualPose, mg);
  const IMat centre = model.inverseJacobian(box.centrePose);
  DMat c;
  if (!approximateInverse(midpoint(centre), c)) return;

  // A = C J^-1(centre) + sum_i (C dJ^-1/dt_i) dev_i, intersected with the naive C J^-1(box).
  IMat a = multiplyMidRad(c, centre);
  for (int i = 0; i < vars; ++i) {
    const IMat cd = multiplyMidRad(c, mg.d[i]);
    const Interval dev = box.deviation[i];
    double score = 0.0;
    for (int r = 0; r < n; ++r) {
      for (int s = 0; s < n; ++s) {
        a(r, s) += cd(r, s) * dev;
        score = std::max(score, cd(r, s).mag());
      }
    }
    out.splitScore[i] = score * dev.mag();
  }
  const IMat naive = multiplyMidRad(c, mg.value);
  for (int r = 0; r < n; ++r)
    for (int s = 0; s < n; ++s) {
      const Interval both = intersect(a(r, s), naive(r, s));
      // Both contain the true range, so the intersection cannot be empty except through a bug; keep `a` then.
      if (!both.isEmpty()) a(r, s) = both;
    }

  IMat inv;
  if (!gaussInverse(a, inv, false)) return;
  const IVec f = errorFromJacobian(multiplyMidRad(inv, c), model.sensorError());
  for (int k = 0; k < n; ++k) {
    out.upper[k] = f[k].upper();
    out.lower[k] = f[k].lower();
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
