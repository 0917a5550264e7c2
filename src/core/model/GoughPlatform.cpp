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
