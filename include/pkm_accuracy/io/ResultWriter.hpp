// Reports of a verifier run: JSON (hand-written, strict RFC 8259), YAML (block style, same keys and values) and a
// human summary. ROS-free; used by the command-line tool pkm_verify.
//
// Poses (witness, max_error.argmax, singular from_pose / to_pose, sensitive pose) are in the robot's base frame, also
// for a domain given in another frame (TransformedDomain): the midpoints of the verifier's certified pose enclosures.
// The points in the domain's own variables (witness_variables, max_error.argmax_variables, singular from / to,
// sensitive point, the boxes) stay in that frame.
//
// Numbers are printed with up to 17 significant digits: the shortest of %.15g, %.16g, %.17g that reads back to the
// same double (so 1e-4 prints as 1e-4, and nothing is lost). +-inf and NaN are never printed as bare tokens: JSON
// writes null, YAML writes .inf / -.inf / .nan (standard YAML floats).
//
// JSON / YAML keys (every key is always present; null where it does not apply):
//   tool, version, exit_code, verdict ("SAFE" | "UNSAFE" | "UNDECIDED"), reason ("precision_limit", ... for
//   UNDECIDED; "" otherwise), message, mode ("verify" | "max_error"), robot, robot_type (e.g. "gough", "delta3"),
//   workspace, workspace_region, workspace_box ([[lo, hi] x variables]), variables (names), components (["dx", "dy",
//   "dz", "drx", "dry", "drz"]), units (["m", "m", "m", "rad", ...]), method, thresholds ([6] or null), alpha,
//   alpha_relative, anchor_uncertainty (the largest half-width of an anchor coordinate, m), max_boxes, time_limit,
//   min_width, geometry_splitting ("auto" | "never" | "always"),
//   tuning (the search's internal knobs as run, verify::SearchTuning: {bisection ("smear" | "width" | "round-robin"),
//   stall_levels, faces, skip_hopeless, decompose_geometry, centre_check_period}), geometry_parameters (names of the
//   uncertain geometry parameters, e.g. "platform_anchors[3].z", in the order of the model's parameters; null without
//   geometric uncertainty), geometry_ranges ({parameter name: [lo, hi]}, the admissible values; null without),
//   witness (the pose [x, y, z, roll, pitch, yaw] when UNSAFE), witness_variables (in the
//   domain's variables), witness_component (index), witness_component_name, witness_lower_bound, witness_error_lower
//   ([6] or null), singular (a certified singular pose, else null: {from, to (domain variables; det J^-1 has
//   certified opposite signs there and the segment between them lies in the domain), from_pose, to_pose ([6]),
//   from_t, to_t (trajectories: s; else null), geometry (null: for every admissible geometry; else {parameter name:
//   value}, the nominal geometry, max_error mode)}), sensitive_count (uncertainty-sensitive poses found: some
//   admissible geometry exceeds a threshold there, none was shown to exceed for every geometry), sensitive (the first
//   ones, at most max_listed_boxes: [{point (domain variables), pose ([6], midpoints of its enclosure), region (the
//   search box [[lo, hi] x variables]), component, component_name, failing_lower, failing_geometry ({parameter name:
//   value}), passing_geometry ({name: value} or null), passing_upper (or null), passes_all, t and region_t
//   (trajectories: s; else null)}]), max_error: {lower: [6], upper: [6], converged, argmax: [the pose [x, y, z,
//               roll, pitch, yaw] attaining lower, per component, or null], argmax_variables: [the same points in the
//               domain's variables, or null] (trajectories: also argmax_t, the time of every argmax in s),
//               argmax_geometry ({parameter name: value} per component, the geometry attaining lower at argmax; null
//               entries where the bound holds for every geometry; null without geometric uncertainty)} in max_error
//               mode,
//   stats: {boxes, seconds, max_depth, safe_fraction, unsafe_fraction, undecided_fraction, outside_fraction,
//           threads, geometry_switches, geometry_splits, face_switches, face_boxes, unenclosed_boxes,
//           self_check_points (with the self-check: the points evaluated, each within its box's bounds; else null)},
//   undecided_boxes: {count, recorded, listed, boxes: [[[lo, hi] x variables] ...], upper: [[6] ...],
//                     geometry: [{parameter name: [lo, hi]} or null (every admissible geometry), one per listed box]
//                     or null without geometric uncertainty},
//   domain ("workspace" | "trajectory" | "variety"), trajectory (file path or null), trajectory_type (null for a
//   workspace), time_span ([t_0, t_N] in s, trajectories only), witness_t (the witness time in s when UNSAFE on a
//   trajectory), undecided_t (trajectories: the recorded undecided boxes as time intervals [[t_lo, t_hi] ...], sorted
//   and merged where they touch; [] if none).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"

