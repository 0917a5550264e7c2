#include "pkm_accuracy/core/model/GoughPlatform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/MidRad.hpp"
#include "pkm_accuracy/core/interval/SegmentAffineForm.hpp"

namespace pkm_accuracy {
namespace model {
namespace {

using interval::sqr;

// One implementation of the kinematics for every scalar type S (double, Interval, Dual<Interval, N>) and geometry
// coefficient type G (double, Interval). `rows[i]` receives row i of J^-1, `lengths[i]` the length of leg i.
template <typename S, typename G>
void goughKinematics(const S pose[6], const std::array<std::array<G, 3>, 6>& a,
                     const std::array<std::array<G, 3>, 6>& b, const std::array<G, 3>& c, S rows[6][6], S lengths[6]) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S sr = sin(pose[3]), cr = cos(pose[3]);
  const S sp = sin(pose[4]), cp = cos(pose[4]);
  const S sy = sin(pose[5]), cy = cos(pose[5]);
  const S cysp = cy * sp, sysp = sy * sp;
  const S r[3][3] = {{cy * cp, cysp * sr - sy * cr, cysp * cr + sy * sr},
                     {sy * cp, sysp * sr + cy * cr, sysp * cr - cy * sr},
                     {-sp, cp * sr, cp * cr}};
  for (int i = 0; i < 6; ++i) {
    S rb[3], u[3], d[3];
    for (int k = 0; k < 3; ++k) {
      rb[k] = r[k][0] * b[i][0] + r[k][1] * b[i][1] + r[k][2] * b[i][2];
    }
    const G bc[3] = {b[i][0] - c[0], b[i][1] - c[1], b[i][2] - c[2]};
    for (int k = 0; k < 3; ++k) {
      u[k] = r[k][0] * bc[0] + r[k][1] * bc[1] + r[k][2] * bc[2];
      d[k] = pose[k] + rb[k] - a[i][k];
    }
    const S len = sqrt(sqr(d[0]) + sqr(d[1]) + sqr(d[2]));
    lengths[i] = len;
    rows[i][0] = d[0] / len;
    rows[i][1] = d[1] / len;
    rows[i][2] = d[2] / len;
    rows[i][3] = (u[1] * d[2] - u[2] * d[1]) / len;
    rows[i][4] = (u[2] * d[0] - u[0] * d[2]) / len;
    rows[i][5] = (u[0] * d[1] - u[1] * d[0]) / len;
  }
}

template <typename T>
std::array<std::array<T, 3>, 6> toArray(const std::vector<Eigen::Vector3d>& v) {
  std::array<std::array<T, 3>, 6> out;
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) out[i][k] = T(v[i][k]);
  return out;
}

Interval around(double v, double h) {
  return h > 0.0 ? Interval(interval::rounding::subDown(v, h), interval::rounding::addUp(v, h)) : Interval(v);
}

/// Derivative of one row of J^-1, (n, m) = (d / L, (u x d) / L), given the derivatives dd of d and du of u:
///   dL = (d . dd) / L,  dn = (dd - n dL) / L,  dm = (du x d + u x dd - m dL) / L.
void rowDerivative(const Interval d[3], const Interval u[3], const Interval n[3], const Interval m[3],
                   const Interval& len, const Interval dd[3], const Interval du[3], Interval out[6]) {
  // One division: x / L is enclosed by x * [1 / L] (an enclosure of the reciprocal), at most an ulp or so wider.
  const Interval inv = Interval(1.0) / len;
  const Interval dl = (d[0] * dd[0] + d[1] * dd[1] + d[2] * dd[2]) * inv;
  const Interval dw[3] = {du[1] * d[2] - du[2] * d[1] + (u[1] * dd[2] - u[2] * dd[1]),
                          du[2] * d[0] - du[0] * d[2] + (u[2] * dd[0] - u[0] * dd[2]),
                          du[0] * d[1] - du[1] * d[0] + (u[0] * dd[1] - u[1] * dd[0])};
  for (int k = 0; k < 3; ++k) {
    out[k] = (dd[k] - n[k] * dl) * inv;
    out[3 + k] = (dw[k] - m[k] * dl) * inv;
  }
}

/// R = Rz(yaw) Ry(pitch) Rx(roll) over a pose box, with the sines and cosines it is made of.
struct Rotation {
  Interval sr, cr, sp, cp, sy, cy, cysp, sysp;
  Interval r[3][3];
  /// dR/dpitch = Rz dRy/dpitch Rx, entry by entry.
  Interval pitch[3][3];
  explicit Rotation(const IVec& q)
      : sr(interval::sin(q[3])),
        cr(interval::cos(q[3])),
        sp(interval::sin(q[4])),
        cp(interval::cos(q[4])),
        sy(interval::sin(q[5])),
        cy(interval::cos(q[5])),
        cysp(cy * sp),
        sysp(sy * sp),
        r{{cy * cp, cysp * sr - sy * cr, cysp * cr + sy * sr},
          {sy * cp, sysp * sr + cy * cr, sysp * cr - cy * sr},
          {-sp, cp * sr, cp * cr}} {
    const Interval cycp = cy * cp, sycp = sy * cp;
    const Interval p[3][3] = {{-cysp, cycp * sr, cycp * cr}, {-sysp, sycp * sr, sycp * cr}, {-cp, -sp * sr, -sp * cr}};
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) pitch[k][l] = p[k][l];
  }
};

/// The rotation pieces in a scalar type S (interval::MidRad over a pose box, or interval::AffineForm in the pose
/// symbols): R, R_pitch, and the first and second derivatives of R v.
template <typename S>
struct RotationOps {
  S r[3][3], dp[3][3], sr, cr, sy, cy;
  S zero{0.0}, one{1.0};
  static void mul(const S m[3][3], const S v[3], S o[3]) {
    for (int k = 0; k < 3; ++k) o[k] = m[k][0] * v[0] + m[k][1] * v[1] + m[k][2] * v[2];
  }
  static void cross(const S x[3], const S y[3], S o[3]) {
    o[0] = x[1] * y[2] - x[2] * y[1];
    o[1] = x[2] * y[0] - x[0] * y[2];
    o[2] = x[0] * y[1] - x[1] * y[0];
  }
  /// x cross e_axis (no products).
  void crossUnit(const S x[3], int axis, S o[3]) const {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    o[axis] = zero;
    o[a1] = x[a2];
    o[a2] = -x[a1];
  }
  /// R_a v for a rotation variable a (3: roll, 4: pitch, 5: yaw).
  void first(int var, const S v[3], S o[3]) const {
    if (var == 3) {
      const S w[3] = {zero, -v[2], v[1]};
      mul(r, w, o);
    } else if (var == 4) {
      mul(dp, v, o);
    } else {
      S t[3];
      mul(r, v, t);
      o[0] = -t[1];
      o[1] = t[0];
      o[2] = zero;
    }
  }
  /// R_ab v for rotation variables 3 <= a <= b.
  void second(int va, int vb, const S v[3], S o[3]) const {
    const S ex[3] = {zero, -v[2], v[1]};  // e_x x v
    S t[3];
    if (va == 3 && vb == 3) {
      const S w[3] = {zero, -v[1], -v[2]};
      mul(r, w, o);
    } else if (va == 3 && vb == 4) {
      mul(dp, ex, o);
    } else if (va == 3) {  // (roll, yaw)
      mul(r, ex, t);
      o[0] = -t[1];
      o[1] = t[0];
      o[2] = zero;
    } else if (vb == 4) {  // (pitch, pitch)
      mul(r, v, t);
      const S s = cr * v[1] - sr * v[2];
      o[0] = -t[0] - sy * s;
      o[1] = -t[1] + cy * s;
      o[2] = -t[2];
    } else if (va == 4) {  // (pitch, yaw)
      mul(dp, v, t);
      o[0] = -t[1];
      o[1] = t[0];
      o[2] = zero;
    } else {  // (yaw, yaw)
      mul(r, v, t);
      o[0] = -t[0];
      o[1] = -t[1];
      o[2] = zero;
    }
  }
};

