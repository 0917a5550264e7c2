// Reading robot files of any registered type (model::ModelRegistry) with yaml-cpp. ROS-free.
//
// A file names its type (`type: delta3`; without it the file is a `gough` file, read by loadRobotFile) and gives the
// type's geometry values (RobotDescription::geometry, docs/models.md lists them per type) as top-level keys, one per
// group: a value "g[i].x" comes from key g, "g[i]" from g, "g.x" from g, "g" from g:
//   g: v                        # every element of the group (scalar)
//   g: [v0, v1, ...]            # one per index i
//   g: [[x, y, z], ...]         # one per index i and axis (x, y or x, y, z as the type's values have them)
//   g: [x, y, z]                # an unindexed group with axes (e.g. tool_point)
//   sensor_error: e or [e0, ...]            # one per joint, in the joint's unit (m or rad)
//   uncertainty:                            # optional: per group or per value name ("forearm_length[2]"),
//     g: h | [h0, h1, ...] | {lo: l, hi: h}  # a half-width h >= 0 for every element, one per index, or offsets
//   workspaces:                             # optional: boxes of the pose coordinates, keyed by their names
//     name: {x: [min, max], y: [min, max], z: v, ...}   # every coordinate: a range or a fixed value
// planar3rpr files keep their workspace forms (PlanarRobotFile.hpp: boxes and discs).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/core/model/RobotDescription.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace io {

struct ModelFile {
  std::string type;
  model::RobotDescription description;  ///< the file's values, validated
  std::shared_ptr<const model::RobotModel> model;
  std::map<std::string, std::shared_ptr<const domain::Domain>> workspaces;
  std::vector<std::string> unknown_keys;  ///< top-level keys the type does not use (warnings, not errors)
};

/// The `type` of a robot file: its `type` key, or "gough" without one.
/// @throws ParseError if the file cannot be read or `type` is not a string.
std::string robotFileType(const std::string& path);

/// Reads a robot file of a registered type other than gough (use loadRobotFile for gough files).
/// @throws ParseError naming the file and key (missing value, wrong shape, unknown type: the message lists the
///         registered ones) or InvalidGeometry / InvalidArgument for values that parse but are invalid.
ModelFile loadModelFile(const std::string& path, const model::ModelRegistry& registry = model::ModelRegistry::global());

/// The same from a YAML document held in a string (e.g. the node's parameters); `name` stands for the file name in
/// messages.
ModelFile parseModelDocument(const std::string& yamlText, const std::string& name,
                             const model::ModelRegistry& registry = model::ModelRegistry::global());

/// A workspace file for a model of any type: a YAML map keyed by the model's pose coordinate names, each a range
/// [min, max] or a fixed value.
/// @throws ParseError naming the file and key.
std::shared_ptr<const domain::Domain> loadPoseBoxFile(const std::string& path, const model::RobotModel& model,
                                                      const model::RobotDescription& description);

}  // namespace io
}  // namespace pkm_accuracy
