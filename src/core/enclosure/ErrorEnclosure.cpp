#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

#include <limits>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"
#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PaperBaselineEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

std::vector<std::string> enclosureNames() { return {"second_order", "mean_value", "precond", "paper_baseline"}; }

std::unique_ptr<ErrorEnclosure> makeEnclosure(const std::string& name) {
  if (name == "second_order" || name == "default") return std::make_unique<MeanValueEnclosure>(true);
  if (name == "mean_value") return std::make_unique<MeanValueEnclosure>(false);
  if (name == "precond") return std::make_unique<PreconditionedEnclosure>();
  if (name == "paper_baseline") return std::make_unique<PaperBaselineEnclosure>();
  std::string list;
  for (const auto& n : enclosureNames()) list += (list.empty() ? "" : ", ") + n;
  throw InvalidArgument("method: expected one of " + list + ", got '" + name + "'");
}

IVec errorFromJacobian(const IMat& jacobian, const std::vector<double>& sensorError) {
  const int n = static_cast<int>(jacobian.rows());
  IVec f(n);
  for (int k = 0; k < n; ++k) {
    Interval s(0.0);
    for (int j = 0; j < n; ++j) s += abs(jacobian(k, j)) * Interval(sensorError[j]);
    f[k] = s;
  }
  return f;
}

bool errorAtPose(const model::RobotModel& model, const IVec& pose, IVec& f) {
  const IMat m = model.inverseJacobian(pose);
  DMat c;
  if (!approximateInverse(midpoint(m), c)) return false;
  IMat n;
  if (!gaussInverse(multiply(c, m), n, false)) return false;
  f = errorFromJacobian(multiply(n, c), model.sensorError());
  return true;
}

DVec errorAtPoseDouble(const model::RobotModel& model, const DVec& pose) {
  DMat inv;
  const int n = model.dof();
  if (!approximateInverse(model.inverseJacobian(pose), inv)) {
    return DVec::Constant(n, std::numeric_limits<double>::infinity());
  }
  DVec f(n);
  for (int k = 0; k < n; ++k) {
    double s = 0.0;
    for (int j = 0; j < n; ++j) s += std::abs(inv(k, j)) * model.sensorError()[j];
    f[k] = s;
  }
  return f;
}

}  // namespace enclosure
}  // namespace pkm_accuracy
