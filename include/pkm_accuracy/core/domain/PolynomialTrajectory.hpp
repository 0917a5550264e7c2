// A trajectory given by polynomial segments (e.g. quintic splines from a planner): on segment k = [start_k, end_k],
// every pose coordinate i is p_ki(tau) = sum_j c_kij tau^j in the local time tau = t - start_k (s), lowest degree
// first. Segments must tile the time span (end_k == start_k+1 exactly); the pose need not be continuous at a
// boundary (both one-sided poses are verified, PiecewiseTrajectory). Evaluated by interval Horner's scheme with
// forward-mode Dual derivatives.
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
    /// Per coordinate (x, y, z in m; roll, pitch, yaw in rad): coefficients of tau^0, tau^1, ... (at least one).
    std::array<std::vector<double>, 6> coefficients;
  };

  /// Highest accepted degree.
  static constexpr int kMaxDegree = 31;

  /// @throws InvalidArgument ("polynomial_segments[k]...: ...") for no segment, non-finite or inverted times,
  ///         segments that do not tile the span, missing or non-finite coefficients, degree > kMaxDegree.
  explicit PolynomialTrajectory(std::vector<Segment> segments);

  const std::vector<Segment>& polynomialSegments() const { return segments_; }
  std::string description() const override;

 protected:
  void segmentPose(int k, const TimeDualI& t, PoseDualI& out) const override;
  void segmentPose(int k, const TimeDualD& t, PoseDualD& out) const override;

 private:
  template <typename D>
  void evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const;
  static std::vector<double> timesOf(const std::vector<Segment>& segments);

  std::vector<Segment> segments_;
};

}  // namespace domain
}  // namespace pkm_accuracy
