#include "pkm_accuracy/ros/RobotLoader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>
#include <Eigen/Geometry>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace ros_layer {
namespace {

constexpr int kLegs = 6;

/// Short human description of a parameter value, for "got ..." in error messages.
std::string describeValue(const XmlRpc::XmlRpcValue& v) {
  std::ostringstream os;
  os.precision(10);
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeInvalid:
      return "nothing (parameter not set)";
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return std::string("the boolean ") + (static_cast<const bool&>(v) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt:
      os << "the number " << static_cast<const int&>(v);
      return os.str();
    case XmlRpc::XmlRpcValue::TypeDouble:
      os << "the number " << static_cast<const double&>(v);
      return os.str();
    case XmlRpc::XmlRpcValue::TypeString:
      return "the string \"" + static_cast<const std::string&>(v) + "\"";  // (numeric strings are read as numbers)
    case XmlRpc::XmlRpcValue::TypeArray:
      os << "a list of " << v.size() << (v.size() == 1 ? " item" : " items");
      return os.str();
    case XmlRpc::XmlRpcValue::TypeStruct:
      return "a dictionary";
    default:
      return "a value of an unsupported type";
  }
}

std::string numStr(double x) {
  std::ostringstream os;
  os.precision(10);
  os << x;
  return os.str();
}

bool toNumber(const XmlRpc::XmlRpcValue& v, double& out) { return parameterNumber(v, out); }

/// Reads a finite number; `what` is the full name used in messages.
bool readFinite(const XmlRpc::XmlRpcValue& v, const std::string& what, const char* unit, double& out,
                std::string& error) {
  if (!toNumber(v, out)) {
    error = what + ": expected a number (" + unit + "), got " + describeValue(v);
    return false;
  }
  if (!std::isfinite(out)) {
    error = what + ": expected a finite number (" + unit + "), got " + numStr(out);
    return false;
  }
  return true;
}

bool readPoint(const XmlRpc::XmlRpcValue& v, const std::string& what, Eigen::Vector3d& out, std::string& error) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() != 3) {
    error = what + ": expected a point [x, y, z] of 3 numbers (m), got " + describeValue(v);
    return false;
  }
  for (int k = 0; k < 3; ++k) {
    if (!readFinite(v[k], what + "[" + std::to_string(k) + "]", "m", out[k], error)) return false;
  }
  return true;
}

/// One coordinate's bound: a half-width >= 0 (m) or offsets [lo, hi] (m) with lo <= hi.
bool readCoordinateBound(const XmlRpc::XmlRpcValue& v, const std::string& what, model::CoordinateBound& out,
                         std::string& error) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    double lo = 0.0, hi = 0.0;
    if (v.size() != 2) {
      error = what + ": expected a half-width >= 0 (m) or offsets [lo, hi] (m), got " + describeValue(v);
      return false;
    }
    if (!readFinite(v[0], what + "[0]", "m", lo, error) || !readFinite(v[1], what + "[1]", "m", hi, error))
      return false;
    if (!(lo <= hi)) {
      error = what + ": expected offsets [lo, hi] with lo <= hi (m), got [" + numStr(lo) + ", " + numStr(hi) + "]";
      return false;
    }
    out = model::CoordinateBound::offsets(lo, hi);
    return true;
  }
  double h = 0.0;
  if (!readFinite(v, what, "m", h, error)) return false;
  if (h < 0.0) {
    error = what + ": expected a half-width >= 0 (m), got " + numStr(h);
    return false;
  }
  out = model::CoordinateBound::halfwidth(h);
  return true;
}

