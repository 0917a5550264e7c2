// Method 3, "symbolic_precond" (seed paper section 4.1), for the Gough platform. With the un-normalised inverse
// Jacobian M' (row i: [d_i, (R (b_i - c)) x d_i], d_i = p + R b_i - A_i, so J^-1 = diag(1/L) M' and
// J = M'^-1 diag(L)), the preconditioned product C M' is expanded symbolically so that each position variable
// occurs once per entry:
//   position columns:  (C M')_k,l = p_l sum_i C_ki + (R beta_k)_l - sum_i C_ki A_i,l,   beta_k = sum_i C_ki b_i
//   rotation columns:  (C M')_k,3+l = ((R gamma_k) x p)_l - (sum_i C_ki (R (b_i - c)) x A_i)_l - (R delta_k)_l,
//                      gamma_k = sum_i C_ki (b_i - c),  delta_k = sum_i C_ki (c x b_i),
// then N' = (C M')^-1 by interval Gauss elimination and f_k = sum_j |(N' C)_kj| L_j e_j with L_j enclosing the
// leg lengths. C is the inverse of M' at the box centre. Models other than the Gough platform fall back to
// "precond".
// Contract: enclose() fills out.upper / out.lower (certified, +inf / 0 where M' or C M' cannot be inverted), no
// hints. Derivation and symbols: docs/enclosures.md.
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class SymbolicPreconditionedEnclosure final : public ErrorEnclosure {
 public:
  std::string name() const override { return "symbolic_precond"; }
  bool needsGradient() const override { return false; }
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
