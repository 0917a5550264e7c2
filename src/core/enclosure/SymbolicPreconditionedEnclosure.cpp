#include "pkm_accuracy/core/enclosure/SymbolicPreconditionedEnclosure.hpp"

#include <limits>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedEnclosure.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"

namespace pkm_accuracy {
namespace enclosure {
namespace {

using Vec3 = std::array<Interval, 3>;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Vec3 rotate(const Interval r[3][3], const Vec3& v) {
  Vec3 out;
  for (int k = 0; k < 3; ++k) out[k] = r[k][0] * v[0] + r[k][1] * v[1] + r[k][2] * v[2];
  return out;
}

/// The anchors (intervals when uncertain) and the tool point of the geometry.
void anchorsOf(const model::GoughGeometry& g, Vec3 a[6], Vec3 b[6], Vec3& c) {
  auto around = [](double v, double h) {
    return h > 0.0 ? Interval(interval::rounding::subDown(v, h), interval::rounding::addUp(v, h)) : Interval(v);
  };
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) {
      a[i][k] = around(g.base_anchors[i][k], g.base_anchor_halfwidth.empty() ? 0.0 : g.base_anchor_halfwidth[i][k]);
      b[i][k] = around(g.platform_anchors[i][k],
                       g.platform_anchor_halfwidth.empty() ? 0.0 : g.platform_anchor_halfwidth[i][k]);
    }
  for (int k = 0; k < 3; ++k) c[k] = around(g.tool_point[k], g.tool_point_halfwidth[k]);
}

/// C = (M' at the box centre)^-1, M' = diag(L) J^-1 (double; any approximation is fine for a preconditioner).
/// @return false if M' cannot be inverted there.
bool preconditionerAtCentre(const model::RobotModel& model, const BoxInput& box, DMat& cm) {
  DVec centre(6);
  for (int i = 0; i < 6; ++i) centre[i] = box.pose[i].mid();
  const DMat mc = model.inverseJacobian(centre);
  const DVec lc = model.legLengths(centre);
  DMat mprime(6, 6);
  for (int i = 0; i < 6; ++i) mprime.row(i) = mc.row(i) * lc[i];
  return approximateInverse(mprime, cm);
}

/// R = Rz(yaw) Ry(pitch) Rx(roll) over the box.
void rotationOver(const BoxInput& box, Interval r[3][3]) {
  const Interval sr = interval::sin(box.pose[3]), cr = interval::cos(box.pose[3]);
  const Interval sp = interval::sin(box.pose[4]), cp = interval::cos(box.pose[4]);
  const Interval sy = interval::sin(box.pose[5]), cy = interval::cos(box.pose[5]);
  const Interval rot[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                              {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                              {-sp, cp * sr, cp * cr}};
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) r[k][l] = rot[k][l];
}

/// C M' expanded symbolically (the header's formulas), each position variable once per entry.
IMat symbolicProduct(const DMat& cm, const Interval r[3][3], const Vec3& p, const Vec3 a[6], const Vec3 b[6],
                     const Vec3& c) {
  Vec3 z[6];  // (R (b_i - c)) x A_i, per leg
  for (int i = 0; i < 6; ++i) {
    const Vec3 bc = {b[i][0] - c[0], b[i][1] - c[1], b[i][2] - c[2]};
    z[i] = cross(rotate(r, bc), a[i]);
  }
  IMat am(6, 6);
  for (int k = 0; k < 6; ++k) {
    Interval s(0.0);
    Vec3 beta{Interval(0.0), Interval(0.0), Interval(0.0)}, gamma = beta, delta = beta, sumA = beta, sumZ = beta;
    for (int i = 0; i < 6; ++i) {
      const Interval cki(cm(k, i));
      s += cki;
      const Vec3 cb = cross(c, b[i]);
      for (int l = 0; l < 3; ++l) {
        beta[l] += cki * b[i][l];
        gamma[l] += cki * (b[i][l] - c[l]);
        delta[l] += cki * cb[l];
        sumA[l] += cki * a[i][l];
        sumZ[l] += cki * z[i][l];
      }
    }
    const Vec3 rbeta = rotate(r, beta), rdelta = rotate(r, delta);
    const Vec3 rgxp = cross(rotate(r, gamma), p);
    for (int l = 0; l < 3; ++l) {
      am(k, l) = p[l] * s + rbeta[l] - sumA[l];
      am(k, 3 + l) = rgxp[l] - sumZ[l] - rdelta[l];
    }
  }
  return am;
}

}  // namespace

void SymbolicPreconditionedEnclosure::enclose(const model::RobotModel& model, const BoxInput& box,
                                              ErrorBounds& out) const {
  const auto* gough = dynamic_cast<const model::GoughPlatform*>(&model);
  if (gough == nullptr) {
    PreconditionedEnclosure().enclose(model, box, out);
    return;
  }
  const int n = 6;
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.lower = DVec::Zero(n);
  out.splitScore.resize(0);
  out.internals.valid = false;
  const std::vector<double>& e = gough->sensorError();
  Vec3 a[6], b[6], c;
  anchorsOf(gough->geometry(), a, b, c);
  DMat cm;
  if (!preconditionerAtCentre(model, box, cm)) return;
  Interval r[3][3];
  rotationOver(box, r);
  const Vec3 p = {box.pose[0], box.pose[1], box.pose[2]};
  const IMat am = symbolicProduct(cm, r, p, a, b, c);
  IMat inv;
  if (!gaussInverse(am, inv, false)) return;
  const IMat jprime = multiply(inv, cm);  // M'^-1
  const IVec len = gough->legLengths(box.pose);
  for (int k = 0; k < 6; ++k) {
    Interval f(0.0);
    for (int j = 0; j < 6; ++j) f += abs(jprime(k, j)) * len[j] * Interval(e[j]);
    out.upper[k] = f.upper();
    out.lower[k] = f.lower();
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