/// The bounds of a point's 3 coordinates, [bx, by, bz], applied to the point and its half-widths (an asymmetric
/// range moves the coordinate to its centre). On failure the point and half-widths are unspecified.
bool readPointBounds(const XmlRpc::XmlRpcValue& v, const std::string& what, Eigen::Vector3d& point,
                     Eigen::Vector3d& halfwidth, std::string& error) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() != 3) {
    error =
        what + ": expected [bx, by, bz], each a half-width >= 0 (m) or offsets [lo, hi] (m), got " + describeValue(v);
    return false;
  }
  for (int k = 0; k < 3; ++k) {
    const std::string name = what + "[" + std::to_string(k) + "]";
    model::CoordinateBound b;
    if (!readCoordinateBound(v[k], name, b, error)) return false;
    try {
      model::applyCoordinateBound(b, point[k], halfwidth[k]);
    } catch (const InvalidGeometry& e) {
      error = name + ": " + e.what();
      return false;
    }
  }
  return true;
}

/// The bounds of the 6 anchors of one kind: a half-width (every coordinate) or 6 triples [bx, by, bz] (each a
/// half-width or offsets [lo, hi], m), applied to the anchors and their half-widths (changed only on success).
bool readAnchorBounds(const XmlRpc::XmlRpcValue& v, const std::string& what, std::vector<Eigen::Vector3d>& anchors,
                      std::vector<Eigen::Vector3d>& halfwidths, std::string& error) {
  double h = 0.0;
  std::vector<Eigen::Vector3d> points = anchors, w(kLegs, Eigen::Vector3d::Zero());
  if (points.size() != kLegs) {
    error = what + ": needs the 6 anchors it bounds, got " + std::to_string(points.size());
    return false;
  }
  if (toNumber(v, h)) {
    model::CoordinateBound b;
    if (!readCoordinateBound(v, what, b, error)) return false;
    w.assign(kLegs, Eigen::Vector3d::Constant(b.hi));
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeArray && v.size() == kLegs) {
    for (int i = 0; i < kLegs; ++i) {
      if (!readPointBounds(v[i], what + "[" + std::to_string(i) + "]", points[i], w[i], error)) return false;
    }
  } else {
    error = what +
            ": expected a half-width >= 0 (m) for every coordinate, or a list of 6 triples [bx, by, bz] (each a "
            "half-width or offsets [lo, hi], m), got " +
            describeValue(v);
    return false;
  }
  anchors = points;
  halfwidths = w;
  return true;
}

bool readPointList(const ros::NodeHandle& nh, const std::string& key, std::vector<Eigen::Vector3d>& out,
                   std::string& error) {
  const std::string name = nh.resolveName(key);
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) {
    error = name + ": expected a list of 6 points [x, y, z] (m), got nothing (parameter not set)";
    return false;
  }
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() != kLegs) {
    error = name + ": expected a list of 6 points [x, y, z] (m), got " + describeValue(v);
    return false;
  }
  out.assign(kLegs, Eigen::Vector3d::Zero());
  for (int i = 0; i < kLegs; ++i) {
    if (!readPoint(v[i], name + "[" + std::to_string(i) + "]", out[i], error)) return false;
  }
  return true;
}

bool readSensorError(const ros::NodeHandle& nh, std::vector<double>& out, std::string& error) {
  const std::string key = "sensor_error";
  const std::string name = nh.resolveName(key);
  const std::string expected = "expected 6 numbers > 0 (m, one per leg) or a single number > 0 (m, all legs)";
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) {
    error = name + ": " + expected + ", got nothing (parameter not set)";
    return false;
  }
  double x = 0.0;
  if (toNumber(v, x)) {
    out.assign(kLegs, x);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeArray && v.size() == kLegs) {
    out.assign(kLegs, 0.0);
    for (int i = 0; i < kLegs; ++i) {
      if (!readFinite(v[i], name + "[" + std::to_string(i) + "]", "m", out[i], error)) return false;
    }
  } else {
    error = name + ": " + expected + ", got " + describeValue(v);
    return false;
  }
  for (int i = 0; i < kLegs; ++i) {
    if (!(out[i] > 0.0) || !std::isfinite(out[i])) {
      const std::string which = toNumber(v, x) ? name : name + "[" + std::to_string(i) + "]";
      error = which + ": expected a finite number > 0 (m), got " + numStr(out[i]);
      return false;
    }
  }
  return true;
}

