#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

using TimeDualI = PiecewiseTrajectory::TimeDualI;

/// Hull of two value + derivative enclosures.
TimeDualI hullOf(const TimeDualI& a, const TimeDualI& b) {
  TimeDualI r(hull(a.value(), b.value()));
  r.d(0) = hull(a.d(0), b.d(0));
  return r;
}

}  // namespace

PiecewiseTrajectory::PiecewiseTrajectory(std::vector<double> times, PoseCoordinates pose)
    : times_(std::move(times)), pose_(std::move(pose)) {
  if (times_.size() < 2) throw InvalidArgument("trajectory: expected at least 2 segment boundaries");
  for (std::size_t i = 0; i < times_.size(); ++i) {
    if (!std::isfinite(times_[i]) || (i > 0 && !(times_[i] > times_[i - 1]))) {
      std::ostringstream os;
      os << "trajectory: segment boundary " << i << ": expected a finite time greater than the previous one, got "
         << times_[i];
      throw InvalidArgument(os.str());
    }
  }
  span_ = Interval(times_.back()) - Interval(times_.front());
  initial_.resize(1);
  initial_[0] = Interval(0.0, 1.0);
}

std::string PiecewiseTrajectory::variableName(int i) const { return i == 0 ? "u" : "?"; }

void PiecewiseTrajectory::setRegion(PositionRegion region) {
  const std::array<int, 3> xyz = pose_.positionIndices();
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) {
    throw InvalidArgument("region: a position region needs the pose coordinates x, y, z; " + pose_.describe());
  }
  position_ = xyz;
  region_ = std::move(region);
}

double PiecewiseTrajectory::timeOf(double u) const {
  const double t = times_.front() + u * (times_.back() - times_.front());
  return std::min(std::max(t, times_.front()), times_.back());
}

double PiecewiseTrajectory::parameterOf(double t) const {
  const double u = (t - times_.front()) / (times_.back() - times_.front());
  return std::min(std::max(u, 0.0), 1.0);
}

Interval PiecewiseTrajectory::timeEnclosure(const Interval& u) const {
  const Interval clipped = intersect(u, Interval(0.0, 1.0));
  if (clipped.isEmpty()) {
    std::ostringstream os;
    os << "trajectory parameter u: expected values in [0, 1], got " << u;
    throw InvalidArgument(os.str());
  }
  const Interval t = Interval(times_.front()) + clipped * span_;
  const Interval all(times_.front(), times_.back());
  const Interval r = intersect(t, all);
  // t(u) lies in [t_0, t_N] for u in [0, 1]; the enclosure meets it (an empty result would be a rounding bug).
  return r.isEmpty() ? all : r;
}

void PiecewiseTrajectory::segmentRange(const Interval& T, int& first, int& last) const {
  const int n = segments();
  // Segment k = [t_k, t_k+1] meets T iff t_k <= hi(T) and t_k+1 >= lo(T).
  first = static_cast<int>(std::lower_bound(times_.begin() + 1, times_.end(), T.lower()) - (times_.begin() + 1));
  last = static_cast<int>(std::upper_bound(times_.begin(), times_.end() - 1, T.upper()) - times_.begin()) - 1;
  first = std::min(std::max(first, 0), n - 1);
  last = std::min(std::max(last, first), n - 1);
}

void PiecewiseTrajectory::piece(int k, const Interval& T, PoseDualI& out) const {
  const Interval seg = Interval::fromBoundsUnchecked(times_[k], times_[k + 1]);
  Interval tk = intersect(T, seg);
  if (tk.isEmpty()) tk = T.upper() < seg.lower() ? Interval(seg.lower()) : Interval(seg.upper());  // touching
  TimeDualI t(tk);
  t.d(0) = span_;  // dt/du
  segmentPose(k, t, out);
}

