#include "pkm_accuracy/io/ModelFile.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <sstream>

#include "YamlReading.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PoseBox.hpp"
#include "pkm_accuracy/io/PlanarRobotFile.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

using yaml::fail;
using yaml::number;
using yaml::show;

/// A geometry value's name split as group[index].axis (index -1 / axis -1 where absent).
struct ValueName {
  std::string group;
  int index = -1;
  int axis = -1;
};

ValueName split(const std::string& name) {
  ValueName v;
  std::string rest = name;
  const std::size_t dot = rest.rfind('.');
  if (dot != std::string::npos && dot + 2 == rest.size() && rest[dot + 1] >= 'x' && rest[dot + 1] <= 'z') {
    v.axis = rest[dot + 1] - 'x';
    rest = rest.substr(0, dot);
  }
  const std::size_t open = rest.find('[');
  if (open != std::string::npos && rest.back() == ']') {
    v.index = std::stoi(rest.substr(open + 1, rest.size() - open - 2));
    rest = rest.substr(0, open);
  }
  v.group = rest;
  return v;
}

/// Element (index, axis) of a group node in one of the accepted shapes.
double element(const YAML::Node& g, const ValueName& v, int count, int axes, const std::string& where) {
  if (g.IsScalar()) return number(g, where);
  if (!g.IsSequence()) fail(where, "expected a number or a list, got " + show(g));
  if (v.index < 0) {  // an unindexed group with axes: [x, y(, z)]
    if (static_cast<int>(g.size()) != axes) {
      fail(where, "expected " + std::to_string(axes) + " numbers, got a list of " + std::to_string(g.size()));
    }
    return number(g[static_cast<std::size_t>(v.axis)], where + "[" + std::to_string(v.axis) + "]");
  }
  if (static_cast<int>(g.size()) != count) {
    fail(where, "expected " + std::to_string(count) + " entries (one per index), got " + std::to_string(g.size()));
  }
  const YAML::Node e = g[static_cast<std::size_t>(v.index)];
  const std::string at = where + "[" + std::to_string(v.index) + "]";
  if (v.axis < 0) return number(e, at);
  if (!e.IsSequence() || static_cast<int>(e.size()) != axes) {
    fail(at, "expected " + std::to_string(axes) + " numbers, got " + show(e));
  }
  return number(e[static_cast<std::size_t>(v.axis)], at + "[" + std::to_string(v.axis) + "]");
}

/// Per group: the number of indices and of axes its values have.
struct GroupShape {
  int count = 0, axes = 0;
};

std::map<std::string, GroupShape> shapes(const model::RobotDescription& d) {
  std::map<std::string, GroupShape> out;
  for (const model::GeometryValue& g : d.geometry) {
    const ValueName v = split(g.name);
    GroupShape& s = out[v.group];
    s.count = std::max(s.count, v.index + 1);
    s.axes = std::max(s.axes, v.axis + 1);
  }
  return out;
}

/// Sets the uncertainty of value `g` from a spec: h, or {lo, hi}.
void applySpec(const YAML::Node& spec, model::GeometryValue& g, const std::string& where) {
  if (spec.IsMap()) {
    yaml::checkKeys(spec, where, {"lo", "hi"});
    g.lo = number(spec["lo"], where + ".lo");
    g.hi = number(spec["hi"], where + ".hi");
    if (g.lo > 0.0 || g.hi < 0.0) fail(where, "expected lo <= 0 <= hi (offsets from the value)");
    return;
  }
  const double h = number(spec, where);
  if (h < 0.0) fail(where, "expected a half-width >= 0");
  g.lo = -h;
  g.hi = h;
}

void readUncertainty(const YAML::Node& u, model::RobotDescription& d, const std::string& where) {
  if (!u.IsMap()) fail(where, "expected a map {group or value name: half-width}, got " + show(u));
  const auto groups = shapes(d);
  for (const auto& kv : u) {
    const std::string key = kv.first.Scalar();
    const std::string at = where + "." + key;
    const int exact = d.geometryIndex(key);
    if (exact >= 0) {
      applySpec(kv.second, d.geometry[static_cast<std::size_t>(exact)], at);
      continue;
    }
    if (!groups.count(key)) fail(at, "not a geometry value or group of " + d.type);
    for (model::GeometryValue& g : d.geometry) {
      const ValueName v = split(g.name);
      if (v.group != key) continue;
      if (kv.second.IsSequence()) {
        if (v.index < 0 || kv.second.size() != static_cast<std::size_t>(groups.at(key).count)) {
          fail(at, "expected a half-width, {lo, hi}, or one half-width per index (" +
                       std::to_string(groups.at(key).count) + ")");
        }
        applySpec(kv.second[static_cast<std::size_t>(v.index)], g, at + "[" + std::to_string(v.index) + "]");
      } else {
        applySpec(kv.second, g, at);
      }
    }
  }
}

std::set<std::string> knownKeys(const model::RobotDescription& d) {
  std::set<std::string> keys = {"type", "sensor_error", "uncertainty", "workspaces"};
  for (const auto& kv : shapes(d)) keys.insert(kv.first);
  return keys;
}

