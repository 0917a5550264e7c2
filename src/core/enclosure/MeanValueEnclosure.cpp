#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace enclosure {

void MeanValueEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  const int n = model.dof();
  const int vars = box.variables;
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.internals.valid = false;
  out.componentSmear.resize(0, 0);
  out.lower = DVec::Zero(n);
  out.splitScore = DVec::Constant(vars, 1.0);

  MatrixWithGradient mg;
  model.inverseJacobian(box.dualPose, mg);
  const IMat centre = model.inverseJacobian(box.centrePose);
  DMat c;
  if (!approximateInverse(midpoint(centre), c)) return;

  // A = C J^-1(centre) + sum_i (C dJ^-1/dt_i) dev_i, intersected with the naive C J^-1(box).
  const IMat a0 = multiplyMidRad(c, centre);
  IMat a = a0;
  std::array<IMat, kMaxDof> cds;
  for (int i = 0; i < vars; ++i) {
    cds[i] = multiplyMidRad(c, mg.d[i]);
    const IMat& cd = cds[i];
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
  const IMat jac = multiplyMidRad(inv, c);
  const std::vector<double>& e = model.sensorError();
  const IVec f = errorFromJacobian(jac, e);
  for (int k = 0; k < n; ++k) {
    out.upper[k] = f[k].upper();
    out.lower[k] = f[k].lower();
  }
  if (box.keepInternals) {
    out.internals.valid = true;
    out.internals.variables = vars;
    out.internals.c = c;
    out.internals.inverse = inv;
    out.internals.d = cds;
    out.internals.jacobian = jac;
  }
  if (!secondOrder_) return;

  // Second-order form of f_k itself. With E(t) = C J^-1(t) - I, N = (I + E)^-1 = I - E + E^2 N, and the mean-value
  // form E(t) in E0 + sum_i D_i dev_i (D_i = C dJ^-1/dt_i over the box, E0 = C J^-1(centre) - I):
  //   N(t) in (I - E0 + R) - sum_i D_i dev_i,   R in E_box^2 N_box (second order in the box size).
  // Where J_kj keeps a sign s_kj on the box, |J_kj| = s_kj J_kj, so with w_k = s_k o e and v_k = C w_k:
  //   sum_{j signed} |J_kj| e_j = (N v_k)_k  in  (I - E0 + R)_k. v_k - sum_i (D_i v_k)_k dev_i,
  // where the first-order coefficients (D_i v_k)_k now cancel across j instead of adding up entry by entry.
  // Entries whose sign may change are bounded by their magnitude. Both bounds are valid; the tighter one is kept.
  DMat magE(n, n), magN(n, n);
  for (int r = 0; r < n; ++r)
    for (int q = 0; q < n; ++q) {
      magE(r, q) = (a(r, q) - Interval(r == q ? 1.0 : 0.0)).mag();
      magN(r, q) = inv(r, q).mag();
    }
  // Products of non-negative matrices: the computed value times (1 + 1e-13) bounds the exact one in any rounding
  // mode (relative error below 2 gamma_6 < 3e-15 per product); 1e-300 covers underflow.
  const DMat remainder = ((magE * magE) * magN) * (1.0 + 1e-13) + DMat::Constant(n, n, 1e-300);
  if (!remainder.allFinite()) return;
  DVec smear = DVec::Zero(vars);
  out.componentSmear = DMat::Zero(n, vars);
  for (int k = 0; k < n; ++k) {
    Interval rest(0.0);
    IVec v = IVec::Constant(n, Interval(0.0));
    for (int j = 0; j < n; ++j) {
      const double sign = jac(k, j).lower() > 0.0 ? 1.0 : (jac(k, j).upper() < 0.0 ? -1.0 : 0.0);
      if (sign == 0.0) {
        rest += Interval(jac(k, j).mag()) * Interval(e[j]);
        continue;
      }
      const double w = sign * e[j];  // exact
      for (int l = 0; l < n; ++l) v[l] += Interval(c(l, j)) * Interval(w);
    }
    Interval value(0.0);
    for (int l = 0; l < n; ++l) {
      const Interval nkl = Interval(k == l ? 2.0 : 0.0) - a0(k, l) + Interval(-remainder(k, l), remainder(k, l));
      value += nkl * v[l];
    }
    Interval linear[kMaxDof];
    for (int i = 0; i < vars; ++i) {
      Interval g(0.0);
      for (int l = 0; l < n; ++l) g += cds[i](k, l) * v[l];
      linear[i] = g * box.deviation[i];
      value -= linear[i];
    }
    out.upper[k] = std::min(out.upper[k], (value + rest).upper());
    out.lower[k] = std::max(out.lower[k], value.lower());
    // Bisection hint: each variable's share of the width of this bound, relative to the bound.
    if (out.upper[k] > 0.0 && std::isfinite(out.upper[k])) {
      for (int i = 0; i < vars; ++i) {
        out.componentSmear(k, i) = linear[i].mag() / out.upper[k];
        smear[i] = std::max(smear[i], out.componentSmear(k, i));
      }
    }
  }
  if (smear.maxCoeff() > 0.0) out.splitScore = smear;
}

}  // namespace enclosure
}  // namespace pkm_accuracy