IVec PiecewiseTrajectory::poseHull(const Interval& T) const {
  int first, last;
  segmentRange(T, first, last);
  const int n = poseDimension();
  IVec p(n);
  PoseDualI q;
  for (int k = first; k <= last; ++k) {
    piece(k, T, q);
    for (int i = 0; i < n; ++i) p[i] = k == first ? q[i].value() : hull(p[i], q[i].value());
  }
  return p;
}

void PiecewiseTrajectory::poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const {
  const Interval U = box[0];
  const Interval T = timeEnclosure(U);
  int first, last;
  segmentRange(T, first, last);
  const int n = poseDimension();
  PoseDualI acc, q;
  for (int k = first; k <= last; ++k) {
    piece(k, T, q);
    for (int i = 0; i < n; ++i) acc[i] = k == first ? q[i] : hullOf(acc[i], q[i]);
  }
  out.variables = 1;
  out.hasGradient = gradient;
  out.pose.resize(n);
  out.centrePose.resize(n);
  out.deviation.resize(1);
  for (int i = 0; i < n; ++i) {
    out.pose[i] = acc[i].value();
    out.dualPose[i] = DualI(acc[i].value());
    out.dualPose[i].d(0) = acc[i].d(0);
  }
  for (int i = n; i < kMaxDof; ++i) out.dualPose[i] = DualI(Interval(0.0));
  if (first == last) {
    // One segment: expand around the centre of the box.
    const double c = U.mid();
    piece(first, timeEnclosure(Interval(c)), q);
    for (int i = 0; i < n; ++i) out.centrePose[i] = q[i].value();
    out.deviation[0] = U - Interval(c);
    return;
  }
  // Several segments: expand around the boundaries t_b inside the box, with both one-sided poses there.
  Interval ub = Interval::empty();
  for (int b = first + 1; b <= last; ++b) {
    const Interval tb(times_[b]);
    PoseDualI left, right;
    piece(b - 1, tb, left);
    piece(b, tb, right);
    for (int i = 0; i < n; ++i) {
      const Interval both = hull(left[i].value(), right[i].value());
      out.centrePose[i] = b == first + 1 ? both : hull(out.centrePose[i], both);
    }
    ub = hull(ub, (tb - Interval(times_.front())) / span_);
  }
  out.deviation[0] = U - ub;
}

Containment PiecewiseTrajectory::classify(const IVec& box) const {
  if (!region_) return Containment::Inside;
  const IVec p = poseHull(timeEnclosure(box[0]));
  return region_->classify(p[position_[0]], p[position_[1]], p[position_[2]]);
}

IVec PiecewiseTrajectory::poseAt(const DVec& t) const { return poseHull(timeEnclosure(Interval(t[0]))); }

IVec PiecewiseTrajectory::poseAtTime(double t) const {
  if (!(t >= times_.front() && t <= times_.back())) {
    std::ostringstream os;
    os << "trajectory time: expected a value in [" << times_.front() << ", " << times_.back() << "] s, got " << t;
    throw InvalidArgument(os.str());
  }
  return poseHull(Interval(t));
}

PiecewiseTrajectory::PointPose PiecewiseTrajectory::pointAtTime(double t) const {
  t = std::min(std::max(t, times_.front()), times_.back());
  int k = static_cast<int>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
  k = std::min(std::max(k, 0), segments() - 1);
  PoseDualD q;
  segmentPose(k, TimeDualD::variable(t, 0), q);
  const int n = poseDimension();
  PointPose p;
  p.segment = k;
  p.pose.resize(n);
  p.velocity.resize(n);
  for (int i = 0; i < n; ++i) {
    p.pose[i] = q[i].value();
    p.velocity[i] = q[i].d(0);
  }
  return p;
}

PiecewiseTrajectory::PointPose PiecewiseTrajectory::pointAt(double u) const {
  PointPose p = pointAtTime(timeOf(u));
  p.velocity *= times_.back() - times_.front();
  return p;
}

}  // namespace domain
}  // namespace pkm_accuracy