/// Midpoint-radius rotation pieces over a pose box.
struct RotationMR : RotationOps<interval::MidRad> {
  using S = interval::MidRad;
  explicit RotationMR(const Rotation& rot) {
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) {
        r[k][l] = S(rot.r[k][l]);
        dp[k][l] = S(rot.pitch[k][l]);
      }
    sr = S(rot.sr);
    cr = S(rot.cr);
    sy = S(rot.sy);
    cy = S(rot.cy);
  }
};

/// The first derivatives of row i of J^-1 with respect to the six pose coordinates, from d, u, n, m, 1 / L and the
/// platform anchor b (bv) and b - c (bc): d_a, u_a, L_a = n . d_a, n_a = (d_a - n L_a) / L, m_a = (u_a x d + u x d_a -
/// m L_a) / L.
template <typename S>
struct LegFirst {
  S da[6][3], ua[6][3], la[6], na[6][3], ma[6][3];
  LegFirst(const RotationOps<S>& rm, const S d[3], const S u[3], const S n[3], const S m[3], const S& inv,
           const S bv[3], const S bc[3]) {
    for (int va = 0; va < 6; ++va) {
      S wa[3];
      if (va < 3) {
        for (int k = 0; k < 3; ++k) {
          da[va][k] = k == va ? rm.one : rm.zero;
          ua[va][k] = rm.zero;
        }
        la[va] = n[va];
        rm.crossUnit(u, va, wa);  // w_a = u x e_a
      } else {
        rm.first(va, bv, da[va]);
        rm.first(va, bc, ua[va]);
        la[va] = n[0] * da[va][0] + n[1] * da[va][1] + n[2] * da[va][2];
        S t1[3], t2[3];
        RotationOps<S>::cross(ua[va], d, t1);
        RotationOps<S>::cross(u, da[va], t2);
        for (int k = 0; k < 3; ++k) wa[k] = t1[k] + t2[k];
      }
      for (int k = 0; k < 3; ++k) {
        na[va][k] = (da[va][k] - n[k] * la[va]) * inv;
        ma[va][k] = (wa[k] - m[k] * la[va]) * inv;
      }
    }
  }
};

/// The second derivatives (hn, hm) = d^2 (n, m) / dt_a dt_b (va <= vb) of row i of J^-1 (GoughPlatform::hessian).
template <typename S>
void legSecond(const RotationOps<S>& rm, const S d[3], const S u[3], const S n[3], const S m[3], const S& inv,
               const S bv[3], const S bc[3], const LegFirst<S>& f, int va, int vb, S hn[3], S hm[3]) {
  // (va <= vb) Translations have d_a = e_a, u_a = 0: d_ab = u_ab = 0 unless both are rotations, and the products
  // with e_a are component selections.
  const bool rotations = va >= 3;
  S dab[3] = {rm.zero, rm.zero, rm.zero}, uab[3] = {rm.zero, rm.zero, rm.zero}, wab[3] = {rm.zero, rm.zero, rm.zero};
  S lab;
  if (rotations) {
    rm.second(va, vb, bv, dab);
    rm.second(va, vb, bc, uab);
    lab = f.na[vb][0] * f.da[va][0] + f.na[vb][1] * f.da[va][1] + f.na[vb][2] * f.da[va][2] +
          (n[0] * dab[0] + n[1] * dab[1] + n[2] * dab[2]);
    S t[3];
    auto add = [&](const S x[3], const S y[3]) {
      RotationOps<S>::cross(x, y, t);
      for (int k = 0; k < 3; ++k) wab[k] += t[k];
    };
    add(uab, d);
    add(f.ua[va], f.da[vb]);
    add(f.ua[vb], f.da[va]);
    add(u, dab);
  } else {
    lab = f.na[vb][va];
    if (vb >= 3) rm.crossUnit(f.ua[vb], va, wab);  // u_b x e_a (u_a = 0, d_ab = u_ab = 0)
  }
  for (int k = 0; k < 3; ++k) {
    hn[k] = (dab[k] - f.na[vb][k] * f.la[va] - f.na[va][k] * f.la[vb] - n[k] * lab) * inv;
    hm[k] = (wab[k] - f.ma[vb][k] * f.la[va] - f.ma[va][k] * f.la[vb] - m[k] * lab) * inv;
  }
}

/// The pose coordinates as affine forms in N symbols (one per coordinate, the first six) and the rotation pieces
/// built from them: R = Rz(yaw) Ry(pitch) Rx(roll), its sines and cosines, and with `pitch` also dR/dpitch.
template <typename Aff>
void affineRotation(const IVec& q, Aff pose[6], RotationOps<Aff>& rm, bool pitch) {
  for (int m = 0; m < 6; ++m) pose[m] = Aff::variable(q[m], m);
  rm.sr = sin(pose[3]);
  rm.cr = cos(pose[3]);
  const Aff sp = sin(pose[4]), cp = cos(pose[4]);
  rm.sy = sin(pose[5]);
  rm.cy = cos(pose[5]);
  const Aff &sr = rm.sr, &cr = rm.cr, &sy = rm.sy, &cy = rm.cy;
  const Aff cysp = cy * sp, sysp = sy * sp;
  const Aff r[3][3] = {{cy * cp, cysp * sr - sy * cr, cysp * cr + sy * sr},
                       {sy * cp, sysp * sr + cy * cr, sysp * cr - cy * sr},
                       {-sp, cp * sr, cp * cr}};
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) rm.r[k][l] = r[k][l];
  if (!pitch) return;
  const Aff cycp = cy * cp, sycp = sy * cp;
  const Aff dp[3][3] = {{-cysp, cycp * sr, cycp * cr}, {-sysp, sycp * sr, sycp * cr}, {-cp, -sp * sr, -sp * cr}};
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) rm.dp[k][l] = dp[k][l];
}

