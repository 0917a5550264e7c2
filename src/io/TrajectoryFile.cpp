#include "pkm_accuracy/io/TrajectoryFile.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>

#include "YamlReading.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PolynomialTrajectory.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/WaypointTrajectory.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

using yaml::checkKeys;
using yaml::fail;
using yaml::integer;
using yaml::number;
using yaml::numbers;
using yaml::range;
using yaml::show;
using yaml::vec3;

domain::PositionRegion region(const YAML::Node& n, const std::string& where) {
  if (!n.IsMap() || !n["type"]) fail(where, "expected a map with a 'type' key (box, cylinder, sphere, polyhedron)");
  const std::string type = n["type"].Scalar();
  try {
    if (type == "box" || type == "polyhedron") {
      checkKeys(n, where,
                type == "box" ? std::set<std::string>{"type", "x", "y", "z"}
                              : std::set<std::string>{"type", "x", "y", "z", "normals", "offsets"});
      const Interval x = range(n["x"], where + ".x"), y = range(n["y"], where + ".y"), z = range(n["z"], where + ".z");
      const Eigen::Vector3d lo(x.lower(), y.lower(), z.lower()), hi(x.upper(), y.upper(), z.upper());
      if (type == "box") return domain::PositionRegion::box(lo, hi);
      const YAML::Node normals = n["normals"];
      if (!normals || !normals.IsSequence()) fail(where + ".normals", "expected a list of [nx, ny, nz]");
      std::vector<Eigen::Vector3d> nv;
      for (std::size_t i = 0; i < normals.size(); ++i) {
        nv.push_back(vec3(normals[i], where + ".normals[" + std::to_string(i) + "]"));
      }
      return domain::PositionRegion::polyhedron(nv, numbers(n["offsets"], where + ".offsets"), lo, hi);
    }
    if (type == "cylinder") {
      checkKeys(n, where, {"type", "centre", "radius", "z"});
      const auto c = numbers(n["centre"], where + ".centre", 2, " [x, y]");
      const Interval z = range(n["z"], where + ".z");
      return domain::PositionRegion::cylinder(c[0], c[1], number(n["radius"], where + ".radius"), z.lower(), z.upper());
    }
    if (type == "sphere") {
      checkKeys(n, where, {"type", "centre", "radius"});
      return domain::PositionRegion::sphere(vec3(n["centre"], where + ".centre"),
                                            number(n["radius"], where + ".radius"));
    }
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidArgument& e) {
    fail(where, e.what());
  }
  fail(where + ".type", "expected box, cylinder, sphere or polyhedron, got '" + type + "'");
}

/// `interpolation` (waypoints only): slerp (default) or linear_rpy for the rigid-body pose, linear (default) for
/// other pose coordinates; linear is accepted for any type (for the rigid-body pose it is linear_rpy).
domain::WaypointTrajectory::Interpolation interpolation(const YAML::Node& root, const std::string& name,
                                                        const domain::PoseCoordinates& pose) {
  using Interpolation = domain::WaypointTrajectory::Interpolation;
  const YAML::Node i = root["interpolation"];
  if (!i) return pose.rigidBody() ? Interpolation::Slerp : Interpolation::Linear;
  const std::string s = i.IsScalar() ? i.Scalar() : "";
  const std::string where = name + ": interpolation";
  if (pose.rigidBody()) {
    if (s == "slerp") return Interpolation::Slerp;
    if (s == "linear_rpy" || s == "linear") return Interpolation::Linear;
    fail(where, "expected slerp, linear_rpy or linear, got " + show(i));
  }
  if (s == "linear") return Interpolation::Linear;
  if (s == "slerp" || s == "linear_rpy") {
    fail(where, s + " interpolates the orientation of the rigid-body pose (x, y, z, roll, pitch, yaw); " +
                    pose.describe() + ": expected linear");
  }
  fail(where, "expected linear (" + pose.type() + "), got " + show(i));
}

std::shared_ptr<domain::WaypointTrajectory> waypoints(const YAML::Node& root, const std::string& name,
                                                      const domain::PoseCoordinates& pose) {
  const std::string where = name + ": waypoints";
  const domain::WaypointTrajectory::Interpolation interp = interpolation(root, name, pose);
  const int n = pose.size();
  const std::string shape =
      " [t, " + pose.names() + "] (a time and the " + std::to_string(n) + " pose coordinates of " + pose.type() + ")";
  const YAML::Node rows = root["waypoints"];
  if (!rows.IsSequence()) fail(where, "expected a list of rows" + shape + ", got " + show(rows));
  if (rows.size() < 2) fail(where, "expected at least 2 waypoints, got " + std::to_string(rows.size()));
  std::vector<domain::WaypointTrajectory::Waypoint> w;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string row = where + "[" + std::to_string(i) + "]";
    const auto v = numbers(rows[i], row, static_cast<std::size_t>(n + 1), shape);
    if (i > 0 && !(v[0] > w.back().t)) {
      std::ostringstream os;
      os << "time " << v[0] << " s is not greater than the previous waypoint's time " << w.back().t
         << " s (times must increase strictly)";
      fail(row + "[0]", os.str());
    }
    domain::WaypointTrajectory::Waypoint p;
    p.t = v[0];
    for (int k = 0; k < n; ++k) p.pose[k] = v[k + 1];
    w.push_back(p);
  }
  try {
    return std::make_shared<domain::WaypointTrajectory>(std::move(w), interp, pose);
  } catch (const InvalidArgument& e) {
    throw ParseError(name + ": " + e.what());
  }
}

