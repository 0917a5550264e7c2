#include "pkm_accuracy/core/model/RobotModel.hpp"

#include <Eigen/LU>

#include "pkm_accuracy/core/Exceptions.hpp"

#include <string>

namespace pkm_accuracy {
namespace model {

namespace {
[[noreturn]] void noParameter(const RobotModel& m, int p) {
  throw InvalidArgument("geometry parameter " + std::to_string(p) + ": " + m.name() + " has " +
                        std::to_string(m.geometryParameterCount()) + " uncertain geometry parameters");
}
}  // namespace

std::string RobotModel::jointName(int j) const { return "leg_" + std::to_string(j) + " [m]"; }
std::string RobotModel::geometryParameterName(int p) const { noParameter(*this, p); }
Interval RobotModel::geometryParameterRange(int p) const { noParameter(*this, p); }
double RobotModel::geometryParameterCentre(int p) const { noParameter(*this, p); }
bool RobotModel::geometryDerivatives(const IVec&, GeometryDerivatives& out) const {
  out.count = 0;
  return false;
}
std::unique_ptr<RobotModel> RobotModel::restrictGeometry(const std::vector<Interval>&) const {
  throw InvalidArgument("geometry: " + name() + " has no uncertain geometry parameters to restrict");
}
std::unique_ptr<RobotModel> RobotModel::fixGeometryParameters(const GVec&) const {
  throw InvalidArgument("geometry: " + name() + " has no uncertain geometry parameters to fix");
}

DMat RobotModel::jacobian(const DVec& pose) const {
  const DMat m = inverseJacobian(pose);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
  // Relative pivot threshold: J^-1 has unit-length position parts, so its entries are O(1) or O(size).
  if (!lu.isInvertible() || std::abs(lu.determinant()) < 1e-300) {
    throw SingularMatrix("RobotModel::jacobian: J^-1 is singular at the given pose");
  }
  return lu.inverse();
}

DVec RobotModel::worstErrorAt(const DVec& pose) const {
  const DMat j = jacobian(pose);
  const std::vector<double>& e = sensorError();
  DVec f(dof());
  for (int k = 0; k < dof(); ++k) {
    double s = 0.0;
    for (int l = 0; l < dof(); ++l) s += std::abs(j(k, l)) * e[l];
    f[k] = s;
  }
  return f;
}

}  // namespace model
}  // namespace pkm_accuracy
