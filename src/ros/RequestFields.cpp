#include "RequestFields.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace fields {

namespace {
constexpr std::uint32_t kMaxThreads = 1024;
}  // namespace

std::string frameName(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

geometry_msgs::Pose poseMsg(const std::array<double, 6>& p) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(p[5], Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(p[4], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(p[3], Eigen::Vector3d::UnitX());
  geometry_msgs::Pose m;
  m.position.x = p[0];
  m.position.y = p[1];
  m.position.z = p[2];
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  m.orientation.w = q.w();
  return m;
}

geometry_msgs::Pose identityPose() {
  geometry_msgs::Pose m;
  m.orientation.w = 1.0;
  return m;
}

bool poseFromParts(const Eigen::Vector3d& position, const geometry_msgs::Quaternion& q,
                   const std::string& position_field, const std::string& orientation_field, std::array<double, 6>& pose,
                   std::string& error) {
  if (!position.allFinite()) {
    error = position_field + ": expected finite coordinates (m), got [" + num(position.x()) + ", " + num(position.y()) +
            ", " + num(position.z()) + "]";
    return false;
  }
  const Eigen::Quaterniond quat(q.w, q.x, q.y, q.z);
  const double norm2 = quat.squaredNorm();
  if (!quat.coeffs().allFinite() || !(std::fabs(norm2 - 1.0) <= 1e-2)) {
    error = orientation_field + ": expected a unit quaternion (|q|^2 within 1e-2 of 1), got [x " + num(q.x) + ", y " +
            num(q.y) + ", z " + num(q.z) + ", w " + num(q.w) + "] (|q|^2 = " + num(norm2) + ")";
    return false;
  }
  const Eigen::Matrix3d r = quat.normalized().toRotationMatrix();
  // R = Rz(yaw) M with M = Ry(pitch) Rx(roll) = [[cp, sp sr, sp cr], [0, cr, -sr], [-sp, cp sr, cp cr]]: yaw from
  // the first column (any value where it vanishes, pitch +-pi/2), then roll and pitch from M = Rz(-yaw) R, whose
  // entries used here all have magnitude up to 1 (no division by cos(pitch)).
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  const Eigen::Matrix3d m = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * r;
  pose = {position.x(), position.y(), position.z(), std::atan2(-m(1, 2), m(1, 1)), std::atan2(-m(2, 0), m(0, 0)), yaw};
  return true;
}

std::string num(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

std::string idx(const char* field, std::size_t i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

bool option(double x, double dflt, const char* field, const char* expected, double& out, std::string& error,
            double upper) {
  if (!std::isfinite(x) || x < 0.0 || !(x < upper)) {
    error = std::string(field) + ": expected " + expected + ", got " + num(x);
    return false;
  }
  out = x == 0.0 ? dflt : x;
  return true;
}

bool threads(std::uint32_t requested, std::string& error) {
  if (requested <= kMaxThreads) return true;
  error = "threads: expected 0 (all hardware threads) to " + std::to_string(kMaxThreads) + ", got " +
          std::to_string(requested);
  return false;
}

bool method(const std::string& requested, const std::string& dflt, std::string& out, std::string& error) {
  out = requested.empty() ? dflt : requested;
  if (out.empty()) return true;
  const std::vector<std::string> methods = enclosure::enclosureNames();
  if (std::find(methods.begin(), methods.end(), out) != methods.end()) return true;
  std::string list;
  for (const auto& m : methods) list += (list.empty() ? "\"" : ", \"") + m + "\"";
  error = std::string(requested.empty() ? "method (from ~default_method)" : "method") + ": expected one of " + list +
          " or \"\" (default), got \"" + out + "\"";
  return false;
}

std::string errorNames(const std::vector<model::PoseComponent>& pose) {
  std::string names;
  for (const model::PoseComponent& c : pose) names += (names.empty() ? "" : ", ") + c.errorName();
  return names;
}

std::string rigidBodyOnly(const QueryDefaults& defaults, const char* service) {
  if (defaults.rigidBodyPose()) return "";
  std::string pose;
  for (const model::PoseComponent& c : defaults.pose) pose += (pose.empty() ? "" : ", ") + c.name;
  return std::string(service) + ": the loaded robot, type " + defaults.robot_type + ", has the pose (" + pose +
         "), not the rigid-body pose (x, y, z, roll, pitch, yaw) that " + service +
         " needs; verify its workspaces with verify_workspace (named or pose_min / pose_max)";
}

bool geometrySplitting(const std::string& requested, std::string& out, std::string& error) {
  if (requested.empty() || requested == "auto" || requested == "never" || requested == "always") {
    out = requested.empty() ? "auto" : requested;
    return true;
  }
  error = "geometry_splitting: expected \"auto\", \"never\", \"always\" or \"\" (auto), got \"" + requested + "\"";
  return false;
}

}  // namespace fields
}  // namespace ros_layer
}  // namespace pkm_accuracy