/// Runs GoughGeometry::validate() and turns its message ("base_anchors[2]: ...") into one naming the parameter.
bool validateGeometry(const ros::NodeHandle& nh, const model::GoughGeometry& g, std::string& error) {
  try {
    g.validate();
    return true;
  } catch (const InvalidArgument& e) {
    // The core names fields by their parameter names (base_anchors, platform_anchors, sensor_error, tool_point);
    // prefix the namespace so that the message names the resolved parameter.
    std::string ns = nh.getNamespace();
    if (ns.empty() || ns.back() != '/') ns += '/';
    error = ns + e.what();
    return false;
  } catch (const std::exception& e) {
    error = std::string("robot geometry: ") + e.what();
    return false;
  }
}

bool readOptionalString(const ros::NodeHandle& nh, const std::string& key, std::string& out, std::string& error) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) return true;  // keep the default
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(v).empty()) {
    error = nh.resolveName(key) + ": expected a non-empty string, got " + describeValue(v);
    return false;
  }
  out = static_cast<std::string>(v);
  return true;
}

/// Transform of a urdf::Pose (child frame in parent frame).
Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  double x = 0, y = 0, z = 0, w = 1;
  p.rotation.getQuaternion(x, y, z, w);
  t.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return t;
}

/// Origin of link `link_name` expressed in `ref_link`, composing the chain of fixed joints between them.
bool fixedChainOrigin(const urdf::Model& urdf, const std::string& ref_link, const std::string& link_name,
                      const std::string& label, Eigen::Vector3d& out, std::string& error) {
  urdf::LinkConstSharedPtr link = urdf.getLink(link_name);
  if (!link) {
    error = "URDF link '" + link_name + "' (" + label + "): not found in robot '" + urdf.getName() + "'";
    return false;
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();  // link frame in the frame of the current ancestor
  std::string current = link_name;
  for (std::size_t depth = 0; current != ref_link; ++depth) {
    urdf::LinkConstSharedPtr l = urdf.getLink(current);
    const urdf::JointConstSharedPtr joint = l ? l->parent_joint : nullptr;
    if (!joint || depth > 10000) {
      error = "URDF link '" + link_name + "' (" + label + "): expected a descendant of link '" + ref_link +
              "' through fixed joints, but its chain of parents ends at link '" + current + "'";
      return false;
    }
    if (joint->type != urdf::Joint::FIXED) {
      error = "URDF joint '" + joint->name + "' (between '" + joint->parent_link_name + "' and '" +
              joint->child_link_name + "', on the chain of " + label + " '" + link_name +
              "'): expected a fixed joint, got a movable one";
      return false;
    }
    t = toIsometry(joint->parent_to_joint_origin_transform) * t;
    current = joint->parent_link_name;
  }
  out = t.translation();
  return true;
}

// ---- named workspaces --------------------------------------------------------------------------------------------

bool isMap(const XmlRpc::XmlRpcValue& v) { return v.getType() == XmlRpc::XmlRpcValue::TypeStruct; }

/// The keys of a map that are not in `allowed` make the map invalid (a misspelt key would otherwise be ignored).
bool onlyKeys(const XmlRpc::XmlRpcValue& v, const std::string& what, const std::vector<std::string>& allowed,
              std::string& error) {
  for (auto it = v.begin(); it != v.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it->first) != allowed.end()) continue;
    std::string list;
    for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
    error = what + "/" + it->first + ": unknown key (expected one of " + list + ")";
    return false;
  }
  return true;
}

/// A member of a map, or an error naming it if it is missing.
bool member(const XmlRpc::XmlRpcValue& v, const std::string& what, const std::string& key, XmlRpc::XmlRpcValue& out,
            const std::string& expected, std::string& error) {
  if (!const_cast<XmlRpc::XmlRpcValue&>(v).hasMember(key)) {
    error = what + "/" + key + ": expected " + expected + ", got nothing (key not set)";
    return false;
  }
  out = const_cast<XmlRpc::XmlRpcValue&>(v)[key];
  return true;
}

