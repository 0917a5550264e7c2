// Base of the one-parameter trajectory domains (WaypointTrajectory, PolynomialTrajectory): a pose defined piecewise
// on consecutive time segments [t_k, t_k+1] (k = 0 .. segments - 1), explored by the verifier through a single box
// variable u in [0, 1] with t(u) = t_0 + u (t_N - t_0) (real arithmetic; enclosed rigorously). The poses are in the
// pose coordinates of a robot type (PoseCoordinates: n = its dof coordinates, in the order of its description).
//
// What is certified: every pose of every segment at every time of its closed segment. At a segment boundary both
// one-sided poses (the end of segment k-1 and the start of segment k) belong to the trajectory; they coincide for a
// continuous trajectory up to rounding of the data (e.g. a slerp that ends within 1e-16 rad of the next waypoint),
// and the domain never assumes that they coincide.
//
// poseView of a box U of u (docs/trajectories.md, "Segments"):
//   * T = t(U) enclosed and clipped to [t_0, t_N]; every segment whose closed time interval meets T is a piece;
//   * dualPose: hull over the pieces of the pose and of its derivative with respect to u, each piece evaluated on
//     T intersected with its segment (forward-mode Dual over intervals);
//   * one piece: centrePose is the pose at the centre c of U, deviation = U - c (the usual mean-value data);
//   * several pieces (the box contains the boundaries t_b, b in B): centrePose is the hull of both one-sided poses at
//     every t_b, deviation = U - hull(u_b), u_b = (t_b - t_0) / (t_N - t_0). Sound without continuity: on piece j,
//     g(t) = g_j(t_b) + g_j'(xi) (t - t_b) for a boundary t_b of that piece inside T (mean-value theorem inside one
//     segment), and u - u_b lies in the deviation.
// The mean-value enclosure therefore never differentiates across a segment boundary.
//
// classify(): Inside everywhere, or, with a position region, Inside / Outside / Partial from the enclosure of the
// coordinates x, y, z over the box (the parts of the trajectory outside the region are then not verified, as for a
// workspace; only for pose coordinates that include x, y and z).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/domain/PoseCoordinates.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"
#include "pkm_accuracy/core/interval/Dual.hpp"

namespace pkm_accuracy {
namespace domain {

class PiecewiseTrajectory : public Domain {
 public:
  /// Value and derivative with respect to time along one segment, over intervals or at a point.
  using TimeDualI = interval::Dual<Interval, 1>;
  using TimeDualD = interval::Dual<double, 1>;
  using PoseDualI = std::array<TimeDualI, kMaxDof>;
  using PoseDualD = std::array<TimeDualD, kMaxDof>;

  /// A point of the trajectory in double (not certified): the pose and its derivative with respect to time.
  struct PointPose {
    DVec pose;      ///< the n pose coordinates
    DVec velocity;  ///< d pose / dt (per second)
    int segment = 0;
  };

  int variables() const override { return 1; }
  int poseDimension() const override { return pose_.size(); }
  /// The robot type and pose coordinates the poses are given in.
  const PoseCoordinates& poseCoordinates() const { return pose_; }
  std::string variableName(int i) const override;
  const IVec& initialBox() const override { return initial_; }
  void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const override;
  Containment classify(const IVec& box) const override;
  /// Enclosure of the pose at u = t[0] (the hull of both one-sided poses if t(u) may be a segment boundary).
  IVec poseAt(const DVec& t) const override;

  // ---- time
  // ----------------------------------------------------------------------------------------------------------
  int segments() const { return static_cast<int>(times_.size()) - 1; }
  /// Segment boundaries t_0 < t_1 < ... < t_N (s).
  const std::vector<double>& times() const { return times_; }
  double startTime() const { return times_.front(); }
  double endTime() const { return times_.back(); }
  /// t(u) = t_0 + u (t_N - t_0) in double (the time of a witness; the certified object is the pose enclosure).
  double timeOf(double u) const;
  /// The parameter of a time, in double, clamped to [0, 1].
  double parameterOf(double t) const;
  /// Enclosure of t(U), clipped to [t_0, t_N].
  Interval timeEnclosure(const Interval& u) const;
  /// Certified enclosure of the pose at a time t in [t_0, t_N] (hull of both sides at a boundary).
  IVec poseAtTime(double t) const;
  /// The pose and its time derivative at t in double with the point Dual rules (segment: the last one that starts
  /// at or before t). For tests and sampling oracles; not certified.
  PointPose pointAtTime(double t) const;
  /// The same at u: dpose/du = dpose/dt (t_N - t_0).
  PointPose pointAt(double u) const;

  // ---- optional position region ----------------------------------------------------------------------------------
  /// @throws InvalidArgument if the pose coordinates lack x, y or z (the message names the type and its coordinates).
  void setRegion(PositionRegion region);
  const std::optional<PositionRegion>& region() const { return region_; }

  /// Short description for reports, e.g. "waypoints (slerp), 12 waypoints".
  virtual std::string description() const = 0;

 protected:
  /// @param times the segment boundaries (validated by the subclass: finite, strictly increasing, >= 2 values).
  /// @param pose the pose coordinates (the subclass fills the first pose.size() entries of a pose).
  PiecewiseTrajectory(std::vector<double> times, PoseCoordinates pose);

  /// Pose of segment k over the times `t` (value: an enclosure of times inside [t_k, t_k+1]; derivative: dt/dvar),
  /// for every coordinate (the first poseDimension() entries): value and derivative with respect to the same
  /// variable.
  virtual void segmentPose(int k, const TimeDualI& t, PoseDualI& out) const = 0;
  /// The same at a point in double (Dual<double> rules; not certified).
  virtual void segmentPose(int k, const TimeDualD& t, PoseDualD& out) const = 0;

 private:
  /// First and last segment whose closed time interval meets T (T inside [t_0, t_N], not empty).
  void segmentRange(const Interval& T, int& first, int& last) const;
  /// Pose (value + d/du) of segment k over T intersected with the segment.
  void piece(int k, const Interval& T, PoseDualI& out) const;
  /// Hull of the pose values over T (every piece; no derivative).
  IVec poseHull(const Interval& T) const;

  std::vector<double> times_;
  PoseCoordinates pose_;
  std::array<int, 3> position_{};  ///< indices of x, y, z among the pose coordinates (with a region)
  Interval span_;                  ///< t_N - t_0 (enclosure)
  IVec initial_;
  std::optional<PositionRegion> region_;
};

}  // namespace domain
}  // namespace pkm_accuracy
