#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

#include <algorithm>
#include <limits>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/CombinedEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"
#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PaperBaselineEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedEnclosure.hpp"
#include "pkm_accuracy/core/enclosure/SymbolicPreconditionedEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

bool BoxInput::variablesArePose(int n) const {
  if (!hasGradient || variables != n) return false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < kMaxDof; ++j)
      if (dualPose[i].d(j) != Interval(i == j ? 1.0 : 0.0)) return false;
  return true;
}

std::vector<std::string> enclosureNames() {
  return {"second_order", "combined", "mean_value", "symbolic_precond", "precond", "paper_baseline"};
}

std::unique_ptr<ErrorEnclosure> makeEnclosure(const std::string& name) {
  if (name == "second_order" || name == "default")
    return std::make_unique<MeanValueEnclosure>(MeanValueEnclosure::Bound::SecondOrderColumns);
  if (name == "mean_value") return std::make_unique<MeanValueEnclosure>(MeanValueEnclosure::Bound::JacobianEntries);
  if (name == "precond") return std::make_unique<PreconditionedEnclosure>();
  if (name == "symbolic_precond") return std::make_unique<SymbolicPreconditionedEnclosure>();
  if (name == "combined") return std::make_unique<CombinedEnclosure>();
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

bool errorGradient(const ErrorBounds& bounds, const std::vector<double>& sensorError, int k, IVec& gradient) {
  const EnclosureInternals& in = bounds.internals;
  if (!in.valid) return false;
  const int n = static_cast<int>(in.inverse.rows());
  // v = C w_k as an interval vector (the rounding of C w_k is enclosed).
  IVec v = IVec::Constant(n, Interval(0.0));
  for (int j = 0; j < n; ++j) {
    const Interval& jkj = in.jacobian(k, j);
    const double sign = jkj.lower() > 0.0 ? 1.0 : (jkj.upper() < 0.0 ? -1.0 : 0.0);
    if (sign == 0.0) return false;
    const Interval w(sign * sensorError[j]);
    for (int l = 0; l < n; ++l) v[l] += Interval(in.c(l, j)) * w;
  }
  IVec u = IVec::Constant(n, Interval(0.0));  // N v
  for (int r = 0; r < n; ++r)
    for (int l = 0; l < n; ++l) u[r] += in.inverse(r, l) * v[l];
  gradient.resize(in.variables);
  for (int i = 0; i < in.variables; ++i) {
    Interval g(0.0);
    for (int r = 0; r < n; ++r) {
      Interval y(0.0);  // (D_i u)_r
      for (int l = 0; l < n; ++l) y += in.d[i](r, l) * u[l];
      g += in.inverse(k, r) * y;
    }
    gradient[i] = -g;
  }
  return true;
}

bool errorAtPose(const model::RobotModel& model, const IVec& pose, IVec& f, GMat* sensitivity, unsigned rows) {
  if (sensitivity) sensitivity->resize(0, 0);
  const int dof = static_cast<int>(pose.size());
  if (model.geometryParameterCount() > 0 && model.hasGeometryUncertainty()) {
    // With uncertain geometry, interval coefficients treat every anchor coordinate as independent; the second-order
    // form keeps the first-order effect of each one exact, which tightens both ends (the lower end is what
    // certifies "exceeds for every admissible geometry"). The pose is a (thin) box: no box variables.
    BoxInput in;
    in.variables = 0;
    in.pose = pose;
    in.centrePose = pose;
    in.deviation.resize(0);
    for (int i = 0; i < dof; ++i) in.dualPose[i] = DualI(pose[i]);
    for (int i = dof; i < kMaxDof; ++i) in.dualPose[i] = DualI(Interval(0.0));
    in.hasGradient = true;
    in.rows = rows;
    ErrorBounds b;
    MeanValueEnclosure(MeanValueEnclosure::Bound::SecondOrderColumns).enclose(model, in, b);
    if (b.upper.size() == dof && b.bounded(rows)) {
      f.resize(dof);
      for (int k = 0; k < dof; ++k) f[k] = Interval(std::max(0.0, b.lower[k]), b.upper[k]);
      if (sensitivity) *sensitivity = b.geometrySensitivity;
      return true;
    }
  }
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