/// "one per pose coordinate: 3 for delta3 (x, y, z)", for messages.
std::string perCoordinate(const domain::PoseCoordinates& pose) {
  return "one per pose coordinate: " + std::to_string(pose.size()) + " for " + pose.type() + " (" + pose.names() + ")";
}

/// Fails on keys of a segment / variety map that are neither in `other` nor a pose coordinate.
void checkPoseKeys(const YAML::Node& map, const std::string& where, const std::string& other,
                   const domain::PoseCoordinates& pose) {
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (key == other || pose.indexOf(key) >= 0) continue;
    fail(where + "." + key, "unknown key (expected " + other + " and the polynomials, " + perCoordinate(pose) + ")");
  }
}

std::shared_ptr<domain::PolynomialTrajectory> polynomial(const YAML::Node& root, const std::string& name,
                                                         const domain::PoseCoordinates& pose) {
  const std::string where = name + ": polynomial_segments";
  const std::string shape =
      "{t: [start, end], " + pose.name(0) + ": [...], ..., " + pose.name(pose.size() - 1) + ": [...]}";
  const YAML::Node segs = root["polynomial_segments"];
  if (!segs.IsSequence() || segs.size() == 0)
    fail(where, "expected a non-empty list of segments " + shape + ", got " + show(segs));
  std::vector<domain::PolynomialTrajectory::Segment> out;
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const std::string row = where + "[" + std::to_string(k) + "]";
    const YAML::Node s = segs[k];
    if (!s.IsMap()) fail(row, "expected a map " + shape + ", got " + show(s));
    checkPoseKeys(s, row, "t", pose);
    domain::PolynomialTrajectory::Segment g;
    const auto t = numbers(s["t"], row + ".t", 2, " [start, end]");
    g.start = t[0];
    g.end = t[1];
    if (!(g.start < g.end)) {
      std::ostringstream os;
      os << "expected start < end, got [" << g.start << ", " << g.end << "]";
      fail(row + ".t", os.str());
    }
    if (k > 0 && g.start != out.back().end) {
      std::ostringstream os;
      os << "expected the segment to start where the previous one ends (" << out.back().end << " s), got " << g.start
         << " s";
      fail(row + ".t[0]", os.str());
    }
    for (int i = 0; i < pose.size(); ++i) {
      const std::string key = row + "." + pose.name(i);
      if (!s[pose.name(i)]) {
        fail(key, "missing (coefficients of tau^0, tau^1, ... with tau = t - start; a polynomial " +
                      perCoordinate(pose) + ")");
      }
      g.coefficients[i] = numbers(s[pose.name(i)], key);
      if (g.coefficients[i].empty()) fail(key, "expected at least one coefficient");
    }
    out.push_back(std::move(g));
  }
  try {
    return std::make_shared<domain::PolynomialTrajectory>(std::move(out), pose);
  } catch (const InvalidArgument& e) {
    throw ParseError(name + ": " + e.what());
  }
}

std::shared_ptr<domain::ParametricVariety> variety(const YAML::Node& root, const std::string& name,
                                                   const domain::PoseCoordinates& pose) {
  const std::string where = name + ": variety";
  const YAML::Node v = root["variety"];
  if (!v.IsMap()) {
    fail(where, "expected a map {parameters: m, " + pose.name(0) + ": [[c, e1, .., em], ...], ...}, got " + show(v));
  }
  checkPoseKeys(v, where, "parameters", pose);
  const int m = integer(v["parameters"], where + ".parameters", 1, kMaxDof);
  std::array<std::vector<domain::ParametricVariety::Monomial>, kMaxDof> coords;
  for (int i = 0; i < pose.size(); ++i) {
    const std::string key = where + "." + pose.name(i);
    const YAML::Node list = v[pose.name(i)];
    if (!list) continue;  // the constant 0
    if (!list.IsSequence()) fail(key, "expected a list of monomials [coefficient, exponents...], got " + show(list));
    for (std::size_t j = 0; j < list.size(); ++j) {
      const std::string row = key + "[" + std::to_string(j) + "]";
      const auto r =
          numbers(list[j], row, static_cast<std::size_t>(m + 1), " [coefficient, " + std::to_string(m) + " exponents]");
      domain::ParametricVariety::Monomial mono;
      mono.coefficient = r[0];
      for (int e = 0; e < m; ++e) {
        if (r[e + 1] != std::floor(r[e + 1]) || r[e + 1] < 0 || r[e + 1] > domain::ParametricVariety::kMaxExponent) {
          std::ostringstream os;
          os << "expected an integer exponent from 0 to " << domain::ParametricVariety::kMaxExponent << ", got "
             << r[e + 1];
          fail(row + "[" + std::to_string(e + 1) + "]", os.str());
        }
        mono.exponents[e] = static_cast<int>(r[e + 1]);
      }
      coords[i].push_back(mono);
    }
  }
  try {
    return std::make_shared<domain::ParametricVariety>(m, std::move(coords), pose);
  } catch (const InvalidArgument& e) {
    throw ParseError(name + ": " + e.what());
  }
}

