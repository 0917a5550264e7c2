#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/InverseTrig.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

using Mat3I = std::array<std::array<Interval, 3>, 3>;
using Mat3D = std::array<std::array<double, 3>, 3>;

/// R = Rz(yaw) Ry(pitch) Rx(roll) (docs/conventions.md) for S = double or Interval.
template <typename S>
std::array<std::array<S, 3>, 3> rotationRpy(const S& roll, const S& pitch, const S& yaw) {
  using std::cos;
  using std::sin;
  const S sr = sin(roll), cr = cos(roll), sp = sin(pitch), cp = cos(pitch), sy = sin(yaw), cy = cos(yaw);
  return {{{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
           {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
           {-sp, cp * sr, cp * cr}}};
}

template <typename S>
std::array<std::array<S, 3>, 3> product(const std::array<std::array<S, 3>, 3>& a,
                                        const std::array<std::array<S, 3>, 3>& b) {
  std::array<std::array<S, 3>, 3> c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return c;
}

template <typename S>
std::array<std::array<S, 3>, 3> crossMatrix(const Eigen::Vector3d& u) {
  return {{{S(0.0), S(-u.z()), S(u.y())}, {S(u.z()), S(0.0), S(-u.x())}, {S(-u.y()), S(u.x()), S(0.0)}}};
}

/// Name of column k of a waypoint row [t, q_1 .. q_n].
std::string columnName(int k, const PoseCoordinates& pose) { return k == 0 ? "t" : pose.name(k - 1); }

}  // namespace

std::string WaypointTrajectory::interpolationName(Interpolation i, const PoseCoordinates& pose) {
  if (i == Interpolation::Slerp) return "slerp";
  return pose.rigidBody() ? "linear_rpy" : "linear";
}

std::vector<double> WaypointTrajectory::timesOf(const std::vector<Waypoint>& waypoints, Interpolation interpolation,
                                                const PoseCoordinates& pose) {
  if (interpolation == Interpolation::Slerp && !pose.rigidBody()) {
    throw InvalidArgument(
        "interpolation: slerp interpolates orientations of the rigid-body pose (x, y, z, roll, "
        "pitch, yaw); " +
        pose.describe() + ": use linear");
  }
  if (waypoints.size() < 2) {
    throw InvalidArgument("waypoints: expected at least 2 waypoints, got " + std::to_string(waypoints.size()));
  }
  const int n = pose.size();
  std::vector<double> times;
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& w = waypoints[i];
    for (int k = 0; k <= n; ++k) {
      const double v = k == 0 ? w.t : w.pose[k - 1];
      if (!std::isfinite(v)) {
        std::ostringstream os;
        os << "waypoints[" << i << "][" << k << "] (" << columnName(k, pose) << "): expected a finite number, got "
           << v;
        throw InvalidArgument(os.str());
      }
    }
    for (int k = n; k < kMaxDof; ++k) {
      if (w.pose[k] != 0.0) {
        std::ostringstream os;
        os << "waypoints[" << i << "]: pose entry " << k << " is beyond the " << n << " pose coordinates ("
           << pose.names() << ") of " << pose.type() << ": expected 0, got " << w.pose[k];
        throw InvalidArgument(os.str());
      }
    }
    if (i > 0 && !(w.t > waypoints[i - 1].t)) {
      std::ostringstream os;
      os << "waypoints[" << i << "]: time " << w.t << " s is not greater than the previous waypoint's time "
         << waypoints[i - 1].t << " s (times must increase strictly)";
      throw InvalidArgument(os.str());
    }
    times.push_back(w.t);
  }
  return times;
}

WaypointTrajectory::WaypointTrajectory(std::vector<Waypoint> waypoints, Interpolation interpolation)
    : WaypointTrajectory(std::move(waypoints), interpolation, PoseCoordinates()) {}

WaypointTrajectory::WaypointTrajectory(std::vector<Waypoint> waypoints, Interpolation interpolation,
                                       PoseCoordinates pose)
    : PiecewiseTrajectory(timesOf(waypoints, interpolation, pose), pose),
      waypoints_(std::move(waypoints)),
      interpolation_(interpolation) {
  // (~0.8 KB per segment: reserved, so that a long trajectory is not held twice while the vector grows.)
  if (!waypoints_.empty()) segments_.reserve(waypoints_.size() - 1);
  for (std::size_t k = 0; k + 1 < waypoints_.size(); ++k) addSegment(waypoints_[k], waypoints_[k + 1]);
}