/// One leg over a pose box (and the anchors' ranges), midpoint-radius: d = p + R b - A, u = R (b - c), w = u x d,
/// n = d / L, m = w / L, inv = 1 / L (d, u, L from endpoint intervals, where the dependencies are few).
struct LegBaseMR {
  using S = interval::MidRad;
  S d[3], u[3], w[3], n[3], m[3], inv;
  LegBaseMR(const Rotation& rot, const IVec& q, const std::array<Interval, 3>& a, const std::array<Interval, 3>& b,
            const std::array<Interval, 3>& c) {
    Interval dI[3], uI[3];
    for (int k = 0; k < 3; ++k) {
      dI[k] = q[k] + (rot.r[k][0] * b[0] + rot.r[k][1] * b[1] + rot.r[k][2] * b[2]) - a[k];
      uI[k] = rot.r[k][0] * (b[0] - c[0]) + rot.r[k][1] * (b[1] - c[1]) + rot.r[k][2] * (b[2] - c[2]);
    }
    const Interval lenI = sqrt(sqr(dI[0]) + sqr(dI[1]) + sqr(dI[2]));
    inv = S(Interval(1.0) / lenI);
    for (int k = 0; k < 3; ++k) {
      d[k] = S(dI[k]);
      u[k] = S(uI[k]);
    }
    RotationMR::cross(u, d, w);
    for (int k = 0; k < 3; ++k) {
      n[k] = d[k] * inv;
      m[k] = w[k] * inv;
    }
  }
};

/// LegBaseMR and the first derivatives with respect to the six pose coordinates (LegFirst).
struct LegMR : LegBaseMR {
  S bv[3], bc[3];  // b and b - c
  LegFirst<S> first;
  LegMR(const Rotation& rot, const RotationMR& rm, const IVec& q, const std::array<Interval, 3>& a,
        const std::array<Interval, 3>& b, const std::array<Interval, 3>& c)
      : LegBaseMR(rot, q, a, b, c),
        bv{S(b[0]), S(b[1]), S(b[2])},
        bc{S(b[0] - c[0]), S(b[1] - c[1]), S(b[2] - c[2])},
        first(rm, d, u, n, m, inv, bv, bc) {}
};

/// The remainder of a segment form in its two parts: returns r0, sets r2 (only SegmentAffineForm has them).
template <int N>
double remainderParts(const interval::SegmentAffineForm<N>& f, double& r2) {
  r2 = f.quadraticRadius();
  return f.constantRadius();
}
template <int N>
double remainderParts(const interval::AffineForm<N>& f, double& r2) {
  r2 = 0.0;
  return f.radius();
}

}  // namespace

GoughPlatform::GoughPlatform(GoughGeometry geometry) : geometry_(std::move(geometry)) {
  geometry_.validate();
  uncertain_ = geometry_.hasUncertainty();
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double ha = geometry_.base_anchor_halfwidth.empty() ? 0.0 : geometry_.base_anchor_halfwidth[i][k];
      const double hb = geometry_.platform_anchor_halfwidth.empty() ? 0.0 : geometry_.platform_anchor_halfwidth[i][k];
      a_[i][k] = around(geometry_.base_anchors[i][k], ha);
      b_[i][k] = around(geometry_.platform_anchors[i][k], hb);
    }
  }
  for (int k = 0; k < 3; ++k) c_[k] = around(geometry_.tool_point[k], geometry_.tool_point_halfwidth[k]);
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) {
      if (!a_[i][k].isPoint()) params_.push_back({Parameter::Base, i, k});
    }
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) {
      if (!b_[i][k].isPoint()) params_.push_back({Parameter::Platform, i, k});
    }
  for (int k = 0; k < 3; ++k)
    if (!c_[k].isPoint()) params_.push_back({Parameter::Tool, 0, k});
  aMid_ = a_;
  bMid_ = b_;
  cMid_ = c_;
  for (const Parameter& p : params_) slot(p, true) = Interval(slot(p, false).mid());
}

Interval& GoughPlatform::slot(const Parameter& p, bool centre) {
  return const_cast<Interval&>(static_cast<const GoughPlatform*>(this)->slot(p, centre));
}

const Interval& GoughPlatform::slot(const Parameter& p, bool centre) const {
  switch (p.kind) {
    case Parameter::Base:
      return centre ? aMid_[p.leg][p.coord] : a_[p.leg][p.coord];
    case Parameter::Platform:
      return centre ? bMid_[p.leg][p.coord] : b_[p.leg][p.coord];
    default:
      return centre ? cMid_[p.coord] : c_[p.coord];
  }
}

std::string GoughPlatform::geometryParameterName(int p) const {
  if (p < 0 || p >= geometryParameterCount()) return RobotModel::geometryParameterName(p);
  static const char* kAxis[3] = {"x", "y", "z"};
  const Parameter& q = params_[p];
  std::ostringstream os;
  if (q.kind == Parameter::Tool) {
    os << "tool_point." << kAxis[q.coord];
  } else {
    os << (q.kind == Parameter::Base ? "base_anchors[" : "platform_anchors[") << q.leg << "]." << kAxis[q.coord];
  }
  return os.str();
}

int GoughPlatform::toolPointCoordinate(int p) const {
  if (p < 0 || p >= geometryParameterCount() || params_[p].kind != Parameter::Tool) return -1;
  return params_[p].coord;
}

Interval GoughPlatform::geometryParameterRange(int p) const {
  if (p < 0 || p >= geometryParameterCount()) return RobotModel::geometryParameterRange(p);
  return slot(params_[p], false);
}

double GoughPlatform::geometryParameterCentre(int p) const {
  if (p < 0 || p >= geometryParameterCount()) return RobotModel::geometryParameterCentre(p);
  return slot(params_[p], true).lower();
}

Interval GoughPlatform::geometryParameterAdmissible(int p) const {
  if (p < 0 || p >= geometryParameterCount()) return RobotModel::geometryParameterAdmissible(p);
  const Parameter& q = params_[p];
  const double value = q.kind == Parameter::Base       ? geometry_.base_anchors[q.leg][q.coord]
                       : q.kind == Parameter::Platform ? geometry_.platform_anchors[q.leg][q.coord]
                                                       : geometry_.tool_point[q.coord];
  const double half = q.kind == Parameter::Base       ? geometry_.base_anchor_halfwidth[q.leg][q.coord]
                      : q.kind == Parameter::Platform ? geometry_.platform_anchor_halfwidth[q.leg][q.coord]
                                                      : geometry_.tool_point_halfwidth[q.coord];
  const Interval& range = slot(q, false);
  // (The value itself is always admissible, also where h is below its ulp. A restricted model describes its range
  // by a covering centre and half-width: the range bounds the set there.)
  const double lo = std::min(value, interval::rounding::subUp(value, half));
  const double hi = std::max(value, interval::rounding::addDown(value, half));
  return Interval(std::max(range.lower(), lo), std::min(range.upper(), hi));
}

