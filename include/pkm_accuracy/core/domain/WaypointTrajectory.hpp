// A trajectory through timed waypoints [t, q_1 .. q_n] in the pose coordinates of a robot type (PoseCoordinates, e.g.
// [t, x, y, z] for delta3, [t, x, y, z, roll, pitch, yaw] (s, m, rad) for the rigid-body pose of gough and rus6), one
// segment between consecutive waypoints (PiecewiseTrajectory: one box variable u in [0, 1] over the whole time span).
//
// Within the segment from waypoint a to waypoint b, with s = (t - t_a) / (t_b - t_a) in [0, 1]:
//   * Interpolation::Linear (any type): q(s) = q_a + s (q_b - q_a), every coordinate. For the rigid-body pose this is
//     a straight line in position and roll, pitch, yaw interpolated componentwise (named linear_rpy; a large
//     difference is a large rotation: yaw from 0.3 to 2 pi - 0.3 turns through pi);
//   * Interpolation::Slerp (only for the rigid-body pose): the position linear as above, the orientation along the
//     geodesic R(s) = R_a Rot(axis, s phi), where R_a is the exact rotation of rpy_a and (axis, phi), phi in [0, pi],
//     is the relative rotation R_a^T R_b computed in double at construction; the pose is the principal RPY of R(s)
//     (roll, yaw in (-pi, pi], pitch in [-pi/2, pi/2]) through rigorous interval atan2 (interval/InverseTrig.hpp):
//     roll = atan2(R21, R22), pitch = atan2(-R20, sqrt(R00^2 + R10^2)), yaw = atan2(R10, R00). R(1) equals R_b up to
//     the rounding of (axis, phi) (~1e-16 rad), which the piecewise domain handles as a (tiny) discontinuity; a
//     segment whose two orientations are bitwise equal keeps that RPY. The RPY of a slerp wraps at roll / yaw = +-pi
//     (the enclosure of a box across the wrap is [-pi, pi]: sound, but the verifier then needs more boxes there); near
//     pitch = +-pi/2 (gimbal lock) the derivative enclosures blow up.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"

namespace pkm_accuracy {
namespace domain {

class WaypointTrajectory final : public PiecewiseTrajectory {
 public:
  /// LinearRpy is Linear (its name for the rigid-body pose).
  enum class Interpolation { Linear, Slerp, LinearRpy = Linear };

  struct Waypoint {
    double t = 0.0;                      ///< s
    std::array<double, kMaxDof> pose{};  ///< the n pose coordinates, then zeros
  };

  /// Waypoints in the rigid-body pose (x, y, z, roll, pitch, yaw) of type gough.
  /// @throws InvalidArgument as below.
  WaypointTrajectory(std::vector<Waypoint> waypoints, Interpolation interpolation);
  /// Waypoints in the given pose coordinates.
  /// @throws InvalidArgument ("waypoints[i]...: ...", "interpolation: ...") for fewer than 2 waypoints, non-finite
  ///         values, times that do not increase strictly, a non-zero entry beyond the n pose coordinates, or slerp for
  ///         pose coordinates that are not the rigid-body pose (the message names the type and its coordinates).
  WaypointTrajectory(std::vector<Waypoint> waypoints, Interpolation interpolation, PoseCoordinates pose);

  const std::vector<Waypoint>& waypoints() const { return waypoints_; }
  Interpolation interpolation() const { return interpolation_; }
  std::string description() const override;

  /// "slerp", or for Linear "linear_rpy" (rigid-body pose) / "linear" (other pose coordinates).
  static std::string interpolationName(Interpolation i, const PoseCoordinates& pose = PoseCoordinates());

 protected:
  void segmentPose(int k, const TimeDualI& t, PoseDualI& out) const override;
  void segmentPose(int k, const TimeDualD& t, PoseDualD& out) const override;

 private:
  struct Segment {
    double ta = 0.0;
    Interval h;                                          ///< t_b - t_a
    std::array<double, kMaxDof> a{};                     ///< pose at waypoint a
    std::array<Interval, kMaxDof> delta;                 ///< pose_b - pose_a (position only for slerp)
    bool constantOrientation = false;                    ///< slerp between bitwise equal orientations
    double phi = 0.0;                                    ///< slerp angle (rad)
    std::array<std::array<Interval, 3>, 3> r, ka, kka;   ///< R_a, R_a [axis]x, R_a [axis]x^2 (slerp)
    std::array<std::array<double, 3>, 3> rd, kad, kkad;  ///< the same in double (point evaluation)
  };
  template <typename D>
  void evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const;
  static std::vector<double> timesOf(const std::vector<Waypoint>& waypoints, Interpolation interpolation,
                                     const PoseCoordinates& pose);
  void addSegment(const Waypoint& a, const Waypoint& b);

  std::vector<Waypoint> waypoints_;
  Interpolation interpolation_;
  std::vector<Segment> segments_;
};

}  // namespace domain
}  // namespace pkm_accuracy