/// A range [min, max] of 2 finite numbers with min <= max.
bool readRange(const XmlRpc::XmlRpcValue& v, const std::string& what, const char* unit, double& lo, double& hi,
               std::string& error) {
  const std::string expected = std::string("a range [min, max] of 2 numbers (") + unit + ") with min <= max";
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() != 2) {
    error = what + ": expected " + expected + ", got " + describeValue(v);
    return false;
  }
  if (!readFinite(v[0], what + "[0]", unit, lo, error) || !readFinite(v[1], what + "[1]", unit, hi, error)) {
    return false;
  }
  if (lo <= hi) return true;
  error = what + ": expected " + expected + ", got [" + numStr(lo) + ", " + numStr(hi) + "]";
  return false;
}

/// A list of `n` finite numbers (unit `unit`).
bool readNumbers(const XmlRpc::XmlRpcValue& v, const std::string& what, int n, const char* unit,
                 std::vector<double>& out, std::string& error) {
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || (n > 0 && v.size() != n)) {
    error = what + ": expected a list of " + (n > 0 ? std::to_string(n) + " numbers" : std::string("numbers")) + " (" +
            unit + "), got " + describeValue(v);
    return false;
  }
  out.assign(static_cast<std::size_t>(v.size()), 0.0);
  for (int i = 0; i < v.size(); ++i) {
    if (!readFinite(v[i], what + "[" + std::to_string(i) + "]", unit, out[static_cast<std::size_t>(i)], error)) {
      return false;
    }
  }
  return true;
}

bool readPositiveRadius(const XmlRpc::XmlRpcValue& region, const std::string& what, double& out, std::string& error) {
  XmlRpc::XmlRpcValue v;
  if (!member(region, what, "radius", v, "a number > 0 (m)", error)) return false;
  if (!readFinite(v, what + "/radius", "m", out, error)) return false;
  if (out > 0.0) return true;
  error = what + "/radius: expected a number > 0 (m), got " + numStr(out);
  return false;
}

/// The `region` of a named workspace (its x, y, z ranges already in r.box_min / box_max).
bool readNamedRegion(const XmlRpc::XmlRpcValue& v, const std::string& what, PositionRegion& r, std::string& error) {
  using T = PositionRegion::Type;
  XmlRpc::XmlRpcValue type;
  if (!isMap(v) || !const_cast<XmlRpc::XmlRpcValue&>(v).hasMember("type")) {
    error = what + ": expected a map with a key type (box, cylinder, sphere or polyhedron), got " + describeValue(v);
    return false;
  }
  type = const_cast<XmlRpc::XmlRpcValue&>(v)["type"];
  const std::string name = type.getType() == XmlRpc::XmlRpcValue::TypeString ? static_cast<std::string>(type) : "";
  XmlRpc::XmlRpcValue field;
  std::vector<double> numbers;
  if (name == "box") {
    r.type = T::Box;
    return onlyKeys(v, what, {"type"}, error);
  }
  if (name == "cylinder") {
    r.type = T::Cylinder;
    if (!onlyKeys(v, what, {"type", "centre", "radius", "z"}, error)) return false;
    if (!member(v, what, "centre", field, "a point [x, y] (m)", error) ||
        !readNumbers(field, what + "/centre", 2, "m", numbers, error) ||
        !readPositiveRadius(v, what, r.radius, error)) {
      return false;
    }
    r.center = Eigen::Vector3d(numbers[0], numbers[1], 0.0);
    r.z_min = r.box_min.z();
    r.z_max = r.box_max.z();
    if (const_cast<XmlRpc::XmlRpcValue&>(v).hasMember("z")) {
      return readRange(const_cast<XmlRpc::XmlRpcValue&>(v)["z"], what + "/z", "m", r.z_min, r.z_max, error);
    }
    return true;
  }
  if (name == "sphere") {
    r.type = T::Sphere;
    if (!onlyKeys(v, what, {"type", "centre", "radius"}, error)) return false;
    if (!member(v, what, "centre", field, "a point [x, y, z] (m)", error) ||
        !readNumbers(field, what + "/centre", 3, "m", numbers, error) ||
        !readPositiveRadius(v, what, r.radius, error)) {
      return false;
    }
    r.center = Eigen::Vector3d(numbers[0], numbers[1], numbers[2]);
    return true;
  }
  if (name == "polyhedron") {
    r.type = T::Polyhedron;
    if (!onlyKeys(v, what, {"type", "normals", "offsets"}, error)) return false;
    if (!member(v, what, "normals", field, "a list of normals [nx, ny, nz]", error)) return false;
    if (field.getType() != XmlRpc::XmlRpcValue::TypeArray || field.size() == 0) {
      error = what + "/normals: expected a non-empty list of normals [nx, ny, nz], got " + describeValue(field);
      return false;
    }
    for (int j = 0; j < field.size(); ++j) {
      const std::string at = what + "/normals[" + std::to_string(j) + "]";
      Eigen::Vector3d n;
      if (!readPoint(field[j], at, n, error)) return false;
      if (n.norm() == 0.0) {
        error = at + ": expected a non-zero vector, got [0, 0, 0]";
        return false;
      }
      r.halfspace_normals.push_back(n);
    }
    if (!member(v, what, "offsets", field, "a list of offsets (one per normal)", error) ||
        !readNumbers(field, what + "/offsets", static_cast<int>(r.halfspace_normals.size()), "m", r.halfspace_offsets,
                     error)) {
      return false;
    }
    return true;
  }
  error = what + "/type: expected box, cylinder, sphere or polyhedron, got " + describeValue(type);
  return false;
}

