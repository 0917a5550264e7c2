#include "pkm_accuracy/core/domain/TransformedDomain.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include <Eigen/LU>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/InverseTrig.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

using interval::sqr;

/// Rz(yaw) Ry(pitch) Rx(roll) in double.
Eigen::Matrix3d rpyMatrix(double roll, double pitch, double yaw) {
  const double sr = std::sin(roll), cr = std::cos(roll), sp = std::sin(pitch), cp = std::cos(pitch);
  const double sy = std::sin(yaw), cy = std::cos(yaw);
  Eigen::Matrix3d m;
  m << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return m;
}

/// Principal roll, pitch, yaw of a rotation matrix, in double.
std::array<double, 3> rpyOf(const Eigen::Matrix3d& m) {
  return {std::atan2(m(2, 1), m(2, 2)), std::atan2(-m(2, 0), std::hypot(m(0, 0), m(1, 0))),
          std::atan2(m(1, 0), m(0, 0))};
}

/// The angle of (x, y) measured from the reference angle a0 (cos c0, sin s0), plus a0: equal to the angle of (x, y)
/// modulo 2 pi, and continuous away from a0 + pi instead of pi.
template <typename S>
S angleFrom(const S& y, const S& x, double a0, const Interval& c0, const Interval& s0) {
  using interval::atan2;
  return atan2(y * c0 - x * s0, x * c0 + y * s0) + Interval(a0);
}

}  // namespace

RigidTransform RigidTransform::fromTranslationYaw(const Eigen::Vector3d& translation, double yaw) {
  RigidTransform t;
  t.translation = translation;
  const double c = std::cos(yaw), s = std::sin(yaw);
  t.rotation << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return t;
}

RigidTransform RigidTransform::fromTranslationRpy(const Eigen::Vector3d& translation, double roll, double pitch,
                                                  double yaw) {
  RigidTransform t;
  t.translation = translation;
  t.rotation = rpyMatrix(roll, pitch, yaw);
  return t;
}