IMat GoughPlatform::inverseJacobianAtGeometryCentre(const IVec& pose) const {
  Interval rows[6][6], len[6];
  goughKinematics(pose.data(), aMid_, bMid_, cMid_, rows, len);
  IMat m(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m(i, j) = rows[i][j];
  return m;
}

bool GoughPlatform::geometryDerivatives(const IVec& q, GeometryDerivatives& out) const {
  out.count = 0;
  if (params_.empty()) return true;
  // One entry per (parameter, row it moves), in parameter order: an anchor moves its leg's row, the tool point every
  // row. The anchors' entries come from affine forms in the pose (tighter, and their ranges are tighter than the
  // midpoint-radius evaluation's: bench/RESULTS.md), the tool point's from the midpoint-radius formulas below.
  bool tool = false;
  for (int p = 0; p < geometryParameterCount(); ++p) {
    const Parameter& par = params_[p];
    const int rows = par.kind == Parameter::Tool ? 6 : 1;
    for (int k = 0; k < rows; ++k) {
      GeometryRowDerivative& e = out.entries[out.count++];
      e.parameter = p;
      e.row = par.kind == Parameter::Tool ? k : par.leg;
      e.affine = false;
      e.parameterSlopes = false;
    }
    tool = tool || par.kind == Parameter::Tool;
  }
  affineGeometryDerivatives(q, out);
  if (!tool) return true;
  using S = interval::MidRad;
  const Rotation rot(q);
  const auto& r = rot.r;
  // The legs (LegBaseMR: d, u, |d| from endpoint intervals, the rest in midpoint-radius arithmetic, rigorous and
  // cheaper: bench/RESULTS.md).
  std::array<LegBaseMR, 6> leg{LegBaseMR(rot, q, a_[0], b_[0], c_), LegBaseMR(rot, q, a_[1], b_[1], c_),
                               LegBaseMR(rot, q, a_[2], b_[2], c_), LegBaseMR(rot, q, a_[3], b_[3], c_),
                               LegBaseMR(rot, q, a_[4], b_[4], c_), LegBaseMR(rot, q, a_[5], b_[5], c_)};
  // The tool point c moves d by 0 and u = R (b - c) by -R e_c: dL = 0, dn = 0, dm = (d x R e_c) / L.
  for (int e = 0; e < out.count; ++e) {
    GeometryRowDerivative& entry = out.entries[e];
    const Parameter& par = params_[entry.parameter];
    if (par.kind != Parameter::Tool) continue;
    const int c = par.coord, i = entry.row;
    const S column[3] = {S(r[0][c]), S(r[1][c]), S(r[2][c])};  // R e_c
    S dw[3];
    RotationMR::cross(leg[i].d, column, dw);
    for (int k = 0; k < 3; ++k) {
      entry.d[k] = S(0.0);
      entry.d[3 + k] = dw[k] * leg[i].inv;
    }
  }
  return true;
}

namespace {
template <int N>
void cross(const interval::AffineForm<N> x[3], const interval::AffineForm<N> y[3], interval::AffineForm<N> out[3]) {
  out[0] = x[1] * y[2] - x[2] * y[1];
  out[1] = x[2] * y[0] - x[0] * y[2];
  out[2] = x[0] * y[1] - x[1] * y[0];
}

/// The pose pieces shared by the legs in GoughPlatform::affineGeometryDerivativesWith(): the pose and R in the N
/// symbols, and R c (the tool point c; not computed where c = 0).
template <int N>
struct AffinePoseFrame {
  using Aff = interval::AffineForm<N>;
  Aff pose[6];
  RotationOps<Aff> rot;
  bool toolAtOrigin = false;
  Aff tool[3];
};

/// One leg's pieces in the N symbols: d = p + R b - A, u = R (b - c), n = d / L, m = (u x d) / L, inv = 1 / L.
template <int N>
struct AffineLeg {
  using Aff = interval::AffineForm<N>;
  bool built = false;
  Aff d[3], u[3], n[3], m[3], inv;
  Aff arm[3];       ///< p + R c - A_i (the platform anchors' moment arm)
  double scale[6];  ///< the anchor symbols' scales (0: none)
};

/// The anchor coordinate x (an interval of centre x0 and parameter p, or exact) as a form: with the anchor symbols
/// (N = 2 kMaxDof), x0 + scale gamma (scale >= |range - x0|, gamma the symbol `symbol`); without, the interval
/// itself (its width to the radius).
template <int N>
interval::AffineForm<N> anchorForm(const Interval& x, const Interval& x0, int p, int symbol, double& scale) {
  using Aff = interval::AffineForm<N>;
  constexpr bool kAnchorSymbols = N == 2 * kMaxDof;
  scale = 0.0;
  if (!kAnchorSymbols || p < 0 || x.isPoint()) return Aff(x);
  double coefficients[N] = {};
  scale = (x - x0).mag();
  coefficients[symbol] = scale;
  return Aff::fromParts(x0.lower(), coefficients, 0.0);
}

/// Leg i's pieces from its anchors a (base), b (platform), their centres and parameters (-1: no symbol).
template <int N>
void buildAffineLeg(const std::array<Interval, 3>& a, const std::array<Interval, 3>& aMid,
                    const std::array<Interval, 3>& b, const std::array<Interval, 3>& bMid, const int baseParam[3],
                    const int platformParam[3], const AffinePoseFrame<N>& frame, AffineLeg<N>& leg) {
  using Aff = interval::AffineForm<N>;
  const auto& r = frame.rot.r;
  leg.built = true;
  Aff af[3], bf[3];
  for (int k = 0; k < 3; ++k) {
    af[k] = anchorForm<N>(a[k], aMid[k], baseParam[k], kMaxDof + k, leg.scale[k]);
    bf[k] = anchorForm<N>(b[k], bMid[k], platformParam[k], kMaxDof + 3 + k, leg.scale[3 + k]);
  }
  for (int k = 0; k < 3; ++k) {
    Aff rb(0.0);
    for (int l = 0; l < 3; ++l) rb += r[k][l] * bf[l];
    leg.d[k] = frame.pose[k] + rb - af[k];
    leg.u[k] = frame.toolAtOrigin ? rb : rb - frame.tool[k];  // R (b - c) = R b - R c
    leg.arm[k] = frame.pose[k] + frame.tool[k] - af[k];
  }
  leg.inv = reciprocal(sqrt(leg.d[0] * leg.d[0] + leg.d[1] * leg.d[1] + leg.d[2] * leg.d[2]));
  Aff w[3];
  cross(leg.u, leg.d, w);
  for (int k = 0; k < 3; ++k) {
    leg.n[k] = leg.d[k] * leg.inv;
    leg.m[k] = w[k] * leg.inv;
  }
}

/// The derivative of the leg's row (n, m) with respect to base anchor coordinate c: dd = -e_c, du = 0, so
/// dL = -n_c, dn = (n n_c - e_c) / L, dm = (m n_c - u x e_c) / L.
template <int N>
void baseAnchorDerivative(const AffineLeg<N>& leg, int c, interval::AffineForm<N> v[6]) {
  using Aff = interval::AffineForm<N>;
  const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
  // u x e_c: component c is 0, component c1 is u_c2, component c2 is -u_c1.
  Aff ue[3];
  ue[c] = Aff(0.0);
  ue[c1] = leg.u[c2];
  ue[c2] = -leg.u[c1];
  for (int k = 0; k < 3; ++k) {
    v[k] = (k == c ? leg.n[k] * leg.n[c] - Aff(1.0) : leg.n[k] * leg.n[c]) * leg.inv;
    v[3 + k] = (leg.m[k] * leg.n[c] - ue[k]) * leg.inv;
  }
}

/// The same for platform anchor coordinate c: dd = du = R e_c, so dL = n . R e_c, dn = (R e_c - n dL) / L,
/// dm = (R e_c x (d - u) - m dL) / L, d - u = p + R c - A_i (the leg's arm).
template <int N>
void platformAnchorDerivative(const AffineLeg<N>& leg, const AffinePoseFrame<N>& frame, int c,
                              interval::AffineForm<N> v[6]) {
  using Aff = interval::AffineForm<N>;
  const auto& r = frame.rot.r;
  const Aff column[3] = {r[0][c], r[1][c], r[2][c]};  // R e_c
  Aff dw[3];
  const Aff dl = leg.n[0] * column[0] + leg.n[1] * column[1] + leg.n[2] * column[2];
  cross(column, leg.arm, dw);
  for (int k = 0; k < 3; ++k) {
    v[k] = (column[k] - leg.n[k] * dl) * leg.inv;
    v[3 + k] = (dw[k] - leg.m[k] * dl) * leg.inv;
  }
}

/// The entry from the derivative's forms v: the affine form, and its range as the midpoint-radius enclosure (an
/// infinite radius where the form is not finite, e.g. a leg length range reaching 0: the callers then fall back to
/// other enclosures); with the anchor symbols, the terms in the leg's anchor parameters apart.
template <int N>
void storeAffineEntry(const interval::AffineForm<N> v[6], const AffineLeg<N>& leg, const int baseParam[3],
                      const int platformParam[3], GeometryRowDerivative& entry) {
  constexpr bool kAnchorSymbols = N == 2 * kMaxDof;
  bool finite = true;
  for (int l = 0; l < 6; ++l) {
    finite = finite && v[l].finite();
    entry.centre[l] = v[l].centre();
    entry.radius[l] = v[l].radius();
    for (int m = 0; m < 6; ++m) entry.slope[l][m] = v[l].coefficient(m);
    entry.d[l] = interval::MidRad(v[l].centre(), v[l].deviation());
    if (kAnchorSymbols)
      for (int s = 0; s < 6; ++s) entry.parameterSlope[l][s] = v[l].coefficient((kMaxDof + s) % N);
  }
  entry.parameterSlopes = kAnchorSymbols;
  for (int s = 0; s < 6 && kAnchorSymbols; ++s) {
    entry.slopeParameter[s] = leg.scale[s] > 0.0 ? (s < 3 ? baseParam[s] : platformParam[s - 3]) : -1;
    entry.parameterScale[s] = leg.scale[s];
  }
  entry.affine = finite;
  if (!finite)
    for (int l = 0; l < 6; ++l) entry.d[l] = interval::MidRad(0.0, std::numeric_limits<double>::infinity());
}
}  // namespace

void GoughPlatform::affineGeometryDerivatives(const IVec& q, GeometryDerivatives& out) const {
  if (out.withParameterSlopes) {
    affineGeometryDerivativesWith<2 * kMaxDof>(q, out);
  } else {
    affineGeometryDerivativesWith<kMaxDof>(q, out);
  }
}

template <int N>
void GoughPlatform::affineGeometryDerivativesWith(const IVec& q, GeometryDerivatives& out) const {
  using Aff = interval::AffineForm<N>;
  // With N = 12, symbols 6 + k and 9 + k are the leg's base and platform anchor coordinates k (where uncertain):
  // each entry only combines quantities of its own leg, so the legs share the symbol numbers.
  constexpr bool kAnchorSymbols = N == 2 * kMaxDof;
  int baseParam[6][3], platformParam[6][3];  // (-1 without the anchor symbols)
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) baseParam[i][k] = platformParam[i][k] = -1;
  for (int p = 0; p < static_cast<int>(params_.size()) && kAnchorSymbols; ++p) {
    if (params_[p].kind == Parameter::Base) baseParam[params_[p].leg][params_[p].coord] = p;
    if (params_[p].kind == Parameter::Platform) platformParam[params_[p].leg][params_[p].coord] = p;
  }
  // Row i of J^-1 is (n, m) = (d / L, u x d / L), d = p + R b_i - A_i, u = R (b_i - c), L = |d|. Each anchor
  // coordinate moves d and u along a fixed direction (dL = (d . dd) / L, dn = (dd - n dL) / L,
  // dm = (du x d + u x dd - m dL) / L): baseAnchorDerivative(), platformAnchorDerivative().
  // Evaluated in first-order affine arithmetic with one noise symbol per pose coordinate; the anchors' and the tool
  // point's ranges are constants, so their effect goes to the radii.
  AffinePoseFrame<N> frame;
  affineRotation<Aff>(q, frame.pose, frame.rot, false);
  const auto& r = frame.rot.r;
  frame.toolAtOrigin = c_[0] == 0.0 && c_[1] == 0.0 && c_[2] == 0.0;
  for (int k = 0; k < 3 && !frame.toolAtOrigin; ++k)
    frame.tool[k] = r[k][0] * Aff(c_[0]) + r[k][1] * Aff(c_[1]) + r[k][2] * Aff(c_[2]);
  AffineLeg<N> legs[6];
  for (int e = 0; e < out.count; ++e) {
    GeometryRowDerivative& entry = out.entries[e];
    const Parameter& par = params_[entry.parameter];
    if (par.kind == Parameter::Tool) continue;
    const int i = par.leg, c = par.coord;
    AffineLeg<N>& leg = legs[i];
    if (!leg.built) buildAffineLeg<N>(a_[i], aMid_[i], b_[i], bMid_[i], baseParam[i], platformParam[i], frame, leg);
    Aff v[6];
    if (par.kind == Parameter::Base) {
      baseAnchorDerivative<N>(leg, c, v);
    } else {
      platformAnchorDerivative<N>(leg, frame, c, v);
    }
    storeAffineEntry<N>(v, leg, baseParam[i], platformParam[i], entry);
  }
}

