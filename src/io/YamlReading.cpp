#include "YamlReading.hpp"

#include <cmath>
#include <sstream>

namespace pkm_accuracy {
namespace io {
namespace yaml {

void fail(const std::string& where, const std::string& what) { throw ParseError(where + ": " + what); }

std::string show(const YAML::Node& n) {
  if (!n) return "nothing";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  return "nothing";
}

double number(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsScalar()) fail(where, "expected a number, got " + show(n));
  double v;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(where, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(where, "expected a finite number, got '" + n.Scalar() + "'");
  return v;
}

std::vector<double> numbers(const YAML::Node& n, const std::string& where, std::size_t expected,
                            const std::string& shape) {
  if (!n || !n.IsSequence()) {
    fail(where, "expected a list of " + (expected ? std::to_string(expected) + " numbers" : std::string("numbers")) +
                    shape + ", got " + show(n));
  }
  if (expected > 0 && n.size() != expected) {
    fail(where, "expected " + std::to_string(expected) + " numbers" + shape + ", got " + std::to_string(n.size()));
  }
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

int integer(const YAML::Node& n, const std::string& where, int lo, int hi) {
  const double v = number(n, where);
  if (v != std::floor(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << "expected an integer from " << lo << " to " << hi << ", got '" << n.Scalar() << "'";
    fail(where, os.str());
  }
  return static_cast<int>(v);
}

void checkKeys(const YAML::Node& map, const std::string& where, const std::set<std::string>& allowed) {
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(!where.empty() && where.back() == ':' ? where + " " + key : where + "." + key,
           "unknown key (expected one of " + list + ")");
    }
  }
}

Eigen::Vector2d vec2(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 2, " [x, y]");
  return Eigen::Vector2d(v[0], v[1]);
}

Eigen::Vector3d vec3(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 3, " [x, y, z]");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

domain::RigidTransform frame(const YAML::Node& n, const std::string& where) {
  if (!n.IsMap()) fail(where, "expected a map {translation: [x, y, z], rpy: [roll, pitch, yaw]}, got " + show(n));
  checkKeys(n, where, {"translation", "rpy"});
  const Eigen::Vector3d t = n["translation"] ? vec3(n["translation"], where + ".translation") : Eigen::Vector3d::Zero();
  const Eigen::Vector3d rpy = n["rpy"] ? vec3(n["rpy"], where + ".rpy") : Eigen::Vector3d::Zero();
  return domain::RigidTransform::fromTranslationRpy(t, rpy[0], rpy[1], rpy[2]);
}

std::vector<Eigen::Vector2d> points2(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsSequence()) fail(where, "expected a list of [x, y] points, got " + show(n));
  std::vector<Eigen::Vector2d> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(vec2(n[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

std::vector<Eigen::Vector3d> points3(const YAML::Node& n, const std::string& where) {
  if (!n || !n.IsSequence()) fail(where, "expected a list of [x, y, z] points, got " + show(n));
  std::vector<Eigen::Vector3d> v;
  for (std::size_t i = 0; i < n.size(); ++i) v.push_back(vec3(n[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

Interval range(const YAML::Node& n, const std::string& where) {
  const auto v = numbers(n, where, 2, " [min, max]");
  if (!(v[0] <= v[1])) {
    std::ostringstream os;
    os << "expected a finite range [min, max] with min <= max, got [" << v[0] << ", " << v[1] << "]";
    fail(where, os.str());
  }
  return Interval(v[0], v[1]);
}

YAML::Node loadFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw ParseError(path + ": cannot open file");
  } catch (const YAML::Exception& e) {
    throw ParseError(path + ": invalid YAML: " + e.what());
  }
}

}  // namespace yaml
}  // namespace io
}  // namespace pkm_accuracy