TransformedDomain::TransformedDomain(std::shared_ptr<const Domain> inner, const RigidTransform& base_from_frame)
    : inner_(std::move(inner)), translation_(base_from_frame.translation) {
  if (!inner_) throw InvalidArgument("transformed domain: expected a domain, got none (null)");
  if (inner_->poseDimension() != 6) {
    throw InvalidArgument(
        "transformed domain: expected a domain of rigid-body poses (x, y, z, roll, pitch, yaw), got "
        "one of " +
        std::to_string(inner_->poseDimension()) + " pose coordinates");
  }
  const Eigen::Matrix3d& r = base_from_frame.rotation;
  if (!translation_.allFinite()) {
    std::ostringstream os;
    os << "transform translation: expected 3 finite numbers (m), got [" << translation_.transpose() << "]";
    throw InvalidArgument(os.str());
  }
  if (!r.allFinite())
    throw InvalidArgument("transform rotation: expected a finite rotation matrix, got a non-finite one");
  const double deviation = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(deviation <= kOrthonormalityTolerance) || !(r.determinant() > 0.0)) {
    std::ostringstream os;
    os << "transform rotation: expected a rotation matrix (|R^T R - I| <= " << kOrthonormalityTolerance
       << ", det R = +1), got one with |R^T R - I| = " << deviation << " and det R = " << r.determinant();
    throw InvalidArgument(os.str());
  }
  rpy_ = rpyOf(r);
  aboutZ_ = rpy_[0] == 0.0 && rpy_[1] == 0.0;  // R21 = R20 = 0 (and R22 > 0)
  if (aboutZ_) {
    rpy_[0] = rpy_[1] = 0.0;  // no -0
    rotate_ = rpy_[2] != 0.0;
    if (rotate_) {
      cos_ = interval::cosPoint(rpy_[2]);
      sin_ = interval::sinPoint(rpy_[2]);
    }
    rd_ = rpyMatrix(0.0, 0.0, rpy_[2]);
  } else {
    const Interval sr = interval::sinPoint(rpy_[0]), cr = interval::cosPoint(rpy_[0]);
    const Interval sp = interval::sinPoint(rpy_[1]), cp = interval::cosPoint(rpy_[1]);
    const Interval sy = interval::sinPoint(rpy_[2]), cy = interval::cosPoint(rpy_[2]);
    r_ = {{{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
           {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
           {-sp, cp * sr, cp * cr}}};
    rd_ = rpyMatrix(rpy_[0], rpy_[1], rpy_[2]);
  }
  const double distance = (rd_ - r).cwiseAbs().maxCoeff();
  if (!(distance <= kOrthonormalityTolerance)) {
    std::ostringstream os;
    os << "transform rotation: its roll, pitch, yaw (" << rpy_[0] << ", " << rpy_[1] << ", " << rpy_[2]
       << ") give a rotation " << distance << " away from it (more than " << kOrthonormalityTolerance << ")";
    throw InvalidArgument(os.str());
  }
}

std::array<double, 2> TransformedDomain::referenceAngles(double roll, double pitch, double yaw) const {
  const std::array<double, 3> rpy = rpyOf(rd_ * rpyMatrix(roll, pitch, yaw));
  return {rpy[0], rpy[2]};
}

std::array<double, 2> TransformedDomain::referenceAnglesAt(const IVec& in) const {
  if (aboutZ_) return {0.0, 0.0};
  return referenceAngles(in[3].mid(), in[4].mid(), in[5].mid());
}

template <typename S>
void TransformedDomain::map(S pose[6], const std::array<double, 2>& ref) const {
  S out[6];
  if (aboutZ_) {
    if (rotate_) {
      out[0] = cos_ * pose[0] - sin_ * pose[1];
      out[1] = sin_ * pose[0] + cos_ * pose[1];
      out[5] = pose[5] + Interval(rpy_[2]);
    } else {
      out[0] = pose[0];
      out[1] = pose[1];
      out[5] = pose[5];
    }
    out[2] = pose[2];
    out[3] = pose[3];
    out[4] = pose[4];
  } else {
    using std::cos;
    using std::sin;
    using std::sqrt;
    for (int k = 0; k < 3; ++k) out[k] = r_[k][0] * pose[0] + r_[k][1] * pose[1] + r_[k][2] * pose[2];
    // R_F = Rz(yaw) Ry(pitch) Rx(roll) (columns 0 and 1 and entry (2, 2) are needed), N = R_T R_F.
    const S sr = sin(pose[3]), cr = cos(pose[3]), sp = sin(pose[4]), cp = cos(pose[4]), sy = sin(pose[5]),
            cy = cos(pose[5]);
    const S f0[3] = {cy * cp, sy * cp, -sp};
    const S f1[3] = {cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr};
    const S f2[3] = {cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr};
    auto n = [&](int i, const S f[3]) { return r_[i][0] * f[0] + r_[i][1] * f[1] + r_[i][2] * f[2]; };
    const S n00 = n(0, f0), n10 = n(1, f0), n20 = n(2, f0), n21 = n(2, f1), n22 = n(2, f2);
    using interval::atan2;
    out[3] = angleFrom(n21, n22, ref[0], interval::cosPoint(ref[0]), interval::sinPoint(ref[0]));
    out[4] = atan2(-n20, sqrt(sqr(n00) + sqr(n10)));
    out[5] = angleFrom(n10, n00, ref[1], interval::cosPoint(ref[1]), interval::sinPoint(ref[1]));
  }
  // Zero offsets are skipped so that the identity transform gives exactly the inner domain's own poses.
  for (int k = 0; k < 3; ++k) {
    if (translation_[k] != 0.0) out[k] = out[k] + Interval(translation_[k]);
  }
  for (int k = 0; k < 6; ++k) pose[k] = out[k];
}

void TransformedDomain::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  inner_->poseView(box, gradient, out);
  // One reference for the box, the centre and the gradient: the frame-F centre pose's (the box centre for a
  // workspace).
  const std::array<double, 2> ref = referenceAnglesAt(out.centrePose);
  Interval pose[6], centre[6];
  for (int i = 0; i < 6; ++i) {
    pose[i] = out.pose[i];
    centre[i] = out.centrePose[i];
  }
  map(pose, ref);
  map(centre, ref);
  for (int i = 0; i < 6; ++i) {
    out.pose[i] = pose[i];
    out.centrePose[i] = centre[i];
  }
  if (!out.hasGradient) return;
  if (out.variables != 1) {
    map(out.dualPose.data(), ref);
    return;
  }
  // One variable (a trajectory): map the value and its one derivative rather than kMaxDof derivatives (the others
  // are 0; the same rules; a tilted-frame trajectory box took 80 us with all six, 38 us so, bench/RESULTS.md).
  using Dual1 = interval::Dual<Interval, 1>;
  Dual1 d[6];
  for (int i = 0; i < 6; ++i) {
    d[i] = Dual1(out.dualPose[i].value());
    d[i].d(0) = out.dualPose[i].d(0);
  }
  map(d, ref);
  for (int i = 0; i < 6; ++i) {
    out.dualPose[i] = DualI(d[i].value());
    out.dualPose[i].d(0) = d[i].d(0);
  }
}

std::string TransformedDomain::frameDescription() const {
  std::ostringstream os;
  os.precision(10);
  os << "frame (translation [" << translation_.x() << ", " << translation_.y() << ", " << translation_.z()
     << "] m, rpy [" << rpy_[0] << ", " << rpy_[1] << ", " << rpy_[2] << "] rad)";
  return os.str();
}

IVec TransformedDomain::poseAt(const DVec& t) const {
  IVec p = inner_->poseAt(t);
  const std::array<double, 2> ref = referenceAnglesAt(p);
  Interval pose[6];
  for (int i = 0; i < 6; ++i) pose[i] = p[i];
  map(pose, ref);
  for (int i = 0; i < 6; ++i) p[i] = pose[i];
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