void GoughPlatform::describe(const Parameter& q, double value, double half) {
  if (q.kind == Parameter::Base) {
    geometry_.base_anchors[q.leg][q.coord] = value;
    geometry_.base_anchor_halfwidth[q.leg][q.coord] = half;
  } else if (q.kind == Parameter::Platform) {
    geometry_.platform_anchors[q.leg][q.coord] = value;
    geometry_.platform_anchor_halfwidth[q.leg][q.coord] = half;
  } else {
    geometry_.tool_point[q.coord] = value;
    geometry_.tool_point_halfwidth[q.coord] = half;
  }
}

std::unique_ptr<RobotModel> GoughPlatform::fixGeometryParameters(const GVec& values) const {
  if (params_.empty()) return RobotModel::fixGeometryParameters(values);
  if (values.size() != static_cast<int>(params_.size())) {
    throw InvalidArgument("geometry values: expected " + std::to_string(params_.size()) + " values, got " +
                          std::to_string(values.size()));
  }
  auto out = std::make_unique<GoughPlatform>(*this);
  out->params_.clear();
  bool uncertain = false;
  for (std::size_t p = 0; p < params_.size(); ++p) {
    const Parameter& q = params_[p];
    const double v = values[static_cast<int>(p)];
    if (std::isnan(v)) {
      out->params_.push_back(q);
      uncertain = uncertain || !slot(q, false).isPoint();
      continue;
    }
    if (!slot(q, false).contains(v)) {
      std::ostringstream os;
      os << "geometry values[" << p << "] (" << geometryParameterName(static_cast<int>(p)) << "): expected a point "
         << "of " << slot(q, false) << ", got " << v;
      throw InvalidArgument(os.str());
    }
    out->slot(q, false) = Interval(v);
    out->slot(q, true) = Interval(v);
    out->describe(q, v, 0.0);
  }
  out->uncertain_ = uncertain;
  return out;
}