void WaypointTrajectory::addSegment(const Waypoint& a, const Waypoint& b) {
  Segment g;
  g.ta = a.t;
  g.h = Interval(b.t) - Interval(a.t);
  g.a = a.pose;
  for (int i = 0; i < poseDimension(); ++i) g.delta[i] = Interval(b.pose[i]) - Interval(a.pose[i]);
  if (interpolation_ == Interpolation::Slerp) {
    g.constantOrientation = a.pose[3] == b.pose[3] && a.pose[4] == b.pose[4] && a.pose[5] == b.pose[5];
    const Mat3D ra = rotationRpy<double>(a.pose[3], a.pose[4], a.pose[5]);
    const Mat3D rb = rotationRpy<double>(b.pose[3], b.pose[4], b.pose[5]);
    Eigen::Matrix3d ma, mb;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        ma(i, j) = ra[i][j];
        mb(i, j) = rb[i][j];
      }
    const Eigen::AngleAxisd rel(Eigen::Matrix3d(ma.transpose() * mb));
    g.phi = rel.angle();
    Eigen::Vector3d axis = rel.axis();
    if (!(g.phi > 0.0) || !axis.allFinite() || axis.norm() == 0.0) {
      // Equal rotations (up to rounding): keep rpy_a; the rotation of rpy_b is within ~1e-16 rad of it.
      g.constantOrientation = true;
      g.phi = 0.0;
      axis = Eigen::Vector3d::UnitZ();
    }
    axis.normalize();
    g.r = rotationRpy<Interval>(Interval(a.pose[3]), Interval(a.pose[4]), Interval(a.pose[5]));
    const Mat3I k1 = crossMatrix<Interval>(axis);
    g.ka = product(g.r, k1);
    g.kka = product(g.ka, k1);
    g.rd = ra;
    const Mat3D k1d = crossMatrix<double>(axis);
    g.kad = product(g.rd, k1d);
    g.kkad = product(g.kad, k1d);
  }
  segments_.push_back(g);
}

std::string WaypointTrajectory::description() const {
  return "waypoints (" + interpolationName(interpolation_, poseCoordinates()) + "), " +
         std::to_string(waypoints_.size()) + " waypoints";
}

template <typename D>
void WaypointTrajectory::evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const {
  using T = typename D::Scalar;
  constexpr bool kInterval = std::is_same<T, Interval>::value;
  const Segment& g = segments_[k];
  D s;
  if constexpr (kInterval) {
    const D raw = (t - T(g.ta)) / g.h;
    s = D(intersect(raw.value(), Interval(0.0, 1.0)));
    if (s.value().isEmpty()) s = D(raw.value());
    s.d(0) = raw.d(0);
  } else {
    s = (t - g.ta) / (g.h.mid());
  }
  auto delta = [&](int i) -> T {
    if constexpr (kInterval) {
      return g.delta[i];
    } else {
      return g.delta[i].mid();
    }
  };
  if (interpolation_ == Interpolation::Linear) {
    for (int i = 0; i < poseDimension(); ++i) out[i] = s * delta(i) + T(g.a[i]);
    return;
  }
  // Slerp (rigid-body pose): linear position, geodesic orientation.
  for (int i = 0; i < 3; ++i) out[i] = s * delta(i) + T(g.a[i]);
  if (g.constantOrientation) {
    for (int i = 3; i < 6; ++i) out[i] = D(T(g.a[i]));
    return;
  }
  const D theta = s * T(g.phi);
  const D sn = sin(theta);
  const D cm = T(1.0) - cos(theta);
  auto entry = [&](int i, int j) -> D {
    if constexpr (kInterval) {
      return sn * g.ka[i][j] + cm * g.kka[i][j] + g.r[i][j];
    } else {
      return sn * g.kad[i][j] + cm * g.kkad[i][j] + g.rd[i][j];
    }
  };
  const D m00 = entry(0, 0), m10 = entry(1, 0), m20 = entry(2, 0), m21 = entry(2, 1), m22 = entry(2, 2);
  using interval::atan2;
  out[3] = atan2(m21, m22);
  out[4] = atan2(-m20, sqrt(sqr(m00) + sqr(m10)));
  out[5] = atan2(m10, m00);
}

void WaypointTrajectory::segmentPose(int k, const TimeDualI& t, PoseDualI& out) const { evaluate(k, t, out); }
void WaypointTrajectory::segmentPose(int k, const TimeDualD& t, PoseDualD& out) const { evaluate(k, t, out); }

}  // namespace domain
}  // namespace pkm_accuracy