model::RobotDescription describe(const YAML::Node& root, const model::ModelType& type, const std::string& where) {
  model::RobotDescription d = type.description;
  const auto groups = shapes(d);
  for (model::GeometryValue& g : d.geometry) {
    const ValueName v = split(g.name);
    const YAML::Node node = root[v.group];
    if (!node && g.has_default) continue;
    if (!node) {
      fail(where + " " + v.group,
           "required: the " + type.name + " geometry value(s) " + v.group + " (" + g.unit + "; docs/models.md)");
    }
    const GroupShape& s = groups.at(v.group);
    g.nominal = element(node, v, s.count, s.axes, where + " " + v.group);
  }
  const std::size_t dof = d.pose.size();
  const YAML::Node e = root["sensor_error"];
  if (!e) fail(where + " sensor_error", "required: one bound per joint, or one for every joint");
  if (e.IsScalar()) {
    d.sensor_error.assign(dof, number(e, where + " sensor_error"));
  } else {
    d.sensor_error = yaml::numbers(e, where + " sensor_error", dof, " (one per joint)");
  }
  if (const YAML::Node u = root["uncertainty"]) readUncertainty(u, d, where + " uncertainty");
  try {
    d.validate();
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidArgument& ex) {
    fail(where.substr(0, where.size() - 1), ex.what());
  }
  return d;
}

/// A box workspace of a model from a YAML map keyed by its pose component names.
std::shared_ptr<const domain::Domain> parsePoseBox(const YAML::Node& n, const model::RobotModel& model,
                                                   const model::RobotDescription& description,
                                                   const std::string& where) {
  std::set<std::string> allowed;
  for (const model::PoseComponent& c : description.pose) allowed.insert(c.name);
  if (!n || !n.IsMap()) fail(where, "expected a map with a range [min, max] or a value for each pose coordinate");
  yaml::checkKeys(n, where, allowed);
  IVec box(model.dof());
  std::vector<std::string> names;
  for (int k = 0; k < model.dof(); ++k) {
    const std::string& key = description.pose[static_cast<std::size_t>(k)].name;
    const YAML::Node r = n[key];
    const std::string at = where + "." + key;
    if (!r) fail(at, "required: [min, max] (" + description.pose[static_cast<std::size_t>(k)].unit + ") or a value");
    box[k] = r.IsScalar() ? Interval(number(r, at)) : yaml::range(r, at);
    names.push_back(key + " [" + description.pose[static_cast<std::size_t>(k)].unit + "]");
  }
  return std::make_shared<domain::PoseBox>(names, box);
}

ModelFile parse(const YAML::Node& root, const std::string& name, const model::ModelRegistry& registry) {
  if (!root.IsMap()) throw ParseError(name + ": expected a YAML map at top level");
  const YAML::Node t = root["type"];
  if (!t || !t.IsScalar()) throw ParseError(name + ": type: required (one of the registered robot types)");
  const model::ModelType* type = registry.find(t.Scalar());
  if (!type || type->name == "gough") {
    std::string list;
    for (const std::string& n : registry.names()) list += (list.empty() ? "" : ", ") + n;
    throw ParseError(name + ": type: " +
                     (type ? std::string("gough files are read by loadRobotFile")
                           : "unknown robot type '" + t.Scalar() + "' (registered: " + list + ")"));
  }
  ModelFile out;
  out.type = type->name;
  out.description = describe(root, *type, name + ":");
  out.model = type->make(out.description);
  const std::set<std::string> known = knownKeys(out.description);
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (!known.count(key)) out.unknown_keys.push_back(key);
  }
  if (const YAML::Node w = root["workspaces"]) {
    if (!w.IsMap()) fail(name + ": workspaces", "expected a map {name: workspace}, got " + show(w));
    for (const auto& kv : w) {
      const std::string key = kv.first.Scalar();
      out.workspaces[key] = parsePoseBox(kv.second, *out.model, out.description, name + ": workspaces." + key);
    }
  }
  return out;
}

bool isPlanar(const YAML::Node& root) {
  return root.IsMap() && root["type"] && root["type"].IsScalar() && root["type"].Scalar() == "planar3rpr";
}

/// planar3rpr documents keep their workspace forms (boxes and discs): the workspaces come from the planar reader.
ModelFile withPlanarWorkspaces(const YAML::Node& root, const std::string& name, const model::ModelRegistry& registry,
                               const PlanarRobotFile& planar) {
  YAML::Node copy = YAML::Clone(root);
  copy.remove("workspaces");
  ModelFile out = parse(copy, name, registry);
  for (const auto& kv : planar.workspaces)
    out.workspaces[kv.first] = std::make_shared<domain::PlanarWorkspace>(kv.second);
  return out;
}

}  // namespace

std::string robotFileType(const std::string& path) {
  const YAML::Node root = yaml::loadFile(path);
  if (!root.IsMap()) throw ParseError(path + ": expected a YAML map at top level");
  const YAML::Node t = root["type"];
  if (!t) return "gough";
  if (!t.IsScalar()) throw ParseError(path + ": type: expected a robot type name, got " + show(t));
  return t.Scalar();
}

ModelFile parseModelDocument(const std::string& yamlText, const std::string& name,
                             const model::ModelRegistry& registry) {
  YAML::Node root;
  try {
    root = YAML::Load(yamlText);
  } catch (const YAML::Exception& e) {
    throw ParseError(name + ": invalid YAML: " + e.what());
  }
  if (isPlanar(root)) return withPlanarWorkspaces(root, name, registry, parsePlanarRobotDocument(yamlText, name));
  return parse(root, name, registry);
}

std::shared_ptr<const domain::Domain> loadPoseBoxFile(const std::string& path, const model::RobotModel& model,
                                                      const model::RobotDescription& description) {
  return parsePoseBox(yaml::loadFile(path), model, description, path + ":");
}

ModelFile loadModelFile(const std::string& path, const model::ModelRegistry& registry) {
  const YAML::Node root = yaml::loadFile(path);
  if (isPlanar(root)) return withPlanarWorkspaces(root, path, registry, loadPlanarRobotFile(path));
  return parse(root, path, registry);
}

}  // namespace io
}  // namespace pkm_accuracy
