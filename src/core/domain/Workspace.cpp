#include "pkm_accuracy/core/domain/Workspace.hpp"

#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

const char* kNames[6] = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
const char* kKeys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

void checkInterval(int i, const Interval& r) {
  if (r.isEmpty() || !r.isBounded()) {
    std::ostringstream os;
    os << kKeys[i] << ": expected a finite range [min, max] with min <= max, got " << r;
    throw InvalidArgument(os.str());
  }
  if (i >= 3 && (std::fabs(r.lower()) > Workspace::kMaxAngle || std::fabs(r.upper()) > Workspace::kMaxAngle)) {
    std::ostringstream os;
    os.precision(17);
    os << kKeys[i] << ": expected a range within [-2 pi, 2 pi] = [-" << Workspace::kMaxAngle << ", "
       << Workspace::kMaxAngle << "] (rad; angles are periodic), got " << r;
    throw InvalidArgument(os.str());
  }
}

}  // namespace

Workspace::Workspace(PositionRegion region, const std::array<Interval, 3>& orientation) : region_(std::move(region)) {
  for (int i = 0; i < 3; ++i) checkInterval(3 + i, orientation[i]);
  initial_.resize(6);
  for (int k = 0; k < 3; ++k) initial_[k] = Interval(region_.boundsLo()[k], region_.boundsHi()[k]);
  for (int k = 0; k < 3; ++k) initial_[3 + k] = orientation[k];
}

Workspace Workspace::fromRanges(const std::array<Interval, 6>& ranges) {
  for (int i = 0; i < 6; ++i) checkInterval(i, ranges[i]);
  return Workspace(PositionRegion::box(Eigen::Vector3d(ranges[0].lower(), ranges[1].lower(), ranges[2].lower()),
                                       Eigen::Vector3d(ranges[0].upper(), ranges[1].upper(), ranges[2].upper())),
                   {ranges[3], ranges[4], ranges[5]});
}

std::string Workspace::variableName(int i) const { return (i >= 0 && i < 6) ? kNames[i] : "?"; }

void Workspace::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  identityPoseView(box, gradient, out);
}

Containment Workspace::classify(const IVec& box) const { return region_.classify(box[0], box[1], box[2]); }

IVec Workspace::poseAt(const DVec& t) const {
  IVec p(6);
  for (int i = 0; i < 6; ++i) p[i] = Interval(t[i]);
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