std::unique_ptr<RobotModel> GoughPlatform::restrictGeometry(const std::vector<Interval>& ranges) const {
  if (params_.empty()) return RobotModel::restrictGeometry(ranges);
  if (ranges.size() != params_.size()) {
    throw InvalidArgument("geometry ranges: expected " + std::to_string(params_.size()) + " values, got " +
                          std::to_string(ranges.size()));
  }
  auto out = std::make_unique<GoughPlatform>(*this);
  bool uncertain = false;
  for (std::size_t p = 0; p < params_.size(); ++p) {
    const Interval& current = slot(params_[p], false);
    const Interval& r = ranges[p];
    if (r.isEmpty() || r.lower() < current.lower() || r.upper() > current.upper()) {
      std::ostringstream os;
      os << "geometry ranges[" << p << "] (" << geometryParameterName(static_cast<int>(p)) << "): expected a "
         << "non-empty sub-interval of " << current << ", got " << r;
      throw InvalidArgument(os.str());
    }
    out->slot(params_[p], false) = r;
    out->slot(params_[p], true) = Interval(r.mid());
    uncertain = uncertain || !r.isPoint();
    // Keep the plain description in step (point evaluations in double use it): centre and a covering half-width.
    const double mid = r.mid();
    const double half = interval::radiusAbout(r, mid);
    out->describe(params_[p], mid, half);
  }
  out->uncertain_ = uncertain;
  return out;
}

std::string GoughPlatform::componentName(int k) const {
  // The error components (a displacement and a small rotation vector, both in the base frame), named as in the ROS
  // messages and the CLI's reports: not the pose variables x, ..., yaw.
  static const char* kNames[6] = {"dx [m]", "dy [m]", "dz [m]", "drx [rad]", "dry [rad]", "drz [rad]"};
  return (k >= 0 && k < 6) ? kNames[k] : "?";
}

DMat GoughPlatform::inverseJacobian(const DVec& pose) const {
  const auto a = toArray<double>(geometry_.base_anchors), b = toArray<double>(geometry_.platform_anchors);
  const std::array<double, 3> c = {geometry_.tool_point[0], geometry_.tool_point[1], geometry_.tool_point[2]};
  double rows[6][6], len[6];
  goughKinematics(pose.data(), a, b, c, rows, len);
  DMat m(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m(i, j) = rows[i][j];
  return m;
}

DVec GoughPlatform::legLengths(const DVec& pose) const {
  const auto a = toArray<double>(geometry_.base_anchors), b = toArray<double>(geometry_.platform_anchors);
  const std::array<double, 3> c = {geometry_.tool_point[0], geometry_.tool_point[1], geometry_.tool_point[2]};
  double rows[6][6], len[6];
  goughKinematics(pose.data(), a, b, c, rows, len);
  DVec l(6);
  for (int i = 0; i < 6; ++i) l[i] = len[i];
  return l;
}

IMat GoughPlatform::inverseJacobian(const IVec& pose) const {
  Interval rows[6][6], len[6];
  goughKinematics(pose.data(), a_, b_, c_, rows, len);
  IMat m(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m(i, j) = rows[i][j];
  return m;
}

IVec GoughPlatform::legLengths(const IVec& pose) const {
  Interval rows[6][6], len[6];
  goughKinematics(pose.data(), a_, b_, c_, rows, len);
  IVec l(6);
  for (int i = 0; i < 6; ++i) l[i] = len[i];
  return l;
}

void GoughPlatform::inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const {
  chainRule(pose, a_, b_, c_, out);
}

void GoughPlatform::inverseJacobianAtGeometryCentre(const DualPose& pose, MatrixWithGradient& out) const {
  chainRule(pose, aMid_, bMid_, cMid_, out);
}

void GoughPlatform::chainRule(const DualPose& pose, const Anchors& a, const Anchors& b, const Tool& c,
                              MatrixWithGradient& out) const {
  // Analytic derivatives with respect to the six pose coordinates (much cheaper than propagating six-component
  // gradients through every operation), then the chain rule through the pose map's own gradient.
  IVec q(6);
  for (int i = 0; i < 6; ++i) q[i] = pose[i].value();
  MatrixWithGradient byPose;
  derivatives(q, a, b, c, byPose);
  out.value = byPose.value;
  bool identity = true;
  for (int i = 0; i < 6 && identity; ++i)
    for (int j = 0; j < kMaxDof; ++j)
      if (pose[i].d(j) != Interval(i == j ? 1.0 : 0.0)) {
        identity = false;
        break;
      }
  if (identity) {
    out.d = byPose.d;
    return;
  }
  for (int j = 0; j < kMaxDof; ++j) {
    out.d[j] = IMat::Constant(6, 6, Interval(0.0));
    for (int i = 0; i < 6; ++i) {
      const Interval g = pose[i].d(j);
      if (g == Interval(0.0)) continue;
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) out.d[j](r, c) += byPose.d[i](r, c) * g;
    }
  }
}

void GoughPlatform::poseDerivatives(const IVec& q, MatrixWithGradient& out) const { derivatives(q, a_, b_, c_, out); }

void GoughPlatform::derivatives(const IVec& q, const Anchors& a, const Anchors& b, const Tool& c,
                                MatrixWithGradient& out) const {
  const Rotation rot(q);
  const auto& r = rot.r;
  // dR/droll = R [e_x]x: column 1 <- column 2, column 2 <- -column 1. dR/dyaw = [e_z]x R: row 0 <- -row 1,
  // row 1 <- row 0, row 2 <- 0. dR/dpitch: Rotation::pitch.
  const auto& dp = rot.pitch;
  out.value.resize(6, 6);
  for (auto& d : out.d) d = IMat::Constant(6, 6, Interval(0.0));
  for (int i = 0; i < 6; ++i) {
    Interval rb[3], u[3], d[3];
    const Interval bc[3] = {b[i][0] - c[0], b[i][1] - c[1], b[i][2] - c[2]};
    for (int k = 0; k < 3; ++k) {
      rb[k] = r[k][0] * b[i][0] + r[k][1] * b[i][1] + r[k][2] * b[i][2];
      u[k] = r[k][0] * bc[0] + r[k][1] * bc[1] + r[k][2] * bc[2];
      d[k] = q[k] + rb[k] - a[i][k];
    }
    const Interval len = sqrt(sqr(d[0]) + sqr(d[1]) + sqr(d[2]));
    const Interval n[3] = {d[0] / len, d[1] / len, d[2] / len};
    const Interval w[3] = {u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2], u[0] * d[1] - u[1] * d[0]};
    const Interval m[3] = {w[0] / len, w[1] / len, w[2] / len};
    for (int k = 0; k < 3; ++k) {
      out.value(i, k) = n[k];
      out.value(i, 3 + k) = m[k];
    }
    // Derivatives of d and u for each pose variable, then of n = d / L and m = (u x d) / L (rowDerivative).
    auto emit = [&](int var, const Interval dd[3], const Interval du[3]) {
      Interval v[6];
      rowDerivative(d, u, n, m, len, dd, du, v);
      for (int k = 0; k < 6; ++k) out.d[var](i, k) = v[k];
    };
    const Interval zero(0.0), one(1.0);
    const Interval du0[3] = {zero, zero, zero};
    for (int k = 0; k < 3; ++k) {
      const Interval dd[3] = {k == 0 ? one : zero, k == 1 ? one : zero, k == 2 ? one : zero};
      emit(k, dd, du0);
    }
    // roll: d(R v)/droll = R (e_x x v) = R (0, -v_z, v_y).
    {
      Interval dd[3], du[3];
      for (int k = 0; k < 3; ++k) {
        dd[k] = r[k][2] * b[i][1] - r[k][1] * b[i][2];
        du[k] = r[k][2] * bc[1] - r[k][1] * bc[2];
      }
      emit(3, dd, du);
    }
    {
      Interval dd[3], du[3];
      for (int k = 0; k < 3; ++k) {
        dd[k] = dp[k][0] * b[i][0] + dp[k][1] * b[i][1] + dp[k][2] * b[i][2];
        du[k] = dp[k][0] * bc[0] + dp[k][1] * bc[1] + dp[k][2] * bc[2];
      }
      emit(4, dd, du);
    }
    {
      // yaw: d(R v)/dyaw = e_z x (R v) = (-(Rv)_y, (Rv)_x, 0).
      const Interval dd[3] = {-rb[1], rb[0], zero};
      const Interval du[3] = {-u[1], u[0], zero};
      emit(5, dd, du);
    }
  }
}

