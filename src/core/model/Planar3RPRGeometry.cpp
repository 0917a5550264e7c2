#include "pkm_accuracy/core/model/Planar3RPRGeometry.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace model {
namespace {

constexpr std::size_t kLegs = 3;

std::string vecStr(const Eigen::Vector2d& v) {
  std::ostringstream os;
  os.precision(10);
  os << '[' << v.x() << ", " << v.y() << ']';
  return os.str();
}

void checkPoints(const std::vector<Eigen::Vector2d>& pts, const char* name) {
  if (pts.size() != kLegs) {
    std::ostringstream os;
    os << name << ": expected " << kLegs << " points, got " << pts.size();
    throw InvalidGeometry(os.str());
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) {
      throw InvalidGeometry(std::string(name) + "[" + std::to_string(i) + "]: expected finite coordinates, got " +
                            vecStr(pts[i]));
    }
  }
}

void checkDistinct(const std::vector<Eigen::Vector2d>& pts, const char* name) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if ((pts[i] - pts[j]).norm() < 1e-12 * (1.0 + pts[i].norm())) {
        throw InvalidGeometry(std::string(name) + "[" + std::to_string(i) + "]: coincides with " + name + "[" +
                              std::to_string(j) + "] at " + vecStr(pts[i]));
      }
    }
  }
}

}  // namespace

void Planar3RPRGeometry::validate() const {
  checkPoints(base_anchors, "base_anchors");
  checkPoints(platform_anchors, "platform_anchors");
  checkDistinct(base_anchors, "base_anchors");
  checkDistinct(platform_anchors, "platform_anchors");
  if (sensor_error.size() != kLegs) {
    throw InvalidGeometry("sensor_error: expected 3 values (one per leg), got " + std::to_string(sensor_error.size()));
  }
  for (std::size_t i = 0; i < sensor_error.size(); ++i) {
    if (!(sensor_error[i] > 0.0) || !std::isfinite(sensor_error[i])) {
      std::ostringstream os;
      os << "sensor_error[" << i << "]: expected a finite value > 0 m, got " << sensor_error[i];
      throw InvalidGeometry(os.str());
    }
  }
  if (!tool_point.allFinite()) {
    throw InvalidGeometry("tool_point: expected finite coordinates, got " + vecStr(tool_point));
  }
}

std::string Planar3RPRGeometry::summary() const {
  std::ostringstream os;
  os.precision(4);
  double rb = 0.0, rp = 0.0;
  for (const auto& a : base_anchors) rb = std::max(rb, a.norm());
  for (const auto& b : platform_anchors) rp = std::max(rp, b.norm());
  os << "planar 3-RPR, " << legCount() << " legs, base radius " << rb << " m, platform radius " << rp
     << " m, tool point " << vecStr(tool_point);
  return os.str();
}

}  // namespace model
}  // namespace pkm_accuracy
