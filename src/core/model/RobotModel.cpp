#include "pkm_accuracy/core/model/RobotModel.hpp"

#include <Eigen/LU>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace model {

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