bool readNamedWorkspace(const XmlRpc::XmlRpcValue& v, const std::string& what, NamedWorkspace& out,
                        std::string& error) {
  static const char* const kKeys[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  if (!isMap(v)) {
    error = what + ": expected a map with keys x, y, z, roll, pitch, yaw (and optionally region, frame), got " +
            describeValue(v);
    return false;
  }
  if (!onlyKeys(v, what, {"x", "y", "z", "roll", "pitch", "yaw", "region", "frame"}, error)) return false;
  NamedWorkspace w;
  for (int k = 0; k < 6; ++k) {
    XmlRpc::XmlRpcValue range;
    const char* unit = k < 3 ? "m" : "rad";
    double lo = 0.0, hi = 0.0;
    if (!member(v, what, kKeys[k], range, std::string("a range [min, max] (") + unit + ")", error) ||
        !readRange(range, what + "/" + kKeys[k], unit, lo, hi, error)) {
      return false;
    }
    if (k < 3) {
      w.spec.position.box_min[k] = lo;
      w.spec.position.box_max[k] = hi;
    } else {
      w.spec.angle_min[k - 3] = lo;
      w.spec.angle_max[k - 3] = hi;
    }
  }
  XmlRpc::XmlRpcValue& m = const_cast<XmlRpc::XmlRpcValue&>(v);
  if (m.hasMember("region") && !readNamedRegion(m["region"], what + "/region", w.spec.position, error)) return false;
  w.has_frame = m.hasMember("frame");
  out = w;
  return true;
}

}  // namespace

bool numberFromString(const std::string& text, double& out) {
  // The whole text, nothing around it (no spaces, no unit), in the C locale's syntax of strtod: decimal or
  // hexadecimal, with an optional sign and exponent. "inf" and "nan" parse but are not finite.
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front())) ||
      std::isspace(static_cast<unsigned char>(text.back()))) {
    return false;
  }
  const char* begin = text.c_str();
  char* end = nullptr;
  const double x = std::strtod(begin, &end);  // (rounded to the nearest double, as a YAML float would be)
  if (end != begin + text.size() || !std::isfinite(x)) return false;
  out = x;
  return true;
}

bool parameterNumber(const XmlRpc::XmlRpcValue& v, double& out) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeDouble:
      out = static_cast<const double&>(v);
      return true;
    case XmlRpc::XmlRpcValue::TypeInt:
      out = static_cast<const int&>(v);
      return true;
    case XmlRpc::XmlRpcValue::TypeString:
      return numberFromString(static_cast<const std::string&>(v), out);
    default:
      return false;
  }
}

