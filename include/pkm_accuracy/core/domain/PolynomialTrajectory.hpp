// A trajectory given by polynomial segments (e.g. quintic splines from a planner): on segment k = [start_k, end_k],
// every pose coordinate i (of a robot type's PoseCoordinates: x, y, z, roll, pitch, yaw for gough, x, y, z for
// delta3, ...) is p_ki(tau) = sum_j c_kij tau^j in the local time tau = t - start_k (s), lowest degree first.
// Segments must tile the time span (end_k == start_k+1 exactly); the pose need not be continuous at a boundary (both
// one-sided poses are verified, PiecewiseTrajectory). Evaluated by interval Horner's scheme with forward-mode Dual
// derivatives.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/PiecewiseTrajectory.hpp"

namespace pkm_accuracy {
namespace domain {

class PolynomialTrajectory final : public PiecewiseTrajectory {
 public:
  struct Segment {
    double start = 0.0;  ///< s
    double end = 0.0;    ///< s
    /// Per pose coordinate i < n, in the order of the PoseCoordinates: coefficients of tau^0, tau^1, ... (at least
    /// one); the entries i >= n stay empty.
    std::array<std::vector<double>, kMaxDof> coefficients;
  };

  /// Highest accepted degree.
  static constexpr int kMaxDegree = 31;

  /// Segments in the rigid-body pose (x, y, z, roll, pitch, yaw) of type gough.
  /// @throws InvalidArgument as below.
  explicit PolynomialTrajectory(std::vector<Segment> segments);
  /// Segments in the given pose coordinates.
  /// @throws InvalidArgument ("polynomial_segments[k]...: ...") for no segment, non-finite or inverted times,
  ///         segments that do not tile the span, missing or non-finite coefficients, degree > kMaxDegree, or
  ///         polynomials for more coordinates than the n of `pose` (the message names the expected number).
  PolynomialTrajectory(std::vector<Segment> segments, PoseCoordinates pose);

  const std::vector<Segment>& polynomialSegments() const { return segments_; }
  std::string description() const override;

 protected:
  void segmentPose(int k, const TimeDualI& t, PoseDualI& out) const override;
  void segmentPose(int k, const TimeDualD& t, PoseDualD& out) const override;

 private:
  template <typename D>
  void evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const;
  static std::vector<double> timesOf(const std::vector<Segment>& segments, const PoseCoordinates& pose);
  static void checkCoefficients(const Segment& s, const std::string& where, const PoseCoordinates& pose);

  std::vector<Segment> segments_;
};

}  // namespace domain
}  // namespace pkm_accuracy
