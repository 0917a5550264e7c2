#include "pkm_accuracy/core/model/GoughPlatform.hpp"

#include <cmath>

#include "pkm_accuracy/core/interval/Functions.hpp"

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
}

std::string GoughPlatform::componentName(int k) const {
  static const char* kNames[6] = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
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
  // Analytic derivatives with respect to the six pose coordinates (much cheaper than propagating six-component
  // gradients through every operation), then the chain rule through the pose map's own gradient.
  IVec q(6);
  for (int i = 0; i < 6; ++i) q[i] = pose[i].value();
  MatrixWithGradient byPose;
  poseDerivatives(q, byPose);
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

void GoughPlatform::poseDerivatives(const IVec& q, MatrixWithGradient& out) const {
  const Interval sr = interval::sin(q[3]), cr = interval::cos(q[3]);
  const Interval sp = interval::sin(q[4]), cp = interval::cos(q[4]);
  const Interval sy = interval::sin(q[5]), cy = interval::cos(q[5]);
  const Interval cysp = cy * sp, sysp = sy * sp;
  const Interval r[3][3] = {{cy * cp, cysp * sr - sy * cr, cysp * cr + sy * sr},
                            {sy * cp, sysp * sr + cy * cr, sysp * cr - cy * sr},
                            {-sp, cp * sr, cp * cr}};
  // dR/droll = R [e_x]x: column 1 <- column 2, column 2 <- -column 1. dR/dyaw = [e_z]x R: row 0 <- -row 1,
  // row 1 <- row 0, row 2 <- 0. dR/dpitch = Rz dRy/dpitch Rx, entry by entry.
  const Interval cycp = cy * cp, sycp = sy * cp;
  const Interval dp[3][3] = {{-cysp, cycp * sr, cycp * cr}, {-sysp, sycp * sr, sycp * cr}, {-cp, -sp * sr, -sp * cr}};
  out.value.resize(6, 6);
  for (auto& d : out.d) d = IMat::Constant(6, 6, Interval(0.0));
  for (int i = 0; i < 6; ++i) {
    Interval rb[3], u[3], d[3];
    const Interval bc[3] = {b_[i][0] - c_[0], b_[i][1] - c_[1], b_[i][2] - c_[2]};
    for (int k = 0; k < 3; ++k) {
      rb[k] = r[k][0] * b_[i][0] + r[k][1] * b_[i][1] + r[k][2] * b_[i][2];
      u[k] = r[k][0] * bc[0] + r[k][1] * bc[1] + r[k][2] * bc[2];
      d[k] = q[k] + rb[k] - a_[i][k];
    }
    const Interval len = sqrt(sqr(d[0]) + sqr(d[1]) + sqr(d[2]));
    const Interval n[3] = {d[0] / len, d[1] / len, d[2] / len};
    const Interval w[3] = {u[1] * d[2] - u[2] * d[1], u[2] * d[0] - u[0] * d[2], u[0] * d[1] - u[1] * d[0]};
    const Interval m[3] = {w[0] / len, w[1] / len, w[2] / len};
    for (int k = 0; k < 3; ++k) {
      out.value(i, k) = n[k];
      out.value(i, 3 + k) = m[k];
    }
    // Derivatives of d and u for each pose variable, then of n = d / L and m = (u x d) / L:
    //   dL = (d . dd) / L,  dn = (dd - n dL) / L,  dm = (du x d + u x dd - m dL) / L.
    auto emit = [&](int var, const Interval dd[3], const Interval du[3]) {
      const Interval dl = (d[0] * dd[0] + d[1] * dd[1] + d[2] * dd[2]) / len;
      const Interval dw[3] = {du[1] * d[2] - du[2] * d[1] + (u[1] * dd[2] - u[2] * dd[1]),
                              du[2] * d[0] - du[0] * d[2] + (u[2] * dd[0] - u[0] * dd[2]),
                              du[0] * d[1] - du[1] * d[0] + (u[0] * dd[1] - u[1] * dd[0])};
      for (int k = 0; k < 3; ++k) {
        out.d[var](i, k) = (dd[k] - n[k] * dl) / len;
        out.d[var](i, 3 + k) = (dw[k] - m[k] * dl) / len;
      }
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
        dd[k] = r[k][2] * b_[i][1] - r[k][1] * b_[i][2];
        du[k] = r[k][2] * bc[1] - r[k][1] * bc[2];
      }
      emit(3, dd, du);
    }
    {
      Interval dd[3], du[3];
      for (int k = 0; k < 3; ++k) {
        dd[k] = dp[k][0] * b_[i][0] + dp[k][1] * b_[i][1] + dp[k][2] * b_[i][2];
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