bool parameterInteger(const XmlRpc::XmlRpcValue& v, int& out) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    out = static_cast<const int&>(v);
    return true;
  }
  double x = 0.0;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString || !numberFromString(static_cast<const std::string&>(v), x))
    return false;
  if (x != std::floor(x) || std::fabs(x) > 2147483647.0) return false;
  out = static_cast<int>(x);
  return true;
}

bool readOptionalNumber(const ros::NodeHandle& nh, const std::string& key, double& out, std::string& error) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) return true;  // keep the default
  double x = 0.0;
  if (!parameterNumber(v, x)) {
    error = nh.resolveName(key) + ": expected a finite number (or a string holding one, e.g. \"2e-5\"), got " +
            describeValue(v);
    return false;
  }
  out = x;
  return true;
}

bool readOptionalInteger(const ros::NodeHandle& nh, const std::string& key, int& out, std::string& error) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(key, v)) return true;  // keep the default
  int x = 0;
  if (!parameterInteger(v, x)) {
    error =
        nh.resolveName(key) + ": expected an integer (or a string holding one, e.g. \"2\"), got " + describeValue(v);
    return false;
  }
  out = x;
  return true;
}

std::string formatAnchorName(const std::string& pattern, int index) {
  // The pattern is user input: only allow a single %d (or %i) and no other conversion, so snprintf is safe.
  int conversions = 0;
  for (std::size_t k = 0; k < pattern.size(); ++k) {
    if (pattern[k] != '%') continue;
    if (k + 1 < pattern.size() && pattern[k + 1] == '%') {
      ++k;
      continue;
    }
    if (k + 1 < pattern.size() && (pattern[k + 1] == 'd' || pattern[k + 1] == 'i')) {
      ++conversions;
      ++k;
      continue;
    }
    return "";
  }
  if (conversions != 1) return "";
  std::vector<char> buf(pattern.size() + 32);
  std::snprintf(buf.data(), buf.size(), pattern.c_str(), index);
  return std::string(buf.data());
}

bool loadGoughGeometry(const ros::NodeHandle& nh, model::GoughGeometry& out, std::string& error) {
  model::GoughGeometry g;
  if (!readPointList(nh, "base_anchors", g.base_anchors, error)) return false;
  if (!readPointList(nh, "platform_anchors", g.platform_anchors, error)) return false;
  if (!loadSensorParameters(nh, g, error)) return false;
  out = g;
  return true;
}

bool loadSensorParameters(const ros::NodeHandle& nh, model::GoughGeometry& inout, std::string& error) {
  model::GoughGeometry g = inout;
  if (!readSensorError(nh, g.sensor_error, error)) return false;

  XmlRpc::XmlRpcValue v;
  g.tool_point.setZero();
  if (nh.getParam("tool_point", v) && !readPoint(v, nh.resolveName("tool_point"), g.tool_point, error)) return false;

  double h = 0.0;
  if (nh.getParam("anchor_uncertainty", v)) {
    const std::string name = nh.resolveName("anchor_uncertainty");
    if (!readFinite(v, name, "m", h, error)) return false;
    if (h < 0.0) {
      error = name + ": expected a half-width >= 0 (m), got " + numStr(h);
      return false;
    }
  }
  try {
    g.setUniformAnchorUncertainty(h);
  } catch (const std::exception& e) {
    error = nh.resolveName("anchor_uncertainty") + ": " + e.what();
    return false;
  }
  // Per-anchor bounds replace anchor_uncertainty for their kind of anchor (offsets [lo, hi] move the anchor's
  // coordinate to the centre of its range).
  if (nh.getParam("base_anchor_uncertainty", v) &&
      !readAnchorBounds(v, nh.resolveName("base_anchor_uncertainty"), g.base_anchors, g.base_anchor_halfwidth, error)) {
    return false;
  }
  if (nh.getParam("platform_anchor_uncertainty", v) &&
      !readAnchorBounds(v, nh.resolveName("platform_anchor_uncertainty"), g.platform_anchors,
                        g.platform_anchor_halfwidth, error)) {
    return false;
  }
  g.tool_point_halfwidth.setZero();
  if (nh.getParam("tool_point_uncertainty", v) &&
      !readPointBounds(v, nh.resolveName("tool_point_uncertainty"), g.tool_point, g.tool_point_halfwidth, error)) {
    return false;
  }
  if (!validateGeometry(nh, g, error)) return false;
  inout = g;
  return true;
}

