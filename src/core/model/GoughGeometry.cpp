#include "pkm_accuracy/core/model/GoughGeometry.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace model {
namespace {

std::string vecStr(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(10);
  os << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return os.str();
}

void checkPoints(const std::vector<Eigen::Vector3d>& pts, const char* name, std::size_t expected) {
  if (pts.size() != expected) {
    std::ostringstream os;
    os << name << ": expected " << expected << " points, got " << pts.size();
    throw InvalidGeometry(os.str());
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) {
      throw InvalidGeometry(std::string(name) + "[" + std::to_string(i) + "]: expected finite coordinates, got " +
                            vecStr(pts[i]));
    }
  }
}

void checkDistinct(const std::vector<Eigen::Vector3d>& pts, const char* name) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if ((pts[i] - pts[j]).norm() < 1e-12 * (1.0 + pts[i].norm())) {
        throw InvalidGeometry(std::string(name) + "[" + std::to_string(i) + "]: coincides with " + name + "[" +
                              std::to_string(j) + "] at " + vecStr(pts[i]));
      }
    }
  }
}

void checkHalfwidths(const std::vector<Eigen::Vector3d>& hw, const char* name, std::size_t legs) {
  if (hw.empty()) return;
  checkPoints(hw, name, legs);
  for (std::size_t i = 0; i < hw.size(); ++i) {
    if ((hw[i].array() < 0.0).any()) {
      throw InvalidGeometry(std::string(name) + "[" + std::to_string(i) + "]: expected half-widths >= 0, got " +
                            vecStr(hw[i]));
    }
  }
}

}  // namespace

void applyCoordinateBound(const CoordinateBound& b, double& value, double& halfwidth) {
  if (!std::isfinite(value) || !std::isfinite(b.lo) || !std::isfinite(b.hi)) {
    std::ostringstream os;
    os.precision(10);
    if (b.symmetric) {
      os << "expected a finite half-width >= 0 (m), got " << b.hi;
    } else {
      os << "expected finite offsets [lo, hi] (m), got [" << b.lo << ", " << b.hi << "]";
    }
    throw InvalidGeometry(os.str());
  }
  if (b.symmetric) {
    if (!(b.hi >= 0.0) || b.lo != -b.hi) {
      std::ostringstream os;
      os.precision(10);
      os << "expected a half-width >= 0 (m), got " << b.hi;
      throw InvalidGeometry(os.str());
    }
    halfwidth = b.hi;
    return;
  }
  if (!(b.lo <= b.hi)) {
    std::ostringstream os;
    os.precision(10);
    os << "expected offsets [lo, hi] with lo <= hi (m), got [" << b.lo << ", " << b.hi << "]";
    throw InvalidGeometry(os.str());
  }
  // [value + lo, value + hi] rounded outward, then its centre c and h >= max(c - low, high - c) rounded up: so
  // [c - h, c + h] (which the models round outward again) contains the range.
  const double low = interval::rounding::addDown(value, b.lo), high = interval::rounding::addUp(value, b.hi);
  const double c = 0.5 * low + 0.5 * high;
  const double h = std::max(interval::rounding::subUp(high, c), interval::rounding::subUp(c, low));
  if (!std::isfinite(c) || !std::isfinite(h)) throw InvalidGeometry("the range is not finite");
  value = c;
  halfwidth = std::max(h, 0.0);
}

bool GoughGeometry::hasUncertainty() const {
  auto any = [](const std::vector<Eigen::Vector3d>& v) {
    for (const auto& h : v)
      if ((h.array() > 0.0).any()) return true;
    return false;
  };
  return any(base_anchor_halfwidth) || any(platform_anchor_halfwidth) || (tool_point_halfwidth.array() > 0.0).any();
}

void GoughGeometry::setUniformAnchorUncertainty(double h) {
  if (!(h >= 0.0) || !std::isfinite(h)) {
    throw InvalidArgument("anchor uncertainty: expected a finite half-width >= 0 m, got " + std::to_string(h));
  }
  if (h == 0.0) {
    base_anchor_halfwidth.clear();
    platform_anchor_halfwidth.clear();
    return;
  }
  base_anchor_halfwidth.assign(base_anchors.size(), Eigen::Vector3d::Constant(h));
  platform_anchor_halfwidth.assign(platform_anchors.size(), Eigen::Vector3d::Constant(h));
}

void GoughGeometry::validate() const {
  constexpr std::size_t kLegs = 6;
  checkPoints(base_anchors, "base_anchors", kLegs);
  checkPoints(platform_anchors, "platform_anchors", kLegs);
  checkDistinct(base_anchors, "base_anchors");
  checkDistinct(platform_anchors, "platform_anchors");
  if (sensor_error.size() != kLegs) {
    throw InvalidGeometry("sensor_error: expected 6 values (one per leg), got " + std::to_string(sensor_error.size()));
  }
  for (std::size_t i = 0; i < sensor_error.size(); ++i) {
    if (!(sensor_error[i] > 0.0) || !std::isfinite(sensor_error[i])) {
      std::ostringstream os;
      os << "sensor_error[" << i << "]: expected a finite value > 0 m, got " << sensor_error[i];
      throw InvalidGeometry(os.str());
    }
  }
  if (!tool_point.allFinite())
    throw InvalidGeometry("tool_point: expected finite coordinates, got " + vecStr(tool_point));
  checkHalfwidths(base_anchor_halfwidth, "base_anchor_halfwidth", kLegs);
  checkHalfwidths(platform_anchor_halfwidth, "platform_anchor_halfwidth", kLegs);
  if (!tool_point_halfwidth.allFinite() || (tool_point_halfwidth.array() < 0.0).any()) {
    throw InvalidGeometry("tool_point_halfwidth: expected finite half-widths >= 0, got " +
                          vecStr(tool_point_halfwidth));
  }
}

std::string GoughGeometry::summary() const {
  std::ostringstream os;
  os.precision(4);
  double rb = 0.0, rp = 0.0;
  for (const auto& a : base_anchors) rb = std::max(rb, a.head<2>().norm());
  for (const auto& b : platform_anchors) rp = std::max(rp, b.head<2>().norm());
  os << "Gough platform, " << legCount() << " legs, base radius " << rb << " m, platform radius " << rp
     << " m, tool point " << vecStr(tool_point) << (hasUncertainty() ? ", with anchor uncertainty" : "");
  return os.str();
}

}  // namespace model
}  // namespace pkm_accuracy
