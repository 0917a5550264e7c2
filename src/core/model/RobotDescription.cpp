#include "pkm_accuracy/core/model/RobotDescription.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/model/DependencyMask.hpp"

namespace pkm_accuracy {
namespace model {

namespace {
[[noreturn]] void fail(const std::string& type, const std::string& what) {
  throw InvalidGeometry((type.empty() ? std::string("robot") : type) + ": " + what);
}

std::string number(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}
}  // namespace

std::vector<PoseComponent> rigidBodyPose() {
  return {{"x", "m", false},
          {"y", "m", false},
          {"z", "m", false},
          {"roll", "rad", true, "drx"},
          {"pitch", "rad", true, "dry"},
          {"yaw", "rad", true, "drz"}};
}

bool hasRigidBodyPose(const std::vector<PoseComponent>& pose) {
  const std::vector<PoseComponent> rigid = rigidBodyPose();
  if (pose.size() != rigid.size()) return false;
  for (std::size_t k = 0; k < pose.size(); ++k) {
    if (pose[k].name != rigid[k].name || pose[k].unit != rigid[k].unit || pose[k].angular != rigid[k].angular ||
        pose[k].errorName() != rigid[k].errorName()) {
      return false;
    }
  }
  return true;
}

int RobotDescription::geometryIndex(const std::string& name) const {
  for (std::size_t i = 0; i < geometry.size(); ++i)
    if (geometry[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotDescription::setUncertainty(const std::string& prefix, double h) {
  if (!(h >= 0.0) || !std::isfinite(h)) {
    fail(type, "uncertainty of '" + prefix + "': expected a finite half-width >= 0, got " + number(h));
  }
  int n = 0;
  for (GeometryValue& g : geometry) {
    if (g.name.compare(0, prefix.size(), prefix) != 0) continue;
    g.lo = -h;
    g.hi = h;
    ++n;
  }
  return n;
}

void RobotDescription::validate() const {
  const std::size_t dof = pose.size();
  if (dof < 1 || dof > static_cast<std::size_t>(kMaxDof)) {
    fail(type, "expected 1 to " + std::to_string(kMaxDof) + " pose components, got " + std::to_string(dof));
  }
  if (joints.size() != dof) {
    fail(type, "expected as many joints as pose components (" + std::to_string(dof) + "), got " +
                   std::to_string(joints.size()));
  }
  if (sensor_error.size() != dof) {
    fail(type, "sensor_error: expected " + std::to_string(dof) + " values (one per joint), got " +
                   std::to_string(sensor_error.size()));
  }
  for (std::size_t j = 0; j < dof; ++j) {
    if (!(sensor_error[j] > 0.0) || !std::isfinite(sensor_error[j])) {
      fail(type,
           "sensor_error[" + std::to_string(j) + "]: expected a finite value > 0, got " + number(sensor_error[j]));
    }
  }
  std::set<std::string> names;
  for (const PoseComponent& c : pose)
    if (c.name.empty() || !names.insert("pose:" + c.name).second) fail(type, "pose component '" + c.name + "'");
  for (const Joint& j : joints)
    if (j.name.empty() || !names.insert("joint:" + j.name).second) fail(type, "joint name '" + j.name + "'");
  if (geometry.size() > static_cast<std::size_t>(kMaxGeometryValues)) {
    fail(type,
         "at most " + std::to_string(kMaxGeometryValues) + " geometry values, got " + std::to_string(geometry.size()));
  }
  int uncertain = 0;
  for (const GeometryValue& g : geometry) {
    if (g.name.empty() || !names.insert("geometry:" + g.name).second) {
      fail(type, "geometry value '" + g.name + "': expected a unique non-empty name");
    }
    if (!std::isfinite(g.nominal)) fail(type, g.name + ": expected a finite value, got " + number(g.nominal));
    if (!std::isfinite(g.lo) || !std::isfinite(g.hi) || g.lo > 0.0 || g.hi < 0.0) {
      fail(type, g.name + ": expected an uncertainty range [lo, hi] with lo <= 0 <= hi, got [" + number(g.lo) + ", " +
                     number(g.hi) + "]");
    }
    if (g.tool_point_coordinate < -1 || g.tool_point_coordinate > 2 ||
        (g.tool_point_coordinate >= 0 && !hasRigidBodyPose(pose))) {
      fail(type, g.name + ": a tool-point coordinate (0..2) of a model with the rigid-body pose (rigidBodyPose) only");
    }
    uncertain += g.uncertain() ? 1 : 0;
  }
  if (uncertain > kMaxGeometryParameters) {
    fail(type, "at most " + std::to_string(kMaxGeometryParameters) + " uncertain geometry values, got " +
                   std::to_string(uncertain));
  }
}

}  // namespace model
}  // namespace pkm_accuracy