bool loadNamedWorkspaces(const ros::NodeHandle& nh, std::map<std::string, NamedWorkspace>& out, std::string& error) {
  std::map<std::string, NamedWorkspace> named;
  XmlRpc::XmlRpcValue v;
  if (nh.getParam("workspaces", v)) {
    const std::string what = nh.resolveName("workspaces");
    if (!isMap(v)) {
      error =
          what + ": expected a map of named workspaces (name: {x, y, z, roll, pitch, yaw}), got " + describeValue(v);
      return false;
    }
    for (auto it = v.begin(); it != v.end(); ++it) {
      NamedWorkspace w;
      if (!readNamedWorkspace(it->second, what + "/" + it->first, w, error)) return false;
      named[it->first] = w;
    }
  }
  out = named;
  return true;
}

bool loadRobotFrames(const ros::NodeHandle& nh, RobotFrames& out, std::string& error) {
  RobotFrames f;
  if (!readOptionalString(nh, "base_frame", f.base_frame, error)) return false;
  if (!readOptionalString(nh, "platform_frame", f.platform_frame, error)) return false;
  out = f;
  return true;
}

bool loadUrdfAnchorNames(const ros::NodeHandle& nh, UrdfAnchorNames& out, std::string& error) {
  UrdfAnchorNames n;
  if (!readOptionalString(nh, "base_frame", n.base_link, error)) return false;
  if (!readOptionalString(nh, "platform_frame", n.platform_link, error)) return false;
  if (!readOptionalString(nh, "base_anchor_pattern", n.base_anchor_pattern, error)) return false;
  if (!readOptionalString(nh, "platform_anchor_pattern", n.platform_anchor_pattern, error)) return false;
  for (const auto& [key, pattern] : {std::make_pair("base_anchor_pattern", n.base_anchor_pattern),
                                     std::make_pair("platform_anchor_pattern", n.platform_anchor_pattern)}) {
    if (formatAnchorName(pattern, 1).empty()) {
      error = nh.resolveName(key) + ": expected a printf pattern with exactly one %d, got \"" + pattern + "\"";
      return false;
    }
  }
  XmlRpc::XmlRpcValue v;
  if (nh.getParam("anchor_first_index", v)) {
    int first = -1;
    if (!parameterInteger(v, first) || (first != 0 && first != 1)) {
      error = nh.resolveName("anchor_first_index") + ": expected the integer 0 or 1, got " + describeValue(v);
      return false;
    }
    n.first_index = first;
  }
  out = n;
  return true;
}

