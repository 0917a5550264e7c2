#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

DVec centreOf(const IVec& box) {
  DVec c(box.size());
  for (int i = 0; i < box.size(); ++i) c[i] = box[i].mid();
  return c;
}

void identityPoseView(const IVec& box, bool gradient, enclosure::BoxInput& out) {
  const int n = static_cast<int>(box.size());
  out.variables = n;
  out.pose = box;
  out.centrePose.resize(n);
  out.deviation.resize(n);
  for (int i = 0; i < n; ++i) {
    const double c = box[i].mid();
    out.centrePose[i] = Interval(c);
    out.deviation[i] = box[i] - Interval(c);
  }
  out.hasGradient = gradient;
  if (gradient) {
    for (int i = 0; i < n; ++i) out.dualPose[i] = DualI::variable(box[i], i);
    for (int i = n; i < kMaxDof; ++i) out.dualPose[i] = DualI(Interval(0.0));
  }
}

}  // namespace domain
}  // namespace pkm_accuracy