namespace {
/// The second derivatives of J^-1 (hessian()'s formulas) at the anchors' and tool point's centres a, b, c, in the
/// affine form type S over the pose (pose and rm from affineRotation()): h[pair][row * 6 + column].
/// @return false if one of them is not finite.
template <typename S>
bool hessianForms(const S pose[6], const RotationOps<S>& rm, const std::array<std::array<Interval, 3>, 6>& a,
                  const std::array<std::array<Interval, 3>, 6>& b, const std::array<Interval, 3>& c,
                  std::array<std::array<S, 36>, MatrixHessian::kPairs>& h) {
  const auto& r = rm.r;
  bool finite = true;
  for (int i = 0; i < 6; ++i) {
    S bv[3], bc[3], d[3], u[3], w[3], n[3], m[3];
    for (int k = 0; k < 3; ++k) {
      bv[k] = S(b[i][k]);
      bc[k] = S(b[i][k] - c[k]);
    }
    for (int k = 0; k < 3; ++k) {
      d[k] = pose[k] + (r[k][0] * bv[0] + r[k][1] * bv[1] + r[k][2] * bv[2]) - S(a[i][k]);
      u[k] = r[k][0] * bc[0] + r[k][1] * bc[1] + r[k][2] * bc[2];
    }
    const S inv = reciprocal(sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    RotationOps<S>::cross(u, d, w);
    for (int k = 0; k < 3; ++k) {
      n[k] = d[k] * inv;
      m[k] = w[k] * inv;
    }
    const LegFirst<S> first(rm, d, u, n, m, inv, bv, bc);
    for (int va = 0; va < 6; ++va) {
      for (int vb = va; vb < 6; ++vb) {
        S hn[3], hm[3];
        legSecond(rm, d, u, n, m, inv, bv, bc, first, va, vb, hn, hm);
        std::array<S, 36>& hp = h[MatrixHessian::index(va, vb)];
        for (int k = 0; k < 3; ++k) {
          hp[i * 6 + k] = hn[k];
          hp[i * 6 + 3 + k] = hm[k];
          finite = finite && hn[k].finite() && hm[k].finite();
        }
      }
    }
  }
  return finite;
}
}  // namespace

bool GoughPlatform::preconditionedHessianMagnitude(const IVec& q, const DMat& c,
                                                   std::array<DMat, MatrixHessian::kPairs>& out,
                                                   std::array<DMat, MatrixHessian::kPairs>* linear,
                                                   std::array<DMat, MatrixHessian::kPairs>* quadratic,
                                                   std::array<DMat, MatrixHessian::kPairs>* rest,
                                                   std::array<DMat, MatrixHessian::kPairs>* centre) const {
  // The second derivatives of hessian() (same formulas) in first-order affine arithmetic, one symbol per pose
  // coordinate: H_il(t) in Hc + sum_m A_m tau_m +- R entry by entry, so C H_il(t) in C Hc + sum_m (C A_m) tau_m +-
  // |C| R, and |C H_il(t)| <= |C Hc| + sum_m |C A_m| + |C| R (+ the products' rounding, below 1e-13 of |C| times the
  // magnitudes); with `linear` the middle term apart; with `quadratic` too, the forms are SegmentAffineForm and R
  // splits into R0 + s^2 R2 on the segments from the box centre, |C| R2 apart
  // (RobotModel::preconditionedHessianMagnitude).
  if (q.size() != 6 || c.rows() != 6 || c.cols() != 6) return false;
  if (quadratic != nullptr && linear == nullptr) return false;
  if (quadratic != nullptr)
    return hessianMagnitude<interval::SegmentAffineForm<kMaxDof>>(q, c, out, linear, quadratic, rest, centre);
  return hessianMagnitude<interval::AffineForm<kMaxDof>>(q, c, out, linear, nullptr, rest, centre);
}

template <typename S>
bool GoughPlatform::hessianMagnitude(const IVec& q, const DMat& c, std::array<DMat, MatrixHessian::kPairs>& out,
                                     std::array<DMat, MatrixHessian::kPairs>* linear,
                                     std::array<DMat, MatrixHessian::kPairs>* quadratic,
                                     std::array<DMat, MatrixHessian::kPairs>* rest,
                                     std::array<DMat, MatrixHessian::kPairs>* centreOut) const {
  S pose[6];
  RotationOps<S> rm;
  affineRotation<S>(q, pose, rm, true);
  // The second derivatives' forms, pair by pair (each pair's 6 x 6 matrix row-major; on the stack, every entry
  // written by hessianForms() before it is read).
  std::array<std::array<S, 36>, MatrixHessian::kPairs> h;
  const bool finite = hessianForms<S>(pose, rm, aMid_, bMid_, cMid_, h);
  if (!finite) return false;
  // (Fixed-size 6 x 6 matrices: these products unroll and vectorise, the dynamic ones do not.)
  using M6 = Eigen::Matrix<double, 6, 6>;
  const M6 c6 = c, absC = c6.cwiseAbs();
  for (int p = 0; p < MatrixHessian::kPairs; ++p) {
    M6 centre, radius, quad = M6::Zero(), absSum, a;
    for (int row = 0; row < 6; ++row)
      for (int col = 0; col < 6; ++col) {
        const S& f = h[p][row * 6 + col];
        centre(row, col) = f.centre();
        radius(row, col) = quadratic != nullptr ? remainderParts(f, quad(row, col)) : f.radius();
      }
    absSum = centre.cwiseAbs();
    M6 slopes = M6::Zero();
    for (int s2 = 0; s2 < 6; ++s2) {
      for (int row = 0; row < 6; ++row)
        for (int col = 0; col < 6; ++col) a(row, col) = h[p][row * 6 + col].coefficient(s2);
      slopes.noalias() += (c6 * a).cwiseAbs();
      absSum += a.cwiseAbs();
    }
    // scale = |C| (|Hc| + sum_m |A_m|): the sum of the products' magnitudes (one product, the same sum).
    const M6 scale = absC * absSum;
    M6 mag = (c6 * centre).cwiseAbs() + absC * radius;
    // (The rounding margin 1e-13 scale covers every product with C, so it goes to each part.)
    if (linear != nullptr) {
      (*linear)[p] = interval::rounding::upEach(M6(slopes + 1e-13 * scale));
      if (!(*linear)[p].allFinite()) return false;
    } else {
      mag += slopes;
    }
    if (quadratic != nullptr) {
      (*quadratic)[p] = interval::rounding::upEach(M6(absC * quad));
      if (!(*quadratic)[p].allFinite()) return false;
    }
    if (rest != nullptr) (*rest)[p] = interval::rounding::upEach(M6(absC * radius + 1e-13 * scale));
    if (centreOut != nullptr) (*centreOut)[p] = c6 * centre;
    out[p] = interval::rounding::upEach(M6(mag + 1e-13 * scale));
    if (!out[p].allFinite()) return false;
  }
  return true;
}

bool GoughPlatform::inverseJacobianHessianAtGeometryCentre(const IVec& pose, MatrixHessian& out, bool second) const {
  return hessian(pose, aMid_, bMid_, cMid_, out, second);
}

bool GoughPlatform::hessian(const IVec& q, const Anchors& a, const Anchors& b, const Tool& c, MatrixHessian& out,
                            bool second) const {
  // Row i of J^-1 is (n, m) = (d / L, w / L), d = p + R b_i - A_i, u = R (b_i - c), w = u x d, L = |d|. With the
  // first derivatives (LegMR) L_a = n . d_a, n_a = (d_a - n L_a) / L, w_a = u_a x d + u x d_a, m_a = (w_a - m L_a) / L,
  // differentiating once more:
  //   L_ab = n_b . d_a + n . d_ab,
  //   n_ab = (d_ab - n_b L_a - n_a L_b - n L_ab) / L,
  //   w_ab = u_ab x d + u_a x d_b + u_b x d_a + u x d_ab,
  //   m_ab = (w_ab - m_b L_a - m_a L_b - m L_ab) / L,
  // where d_a = e_a, u_a = 0 for a translation, d_a = R_a b_i, u_a = R_a (b_i - c) for a rotation, and d_ab, u_ab
  // vanish unless both are rotations: R_ab from R = Rz(yaw) Ry(pitch) Rx(roll) (RotationMR),
  //   R_roll v = R (e_x x v),  R_pitch = Rz Ry' Rx,  R_yaw v = e_z x (R v),
  //   R_roll,roll v = R (e_x x (e_x x v)),  R_roll,pitch v = R_pitch (e_x x v),  R_roll,yaw v = e_z x (R (e_x x v)),
  //   R_pitch,pitch = -R + (Rz e_y)(Rx^T e_y)^T,  R_pitch,yaw v = e_z x (R_pitch v),  R_yaw,yaw v = e_z x (e_z x R v).
  // The rotation and each leg's d, u, L are enclosed in interval arithmetic over the box, then everything else in
  // midpoint-radius arithmetic (interval::MidRad: rigorous, several times cheaper than endpoint intervals here; the
  // operands are narrow) and converted back: enclosures of every first and second derivative over the box.
  using S = interval::MidRad;
  const Rotation rot(q);
  const RotationMR rm(rot);
  bool finite = true;
  for (auto& f : out.first) f.resize(6, 6);
  for (auto& h : out.d) h.resize(second ? 6 : 0, 6);
  for (int i = 0; i < 6; ++i) {
    const LegMR leg(rot, rm, q, a[i], b[i], c);
    // The first derivatives (n_a, m_a) of row i.
    for (int va = 0; va < 6; ++va)
      for (int k = 0; k < 3; ++k) {
        finite = finite && leg.first.na[va][k].finite() && leg.first.ma[va][k].finite();
        out.first[va](i, k) = leg.first.na[va][k].toInterval();
        out.first[va](i, 3 + k) = leg.first.ma[va][k].toInterval();
      }
    if (!second) continue;
    for (int va = 0; va < 6; ++va) {
      for (int vb = va; vb < 6; ++vb) {
        S hn[3], hm[3];
        legSecond(static_cast<const RotationOps<S>&>(rm), leg.d, leg.u, leg.n, leg.m, leg.inv, leg.bv, leg.bc,
                  leg.first, va, vb, hn, hm);
        IMat& h = out.d[MatrixHessian::index(va, vb)];
        for (int k = 0; k < 3; ++k) {
          finite = finite && hn[k].finite() && hm[k].finite();
          h(i, k) = hn[k].toInterval();
          h(i, 3 + k) = hm[k].toInterval();
        }
      }
    }
  }
  return finite;
}

void GoughPlatform::inverseJacobianByDualNumbers(const DualPose& pose, MatrixWithGradient& out) const {
  DualI rows[6][6], len[6];
  goughKinematics(pose.data(), a_, b_, c_, rows, len);
  out.value.resize(6, 6);
  for (auto& d : out.d) d.resize(6, 6);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      out.value(i, j) = rows[i][j].value();
      for (int m = 0; m < kMaxDof; ++m) out.d[m](i, j) = rows[i][j].d(m);
    }
  }
}

}  // namespace model
}  // namespace pkm_accuracy
