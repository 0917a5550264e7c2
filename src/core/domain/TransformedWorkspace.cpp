#include "pkm_accuracy/core/domain/TransformedWorkspace.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include <Eigen/LU>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"

namespace pkm_accuracy {
namespace domain {

RigidTransform RigidTransform::fromTranslationYaw(const Eigen::Vector3d& translation, double yaw) {
  RigidTransform t;
  t.translation = translation;
  const double c = std::cos(yaw), s = std::sin(yaw);
  t.rotation << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return t;
}

TransformedWorkspace::TransformedWorkspace(Workspace workspace, const RigidTransform& base_from_frame)
    : workspace_(std::move(workspace)), translation_(base_from_frame.translation) {
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
  if (r(0, 2) != 0.0 || r(1, 2) != 0.0 || r(2, 0) != 0.0 || r(2, 1) != 0.0) {
    std::ostringstream os;
    os.precision(6);
    os << "transform rotation: only rotations about the z axis of the base frame are supported (roll and pitch of "
          "the frame both 0; general rotations need interval atan2/asin, not in the core yet), got a frame whose z "
          "axis is tilted by "
       << std::atan2(std::hypot(r(0, 2), r(1, 2)), r(2, 2)) << " rad from the base frame's";
    throw InvalidArgument(os.str());
  }
  yaw_ = std::atan2(r(1, 0), r(0, 0));
  rotate_ = yaw_ != 0.0;
  if (rotate_) {
    cos_ = interval::cosPoint(yaw_);
    sin_ = interval::sinPoint(yaw_);
  }
}

template <typename S>
void TransformedWorkspace::map(const S in[6], S out[6]) const {
  if (rotate_) {
    out[0] = cos_ * in[0] - sin_ * in[1];
    out[1] = sin_ * in[0] + cos_ * in[1];
    out[5] = in[5] + Interval(yaw_);
  } else {
    out[0] = in[0];
    out[1] = in[1];
    out[5] = in[5];
  }
  out[2] = in[2];
  out[3] = in[3];
  out[4] = in[4];
  // Zero offsets are skipped so that the identity transform gives exactly the workspace's own poses.
  for (int k = 0; k < 3; ++k) {
    if (translation_[k] != 0.0) out[k] = out[k] + Interval(translation_[k]);
  }
}

void TransformedWorkspace::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  out.variables = 6;
  Interval in[6], mapped[6], centre[6], centreMapped[6];
  for (int i = 0; i < 6; ++i) {
    in[i] = box[i];
    centre[i] = Interval(box[i].mid());
  }
  map(in, mapped);
  map(centre, centreMapped);
  out.pose.resize(6);
  out.centrePose.resize(6);
  out.deviation.resize(6);
  for (int i = 0; i < 6; ++i) {
    out.pose[i] = mapped[i];
    out.centrePose[i] = centreMapped[i];
    out.deviation[i] = box[i] - centre[i];
  }
  out.hasGradient = gradient;
  if (gradient) {
    DualI v[6], d[6];
    for (int i = 0; i < 6; ++i) v[i] = DualI::variable(box[i], i);
    map(v, d);
    for (int i = 0; i < 6; ++i) out.dualPose[i] = d[i];
  }
}

IVec TransformedWorkspace::poseAt(const DVec& t) const {
  Interval in[6], mapped[6];
  for (int i = 0; i < 6; ++i) in[i] = Interval(t[i]);
  map(in, mapped);
  IVec p(6);
  for (int i = 0; i < 6; ++i) p[i] = mapped[i];
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