namespace pkm_accuracy {
namespace io {

/// What the result refers to (the result itself does not know its robot, domain or options).
struct RunInfo {
  std::string tool = "pkm_verify";
  std::string version;                 ///< the package's version (pkm_accuracy::version())
  std::string robot;                   ///< robot file path
  std::string robot_type = "gough";    ///< the robot's type (model::ModelRegistry)
  std::string workspace;               ///< workspace name (from the robot file) or workspace file path
  std::string workspace_region;        ///< "box", "cylinder", "sphere", "polyhedron"
  IVec workspace_box;                  ///< initial box of the domain's variables
  std::vector<std::string> variables;  ///< names of the domain's variables
  /// The robot's pose coordinates with their units ("x [m]", ...; the poses of a trajectory, a variety, a witness).
  std::vector<std::string> pose_coordinates = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
  std::vector<std::string> components = {"dx", "dy", "dz", "drx", "dry", "drz"};  ///< error components
  std::vector<std::string> units = {"m", "m", "m", "rad", "rad", "rad"};          ///< unit of each component
  double anchor_uncertainty = 0.0;      ///< m: the largest half-width of an anchor coordinate
  double tool_point_uncertainty = 0.0;  ///< m: the largest half-width of a tool point coordinate
  /// True when every anchor coordinate has the half-width anchor_uncertainty and the tool point is exact.
  bool uniform_uncertainty = true;
  /// Names of the model's uncertain geometry parameters (model::RobotModel::geometryParameterName), in the order of
  /// every geometry vector of the result; empty without geometric uncertainty.
  std::vector<std::string> geometry_parameters;
  /// The range of every geometry parameter (model::RobotModel::geometryParameterRange: the admissible values, rounded
  /// outward), same order.
  std::vector<Interval> geometry_ranges;
  int exit_code = -1;                  ///< the process exit code, if known (-1: not written)
  std::size_t max_listed_boxes = 100;  ///< undecided boxes listed in the reports
  // Trajectories and motion varieties (pkm_verify --trajectory).
  std::string domain = "workspace";  ///< "workspace", "trajectory" or "variety"
  std::string trajectory;            ///< trajectory / variety file path (empty for a workspace)
  std::string trajectory_type;       ///< e.g. "waypoints (slerp), 12 waypoints"
  /// Trajectories: the time span; the box variable u maps to t = time_start + u (time_end - time_start).
  double time_start = 0.0, time_end = 0.0;
  /// t(u) for a trajectory (double; clamped to the time span).
  double timeOf(double u) const;
};

/// Trajectories: the undecided boxes of a result as time intervals, sorted and merged where they touch or overlap.
std::vector<std::pair<double, double>> undecidedTimes(const verify::VerifierResult& result, const RunInfo& info);

/// Name of a mode as on the command line and in the ROS messages: "verify", "max_error".
std::string modeName(verify::Mode mode);
/// Name of a bisection rule as in the reports' tuning.bisection: "smear", "width", "round-robin".
std::string bisectionName(verify::Bisection bisection);

/// Name of a geometry splitting mode as on the command line: "auto", "never", "always".
std::string geometrySplittingName(verify::GeometrySplitting splitting);

/// A double as JSON: up to 17 significant digits (exact round trip), "null" for inf / NaN.
std::string jsonNumber(double x);
/// A string as a JSON string literal (quotes and escapes included).
std::string jsonString(const std::string& s);

/// The whole report as one JSON object (ends with a newline).
std::string toJson(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info);
/// The same content as a YAML document (ends with a newline).
std::string toYaml(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info);

/// Human summary: verdict, message, witness, per-component bounds with units, statistics, undecided boxes.
void writeSummary(std::ostream& os, const verify::VerifierResult& result, const verify::VerifierOptions& options,
                  const RunInfo& info);

/// Writes `text` to `path` ("-": standard output). @throws InvalidArgument naming the path if it cannot be written.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace io
}  // namespace pkm_accuracy
