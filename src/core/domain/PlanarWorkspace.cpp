#include "pkm_accuracy/core/domain/PlanarWorkspace.hpp"

#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

const char* kNames[3] = {"x [m]", "y [m]", "theta [rad]"};
const char* kKeys[3] = {"x", "y", "theta"};

void checkInterval(int i, const Interval& r) {
  if (r.isEmpty() || !r.isBounded()) {
    std::ostringstream os;
    os << kKeys[i] << ": expected a finite range [min, max] with min <= max, got " << r;
    throw InvalidArgument(os.str());
  }
}

}  // namespace

PlanarWorkspace PlanarWorkspace::fromRanges(const std::array<Interval, 3>& ranges) {
  for (int i = 0; i < 3; ++i) checkInterval(i, ranges[i]);
  PlanarWorkspace w;
  w.initial_.resize(3);
  for (int i = 0; i < 3; ++i) w.initial_[i] = ranges[i];
  return w;
}

PlanarWorkspace PlanarWorkspace::disc(const Eigen::Vector2d& centre, double radius, const Interval& theta) {
  if (!centre.allFinite()) throw InvalidArgument("disc centre: expected finite coordinates");
  if (!std::isfinite(radius) || !(radius > 0.0)) {
    std::ostringstream os;
    os << "disc radius: expected a finite value > 0, got " << radius;
    throw InvalidArgument(os.str());
  }
  checkInterval(2, theta);
  PlanarWorkspace w;
  w.disc_ = true;
  w.centre_ = centre;
  w.radius_ = radius;
  w.initial_.resize(3);
  for (int k = 0; k < 2; ++k) {
    w.initial_[k] =
        Interval(interval::rounding::subDown(centre[k], radius), interval::rounding::addUp(centre[k], radius));
  }
  w.initial_[2] = theta;
  return w;
}

std::string PlanarWorkspace::variableName(int i) const { return (i >= 0 && i < 3) ? kNames[i] : "?"; }

void PlanarWorkspace::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  identityPoseView(box, gradient, out);
}

Containment PlanarWorkspace::classify(const IVec& box) const {
  // The ranges of the initial box by exact comparisons (a point on a face is inside).
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    if (box[k].isEmpty() || box[k].lower() > initial_[k].upper() || box[k].upper() < initial_[k].lower()) {
      return Containment::Outside;
    }
    if (box[k].lower() < initial_[k].lower() || box[k].upper() > initial_[k].upper()) inside = false;
  }
  if (disc_) {
    const Interval g = interval::sqr(box[0] - Interval(centre_.x())) + interval::sqr(box[1] - Interval(centre_.y())) -
                       interval::sqr(Interval(radius_));
    if (g.lower() > 0.0) return Containment::Outside;
    if (g.upper() > 0.0) inside = false;
  }
  return inside ? Containment::Inside : Containment::Partial;
}

IVec PlanarWorkspace::poseAt(const DVec& t) const {
  IVec p(3);
  for (int i = 0; i < 3; ++i) p[i] = Interval(t[i]);
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
