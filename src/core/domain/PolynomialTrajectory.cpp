#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {

void PolynomialTrajectory::checkCoefficients(const Segment& s, const std::string& where, const PoseCoordinates& pose) {
  const int n = pose.size();
  for (int i = n; i < kMaxDof; ++i) {
    if (!s.coefficients[i].empty()) {
      throw InvalidArgument(where + ": expected " + std::to_string(n) + " coordinate polynomials (" + pose.names() +
                            ") for " + pose.type() + ", got one for coordinate " + std::to_string(i));
    }
  }
  for (int i = 0; i < n; ++i) {
    const auto& c = s.coefficients[i];
    const std::string key = where + "." + pose.name(i);
    if (c.empty() || static_cast<int>(c.size()) > kMaxDegree + 1) {
      throw InvalidArgument(key + ": expected 1 to " + std::to_string(kMaxDegree + 1) + " coefficients, got " +
                            std::to_string(c.size()));
    }
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (!std::isfinite(c[j])) {
        std::ostringstream os;
        os << key << "[" << j << "]: expected a finite number, got " << c[j];
        throw InvalidArgument(os.str());
      }
    }
  }
}

std::vector<double> PolynomialTrajectory::timesOf(const std::vector<Segment>& segments, const PoseCoordinates& pose) {
  if (segments.empty()) throw InvalidArgument("polynomial_segments: expected at least one segment, got none");
  std::vector<double> times;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const Segment& s = segments[k];
    const std::string where = "polynomial_segments[" + std::to_string(k) + "]";
    if (!std::isfinite(s.start) || !std::isfinite(s.end) || !(s.start < s.end)) {
      std::ostringstream os;
      os << where << ".t: expected finite times [start, end] with start < end, got [" << s.start << ", " << s.end
         << "]";
      throw InvalidArgument(os.str());
    }
    if (k > 0 && s.start != segments[k - 1].end) {
      std::ostringstream os;
      os << where << ".t: expected the segment to start where the previous one ends (" << segments[k - 1].end
         << " s), got " << s.start << " s";
      throw InvalidArgument(os.str());
    }
    checkCoefficients(s, where, pose);
    times.push_back(s.start);
  }
  times.push_back(segments.back().end);
  return times;
}

PolynomialTrajectory::PolynomialTrajectory(std::vector<Segment> segments)
    : PolynomialTrajectory(std::move(segments), PoseCoordinates()) {}

PolynomialTrajectory::PolynomialTrajectory(std::vector<Segment> segments, PoseCoordinates pose)
    : PiecewiseTrajectory(timesOf(segments, pose), pose), segments_(std::move(segments)) {}

std::string PolynomialTrajectory::description() const {
  int degree = 0;
  for (const auto& s : segments_)
    for (const auto& c : s.coefficients) degree = std::max(degree, static_cast<int>(c.size()) - 1);
  return "polynomial, " + std::to_string(segments_.size()) + " segment" + (segments_.size() == 1 ? "" : "s") +
         ", degree <= " + std::to_string(degree);
}

template <typename D>
void PolynomialTrajectory::evaluate(int k, const D& t, std::array<D, kMaxDof>& out) const {
  using T = typename D::Scalar;
  const Segment& g = segments_[k];
  D tau = t - T(g.start);
  if constexpr (std::is_same<T, Interval>::value) {
    // tau lies in [0, end - start] for the times of this segment.
    const Interval range = Interval::fromBoundsUnchecked(0.0, interval::rounding::subUp(g.end, g.start));
    const Interval v = intersect(tau.value(), range);
    if (!v.isEmpty()) {
      D clipped(v);
      clipped.d(0) = tau.d(0);
      tau = clipped;
    }
  }
  for (int i = 0; i < poseDimension(); ++i) {
    const auto& c = g.coefficients[i];
    D p(T(c.back()));
    for (int j = static_cast<int>(c.size()) - 2; j >= 0; --j) p = p * tau + T(c[j]);
    out[i] = p;
  }
}

void PolynomialTrajectory::segmentPose(int k, const TimeDualI& t, PoseDualI& out) const { evaluate(k, t, out); }
void PolynomialTrajectory::segmentPose(int k, const TimeDualD& t, PoseDualD& out) const { evaluate(k, t, out); }

}  // namespace domain
}  // namespace pkm_accuracy
