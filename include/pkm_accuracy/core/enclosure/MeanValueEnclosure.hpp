// Method 5, "mean_value" (the default): mean-value form of the *preconditioned* matrix.
//   C = J^-1(centre)^-1 (double),
//   C J^-1(t) in C J^-1(centre) + sum_i [C dJ^-1/dt_i](box) (t_i - centre_i), intersected with C [J^-1](box);
//   N = (C J^-1)^-1 by interval Gauss elimination (A is close to I), J = N C, f_k = sum_j |J_kj| e_j.
// The derivative enclosures come from forward-mode differentiation over the box (Dual<Interval>). The per-variable
// terms |C dJ^-1/dt_i| rad(t_i) are returned as bisection hints (the "smear" of the preconditioned matrix).
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

//
// With secondOrder (registry name "second_order", the default), a second bound of f_k is computed from the
// identity N = I - E + E^2 N (E = C J^-1 - I): its first-order part keeps the cancellations between the terms of
// sum_j |J_kj| e_j, its remainder is quadratic in the box size (see the .cpp); the tighter bound is returned.
class MeanValueEnclosure final : public ErrorEnclosure {
 public:
  explicit MeanValueEnclosure(bool secondOrder = false) : secondOrder_(secondOrder) {}
  std::string name() const override { return secondOrder_ ? "second_order" : "mean_value"; }
  bool needsGradient() const override { return true; }
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;

 private:
  bool secondOrder_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