/// `frame` (optional): the pose of the file's frame F in the robot's base frame, {translation: [x, y, z] (m), rpy:
/// [roll, pitch, yaw] (rad, R = Rz(yaw) Ry(pitch) Rx(roll))}, each 0 when missing. The file's domain (poses and
/// region in F) is then verified in the base frame through the core's TransformedDomain.
void placeInFrame(const YAML::Node& root, const std::string& name, const domain::PoseCoordinates& pose,
                  TrajectoryFile& f) {
  const YAML::Node n = root["frame"];
  if (!n) return;
  const std::string where = name + ": frame";
  if (!pose.rigidBody()) {
    fail(where, "a frame maps poses of the rigid-body pose (x, y, z, roll, pitch, yaw); " + pose.describe());
  }
  const domain::RigidTransform t = yaml::frame(n, where);
  try {
    const auto framed = std::make_shared<domain::TransformedDomain>(f.domain, t);
    f.domain = framed;
    f.description += ", in " + framed->frameDescription();
  } catch (const InvalidArgument& e) {
    fail(where, e.what());
  }
}

/// Sets the region (`reg`, if any) of a trajectory or variety; fails naming `region` if the pose has no x, y, z.
template <typename D>
void setRegion(D& d, const std::optional<domain::PositionRegion>& reg, const std::string& name) {
  if (!reg) return;
  try {
    d.setRegion(*reg);
  } catch (const InvalidArgument& e) {
    throw ParseError(name + ": " + e.what());
  }
}

TrajectoryFile build(const YAML::Node& root, const std::string& name, const domain::PoseCoordinates& pose) {
  if (!root.IsMap()) fail(name, "expected a YAML map at top level (waypoints, polynomial_segments or variety)");
  checkKeys(root, name + ":", {"interpolation", "waypoints", "polynomial_segments", "variety", "region", "frame"});
  const int kinds = (root["waypoints"] ? 1 : 0) + (root["polynomial_segments"] ? 1 : 0) + (root["variety"] ? 1 : 0);
  if (kinds != 1) {
    fail(name, std::string(kinds == 0 ? "expected one of" : "expected exactly one of") +
                   " the keys waypoints, polynomial_segments, variety");
  }
  if (root["interpolation"] && !root["waypoints"]) fail(name + ": interpolation", "only applies to waypoints");
  TrajectoryFile f;
  std::optional<domain::PositionRegion> reg;
  if (root["region"]) reg = region(root["region"], name + ": region");
  f.region = reg ? reg->typeName() : "none";
  if (root["variety"]) {
    auto v = variety(root, name, pose);
    setRegion(*v, reg, name);
    f.kind = TrajectoryFile::Kind::Variety;
    f.description = v->description();
    f.variety = v;
    f.domain = v;
    placeInFrame(root, name, pose, f);
    return f;
  }
  std::shared_ptr<domain::PiecewiseTrajectory> t;
  if (root["waypoints"]) {
    t = waypoints(root, name, pose);
    f.kind = TrajectoryFile::Kind::Waypoints;
  } else {
    t = polynomial(root, name, pose);
    f.kind = TrajectoryFile::Kind::Polynomial;
  }
  setRegion(*t, reg, name);
  f.description = t->description();
  f.trajectory = t;
  f.domain = t;
  placeInFrame(root, name, pose, f);
  return f;
}

}  // namespace

TrajectoryFile parseTrajectory(const std::string& yamlText, const std::string& name,
                               const domain::PoseCoordinates& pose) {
  YAML::Node root;
  try {
    root = YAML::Load(yamlText);
  } catch (const YAML::Exception& e) {
    throw ParseError(name + ": invalid YAML: " + e.what());
  }
  return build(root, name, pose);
}

TrajectoryFile loadTrajectoryFile(const std::string& path, const domain::PoseCoordinates& pose) {
  return build(yaml::loadFile(path), path, pose);
}

}  // namespace io
}  // namespace pkm_accuracy
