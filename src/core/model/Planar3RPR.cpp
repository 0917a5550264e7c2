#include "pkm_accuracy/core/model/Planar3RPR.hpp"

#include <cmath>

#include "pkm_accuracy/core/interval/Functions.hpp"

namespace pkm_accuracy {
namespace model {
namespace {

using interval::sqr;

// One implementation of the kinematics for every scalar type S (double, Interval, Dual<Interval, N>) and geometry
// coefficient type G (double, Interval). `rows[i]` receives row i of J^-1, `lengths[i]` the length of leg i.
template <typename S, typename G>
void planarKinematics(const S pose[3], const std::array<std::array<G, 2>, 3>& a,
                      const std::array<std::array<G, 2>, 3>& b, const std::array<G, 2>& c, S rows[3][3], S lengths[3]) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S st = sin(pose[2]), ct = cos(pose[2]);
  for (int i = 0; i < 3; ++i) {
    const G bc[2] = {b[i][0] - c[0], b[i][1] - c[1]};
    // R b_i, R (b_i - c) and B_i - A_i.
    const S rb[2] = {ct * b[i][0] - st * b[i][1], st * b[i][0] + ct * b[i][1]};
    const S u[2] = {ct * bc[0] - st * bc[1], st * bc[0] + ct * bc[1]};
    const S d[2] = {pose[0] + rb[0] - a[i][0], pose[1] + rb[1] - a[i][1]};
    const S len = sqrt(sqr(d[0]) + sqr(d[1]));
    lengths[i] = len;
    rows[i][0] = d[0] / len;
    rows[i][1] = d[1] / len;
    rows[i][2] = (u[0] * d[1] - u[1] * d[0]) / len;
  }
}

}  // namespace

Planar3RPR::Planar3RPR(Planar3RPRGeometry geometry) : geometry_(std::move(geometry)) {
  geometry_.validate();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 2; ++k) {
      ad_[i][k] = geometry_.base_anchors[i][k];
      bd_[i][k] = geometry_.platform_anchors[i][k];
      a_[i][k] = Interval(ad_[i][k]);
      b_[i][k] = Interval(bd_[i][k]);
    }
  }
  for (int k = 0; k < 2; ++k) {
    cd_[k] = geometry_.tool_point[k];
    c_[k] = Interval(cd_[k]);
  }
}

std::string Planar3RPR::componentName(int k) const {
  static const char* kNames[3] = {"x [m]", "y [m]", "theta [rad]"};
  return (k >= 0 && k < 3) ? kNames[k] : "?";
}

DMat Planar3RPR::inverseJacobian(const DVec& pose) const {
  double rows[3][3], len[3];
  planarKinematics(pose.data(), ad_, bd_, cd_, rows, len);
  DMat m(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = rows[i][j];
  return m;
}

DVec Planar3RPR::legLengths(const DVec& pose) const {
  double rows[3][3], len[3];
  planarKinematics(pose.data(), ad_, bd_, cd_, rows, len);
  DVec l(3);
  for (int i = 0; i < 3; ++i) l[i] = len[i];
  return l;
}

IMat Planar3RPR::inverseJacobian(const IVec& pose) const {
  Interval rows[3][3], len[3];
  planarKinematics(pose.data(), a_, b_, c_, rows, len);
  IMat m(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = rows[i][j];
  return m;
}

IVec Planar3RPR::legLengths(const IVec& pose) const {
  Interval rows[3][3], len[3];
  planarKinematics(pose.data(), a_, b_, c_, rows, len);
  IVec l(3);
  for (int i = 0; i < 3; ++i) l[i] = len[i];
  return l;
}

void Planar3RPR::inverseJacobian(const DualPose& pose, MatrixWithGradient& out) const {
  DualI rows[3][3], len[3];
  planarKinematics(pose.data(), a_, b_, c_, rows, len);
  out.value.resize(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.value(i, j) = rows[i][j].value();
  for (int m = 0; m < kMaxDof; ++m) {
    out.d[m].resize(3, 3);
    // Variables the pose does not depend on get exact zeros (the outward-rounded products would give [-tiny, tiny]).
    bool depends = false;
    for (int k = 0; k < 3; ++k) depends = depends || pose[k].d(m) != Interval(0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.d[m](i, j) = depends ? rows[i][j].d(m) : Interval(0.0);
  }
}

}  // namespace model
}  // namespace pkm_accuracy
