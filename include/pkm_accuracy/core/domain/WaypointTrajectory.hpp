// A trajectory through timed waypoints [t, x, y, z, roll, pitch, yaw] (s, m, rad), one segment between consecutive
// waypoints (PiecewiseTrajectory: one box variable u in [0, 1] over the whole time span).
//
// Within the segment from waypoint a to waypoint b, with s = (t - t_a) / (t_b - t_a) in [0, 1]:
//   * position: p(s) = p_a + s (p_b - p_a);
//   * orientation, Interpolation::LinearRpy: rpy(s) = rpy_a + s (rpy_b - rpy_a) (componentwise; a large difference
//     is a large rotation: yaw from 0.3 to 2 pi - 0.3 turns through pi);
//   * orientation, Interpolation::Slerp: the geodesic R(s) = R_a Rot(axis, s phi), where R_a is the exact rotation of
//     rpy_a and (axis, phi), phi in [0, pi], is the relative rotation R_a^T R_b computed in double at construction;
//     the pose is the principal RPY of R(s) (roll, yaw in (-pi, pi], pitch in [-pi/2, pi/2]) through rigorous
//     interval atan2 (interval/InverseTrig.hpp): roll = atan2(R21, R22), pitch = atan2(-R20, sqrt(R00^2 + R10^2)),
//     yaw = atan2(R10, R00). R(1) equals R_b up to the rounding of (axis, phi) (~1e-16 rad), which the piecewise
//     domain handles as a (tiny) discontinuity; a segment whose two orientations are bitwise equal keeps that RPY.
//     The RPY of a slerp wraps at roll / yaw = +-pi (the enclosure of a box across the wrap is [-pi, pi]: sound, but
//     the verifier then needs more boxes there); near pitch = +-pi/2 (gimbal lock) the derivative enclosures blow up.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"

namespace pkm_accuracy {
namespace domain {

class WaypointTrajectory final : public PiecewiseTrajectory {
 public:
  enum class Interpolation { LinearRpy, Slerp };

  struct Waypoint {
    double t = 0.0;                ///< s
    std::array<double, 6> pose{};  ///< x, y, z (m), roll, pitch, yaw (rad)
  };

  /// @throws InvalidArgument ("waypoints[i]: ...") for fewer than 2 waypoints, non-finite values or times that do not
  ///         increase strictly.
  WaypointTrajectory(std::vector<Waypoint> waypoints, Interpolation interpolation);

  const std::vector<Waypoint>& waypoints() const { return waypoints_; }
  Interpolation interpolation() const { return interpolation_; }
  std::string description() const override;

  /// "slerp" / "linear_rpy".
  static std::string interpolationName(Interpolation i);

 protected:
  void segmentPose(int k, const TimeDualI& t, PoseDualI& out) const override;
  void segmentPose(int k, const TimeDualD& t, PoseDualD& out) const override;

 private:
  struct Segment {
    double ta = 0.0;
    Interval h;                                          ///< t_b - t_a
    std::array<double, 6> a{};                           ///< pose at waypoint a
    std::array<Interval, 6> delta;                       ///< pose_b - pose_a (position; rpy for linear_rpy)
    bool constantOrientation = false;                    ///< slerp between bitwise equal orientations
    double phi = 0.0;                                    ///< slerp angle (rad)
    std::array<std::array<Interval, 3>, 3> r, ka, kka;   ///< R_a, R_a [axis]x, R_a [axis]x^2 (slerp)
    std::array<std::array<double, 3>, 3> rd, kad, kkad;  ///< the same in double (point evaluation)
  };
  template <typename D>
  void evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const;
  static std::vector<double> timesOf(const std::vector<Waypoint>& waypoints);

  std::vector<Waypoint> waypoints_;
  Interpolation interpolation_;
  std::vector<Segment> segments_;
};

}  // namespace domain
}  // namespace pkm_accuracy