bool loadGoughGeometryFromUrdf(const urdf::Model& urdf, const UrdfAnchorNames& names, model::GoughGeometry& out,
                               std::string& error) {
  if (!urdf.getLink(names.base_link)) {
    error = "URDF base link '" + names.base_link + "': not found in robot '" + urdf.getName() + "'";
    return false;
  }
  if (!urdf.getLink(names.platform_link)) {
    error = "URDF platform link '" + names.platform_link + "': not found in robot '" + urdf.getName() + "'";
    return false;
  }
  std::vector<Eigen::Vector3d> base(kLegs), platform(kLegs);
  for (int i = 0; i < kLegs; ++i) {
    const int index = names.first_index + i;
    const std::string a = formatAnchorName(names.base_anchor_pattern, index);
    const std::string b = formatAnchorName(names.platform_anchor_pattern, index);
    if (a.empty()) {
      error = "base anchor pattern: expected a printf pattern with exactly one %d, got \"" + names.base_anchor_pattern +
              "\"";
      return false;
    }
    if (b.empty()) {
      error = "platform anchor pattern: expected a printf pattern with exactly one %d, got \"" +
              names.platform_anchor_pattern + "\"";
      return false;
    }
    if (!fixedChainOrigin(urdf, names.base_link, a, "base anchor " + std::to_string(index), base[i], error)) {
      return false;
    }
    if (!fixedChainOrigin(urdf, names.platform_link, b, "platform anchor " + std::to_string(index), platform[i],
                          error)) {
      return false;
    }
  }
  // Check the anchors alone (distinct, finite) with a placeholder sensor error.
  model::GoughGeometry check;
  check.base_anchors = base;
  check.platform_anchors = platform;
  check.sensor_error.assign(kLegs, 1.0);
  try {
    check.validate();
  } catch (const std::exception& e) {
    error = std::string("URDF anchors (") + names.base_anchor_pattern + " / " + names.platform_anchor_pattern +
            ", numbered from " + std::to_string(names.first_index) + "): " + e.what();
    return false;
  }
  out.base_anchors = base;
  out.platform_anchors = platform;
  return true;
}

std::string toYaml(const XmlRpc::XmlRpcValue& value) {
  XmlRpc::XmlRpcValue v = value;  // (the accessors are not const)
  std::ostringstream os;
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeStruct: {
      os << "{";
      bool first = true;
      for (auto it = v.begin(); it != v.end(); ++it) {
        os << (first ? "" : ", ") << "\"" << it->first << "\": " << toYaml(it->second);
        first = false;
      }
      os << "}";
      break;
    }
    case XmlRpc::XmlRpcValue::TypeArray:
      os << "[";
      for (int i = 0; i < v.size(); ++i) os << (i ? ", " : "") << toYaml(v[i]);
      os << "]";
      break;
    case XmlRpc::XmlRpcValue::TypeDouble: {
      char text[64];
      std::snprintf(text, sizeof text, "%.17g", static_cast<double>(v));
      os << text;
      break;
    }
    case XmlRpc::XmlRpcValue::TypeInt:
      os << static_cast<int>(v);
      break;
    case XmlRpc::XmlRpcValue::TypeBoolean:
      os << (static_cast<bool>(v) ? "true" : "false");
      break;
    case XmlRpc::XmlRpcValue::TypeString: {
      os << "\"";
      for (char c : static_cast<std::string>(v)) os << (c == '"' || c == '\\' ? "\\" : "") << c;
      os << "\"";
      break;
    }
    default:
      os << "null";
  }
  return os.str();
}

bool loadModelFromParameters(const ros::NodeHandle& nh, const std::string& type, io::ModelFile& out,
                             std::string& error) {
  const model::ModelType* t = model::ModelRegistry::global().find(type);
  if (!t) {
    std::string list;
    for (const std::string& n : model::ModelRegistry::global().names()) list += (list.empty() ? "" : ", ") + n;
    error = nh.resolveName("robot_type") + ": unknown robot type \"" + type + "\" (registered: " + list +
            "; a plugin's types need ~plugins)";
    return false;
  }
  // The keys a robot file of this type has: every geometry group, sensor_error, uncertainty; and the workspaces of a
  // type whose pose is not the rigid-body pose (boxes of its own pose coordinates; a rigid-body robot's workspaces
  // have position regions: loadNamedWorkspaces()).
  std::set<std::string> keys = {"sensor_error", "uncertainty"};
  if (!model::hasRigidBodyPose(t->description.pose)) keys.insert("workspaces");
  for (const model::GeometryValue& g : t->description.geometry)
    keys.insert(g.name.substr(0, g.name.find_first_of("[.")));
  std::ostringstream yaml;
  yaml << "{\"type\": \"" << type << "\"";
  for (const std::string& key : keys) {
    XmlRpc::XmlRpcValue v;
    if (nh.getParam(key, v)) yaml << ", \"" << key << "\": " << toYaml(v);
  }
  yaml << "}";
  try {
    out = io::parseModelDocument(yaml.str(), "parameters in " + nh.getNamespace());
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  return true;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy
