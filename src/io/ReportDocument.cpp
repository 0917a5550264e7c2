#include "ReportDocument.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "ReportValues.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

using Node = DocumentNode;

// ---- values ----------------------------------------------------------------------------------------------------
Node numbers(const DVec& v) {
  Node a = Node::array();
  for (int i = 0; i < v.size(); ++i) a.push(Node::number(v[i]));
  return a;
}

Node numbersOrNull(const DVec& v) { return v.size() > 0 ? numbers(v) : Node(); }

Node pair(double lo, double hi) { return Node::array().push(Node::number(lo)).push(Node::number(hi)); }

/// A box as [[lo, hi] ...] (null for an empty interval).
Node box(const IVec& b) {
  Node a = Node::array();
  for (int i = 0; i < b.size(); ++i) a.push(b[i].isEmpty() ? Node() : pair(b[i].lower(), b[i].upper()));
  return a;
}

Node strings(const std::vector<std::string>& v) {
  Node a = Node::array();
  for (const auto& s : v) a.push(Node::string(s));
  return a;
}

Node count(std::size_t n) { return Node::integer(static_cast<long long>(n)); }

/// Name of geometry parameter p ("p<index>" if the run info does not know it).
std::string parameterName(const RunInfo& info, std::size_t p) {
  return p < info.geometry_parameters.size() ? info.geometry_parameters[p] : "p" + std::to_string(p);
}

/// One geometry (a value per parameter) as {name: value}; null if empty.
Node geometryValues(const RunInfo& info, const std::vector<double>& g) {
  if (g.empty()) return Node();
  Node m = Node::object();
  for (std::size_t p = 0; p < g.size(); ++p) m.set(parameterName(info, p), Node::number(g[p]));
  return m;
}

/// Ranges of the geometry parameters as {name: [lo, hi]}; null if empty (every admissible geometry).
Node geometryRanges(const RunInfo& info, const std::vector<Interval>& g) {
  if (g.empty()) return Node();
  Node m = Node::object();
  for (std::size_t p = 0; p < g.size(); ++p) m.set(parameterName(info, p), pair(g[p].lower(), g[p].upper()));
  return m;
}

/// The name of error component k, null if the run info does not know it.
Node componentName(const RunInfo& info, int k) {
  return k >= 0 && k < static_cast<int>(info.components.size()) ? Node::string(info.components[k]) : Node();
}

// ---- sections, in the order of the schema ----------------------------------------------------------------------
/// What was run: the tool, the verdict, the robot, the domain and the options (tuning: the search's internal knobs,
/// verify::SearchTuning, so that a run can be reproduced).
void addRun(Node& d, const verify::VerifierResult& r, const verify::VerifierOptions& o, const RunInfo& info) {
  d.set("tool", Node::string(info.tool));
  d.set("version", Node::string(info.version));
  d.set("exit_code", info.exit_code >= 0 ? Node::integer(info.exit_code) : Node());
  d.set("verdict", Node::string(verify::toString(r.verdict)));
  // (As in the ROS messages: the reason of an UNDECIDED verdict, "" for the others.)
  d.set("reason", Node::string(r.verdict == verify::Verdict::Undecided ? verify::toString(r.reason) : ""));
  d.set("message", Node::string(r.message));
  d.set("mode", Node::string(modeName(o.mode)));
  d.set("robot", Node::string(info.robot));
  d.set("robot_type", Node::string(info.robot_type));
  d.set("workspace", info.trajectory.empty() ? Node::string(info.workspace) : Node());
  d.set("workspace_region", Node::string(info.workspace_region));
  d.set("workspace_box", box(info.workspace_box));
  d.set("variables", strings(info.variables));
  d.set("components", strings(info.components));
  d.set("units", strings(info.units));
  d.set("method", Node::string(o.method));
  d.set("thresholds", numbersOrNull(o.thresholds));
  d.set("alpha", o.mode == verify::Mode::MaxError ? Node::number(o.alpha) : Node());
  d.set("alpha_relative", o.mode == verify::Mode::MaxError ? Node::boolean(o.alpha_relative) : Node());
  d.set("anchor_uncertainty", Node::number(info.anchor_uncertainty));
  d.set("max_boxes", count(o.max_boxes));
  d.set("time_limit", Node::number(o.time_limit_s));
  d.set("min_width", numbersOrNull(o.min_width));
  d.set("geometry_splitting", Node::string(geometrySplittingName(o.geometry_splitting)));
  Node tuning = Node::object();
  tuning.set("bisection", Node::string(bisectionName(o.tuning.bisection)));
  tuning.set("stall_levels", Node::integer(o.tuning.stall_levels));
  tuning.set("faces", Node::boolean(o.tuning.faces));
  tuning.set("skip_hopeless", Node::boolean(o.tuning.skip_hopeless));
  tuning.set("decompose_geometry", Node::boolean(o.tuning.decompose_geometry));
  tuning.set("centre_check_period", Node::integer(o.tuning.centre_check_period));
  d.set("tuning", tuning);
  d.set("geometry_parameters", info.geometry_parameters.empty() ? Node() : strings(info.geometry_parameters));
  d.set("geometry_ranges", geometryRanges(info, info.geometry_ranges));
}

void addWitness(Node& d, const verify::VerifierResult& r, const RunInfo& info) {
  const bool witness = hasWitness(r);
  d.set("witness", witness ? numbers(witnessPose(r)) : Node());
  d.set("witness_variables", witness ? numbers(r.witness) : Node());
  d.set("witness_component", witness ? Node::integer(r.witness_component) : Node());
  d.set("witness_component_name", witness ? componentName(info, r.witness_component) : Node());
  d.set("witness_lower_bound", witness ? Node::number(r.witness_lower_bound) : Node());
  d.set("witness_error_lower", witness ? numbersOrNull(r.witness_error_lower) : Node());
}

/// A certified singular pose (either mode): the two points where det J^-1 has opposite certified signs; else null.
Node singular(const verify::VerifierResult& r, const RunInfo& info) {
  if (!r.singular) return Node();
  Node s = Node::object();
  s.set("from", numbers(r.singular_from));
  s.set("to", numbers(r.singular_to));
  s.set("from_pose", numbers(midpoints(r.singular_pose_from)));
  s.set("to_pose", numbers(midpoints(r.singular_pose_to)));
  const bool t = isTrajectory(info) && r.singular_from.size() > 0 && r.singular_to.size() > 0;
  s.set("from_t", t ? Node::number(info.timeOf(r.singular_from[0])) : Node());
  s.set("to_t", t ? Node::number(info.timeOf(r.singular_to[0])) : Node());
  s.set("geometry", geometryValues(info, r.singular_geometry));
  return s;
}

/// One uncertainty-sensitive pose.
Node sensitivePose(const verify::SensitivePose& p, const RunInfo& info) {
  Node e = Node::object();
  e.set("point", numbers(p.point));
  e.set("pose", p.pose.size() > 0 ? numbers(midpoints(p.pose)) : numbers(p.point));
  e.set("region", box(p.region));
  e.set("component", Node::integer(p.component));
  e.set("component_name", componentName(info, p.component));
  e.set("failing_lower", Node::number(p.failing_lower));
  e.set("failing_geometry", geometryValues(info, p.failing_geometry));
  const bool passing = !p.passing_geometry.empty();
  e.set("passing_geometry", geometryValues(info, p.passing_geometry));
  e.set("passing_upper", passing ? Node::number(p.passing_upper) : Node());
  e.set("passes_all", Node::boolean(passing && p.passes_all));
  const bool timed = isTrajectory(info) && p.point.size() > 0;
  e.set("t", timed ? Node::number(info.timeOf(p.point[0])) : Node());
  const bool timedRegion = timed && p.region.size() > 0 && !p.region[0].isEmpty();
  e.set("region_t", timedRegion ? pair(info.timeOf(p.region[0].lower()), info.timeOf(p.region[0].upper())) : Node());
  return e;
}

/// Uncertainty-sensitive poses (verify mode with uncertain geometry): their count and the first ones.
void addSensitive(Node& d, const verify::VerifierResult& r, const RunInfo& info) {
  d.set("sensitive_count", count(r.sensitive_count));
  Node sensitive = Node::array();
  for (std::size_t i = 0; i < r.sensitive.size() && i < info.max_listed_boxes; ++i) {
    sensitive.push(sensitivePose(r.sensitive[i], info));
  }
  d.set("sensitive", sensitive);
}

/// Max-error mode: the certified brackets and where their lower bounds are attained; else null.
Node maxError(const verify::VerifierResult& r, const verify::VerifierOptions& o, const RunInfo& info) {
  if (o.mode != verify::Mode::MaxError || r.max_lower.size() == 0) return Node();
  Node m = Node::object();
  m.set("lower", numbers(r.max_lower));
  m.set("upper", numbers(r.max_upper));
  m.set("converged", Node::boolean(r.converged));
  // The argmax poses in the base frame (as the witness), and the points of the domain's variables they are at.
  Node argmax = Node::array(), variables = Node::array();
  for (std::size_t k = 0; k < r.max_argmax.size(); ++k) {
    const bool pose = k < r.max_argmax_pose.size() && r.max_argmax_pose[k].size() > 0;
    argmax.push(pose ? numbers(midpoints(r.max_argmax_pose[k])) : Node());
    variables.push(numbersOrNull(r.max_argmax[k]));
  }
  m.set("argmax", argmax);
  m.set("argmax_variables", variables);
  if (isTrajectory(info)) {  // the time of every argmax (s)
    Node times = Node::array();
    for (const DVec& a : r.max_argmax) times.push(a.size() > 0 ? Node::number(info.timeOf(a[0])) : Node());
    m.set("argmax_t", times);
  }
  if (info.geometry_parameters.empty()) {
    m.set("argmax_geometry", Node());
  } else {
    Node geometry = Node::array();
    for (std::size_t k = 0; k < static_cast<std::size_t>(r.max_lower.size()); ++k) {
      geometry.push(k < r.max_argmax_geometry.size() ? geometryValues(info, r.max_argmax_geometry[k]) : Node());
    }
    m.set("argmax_geometry", geometry);
  }
  return m;
}

Node stats(const verify::Statistics& s, bool selfCheck) {
  Node n = Node::object();
  n.set("boxes", count(s.boxes));
  n.set("seconds", Node::number(s.seconds));
  n.set("max_depth", Node::integer(s.max_depth));
  n.set("safe_fraction", Node::number(s.safe_fraction));
  n.set("unsafe_fraction", Node::number(s.unsafe_fraction));
  n.set("undecided_fraction", Node::number(s.undecided_fraction));
  n.set("outside_fraction", Node::number(s.outside_fraction));
  n.set("threads", Node::integer(s.threads));
  n.set("geometry_switches", count(s.geometry_switches));
  n.set("geometry_splits", count(s.geometry_splits));
  n.set("face_switches", count(s.face_switches));
  n.set("face_boxes", count(s.face_boxes));
  n.set("unenclosed_boxes", count(s.unenclosed_boxes));
  n.set("self_check_points", selfCheck ? count(s.self_check_points) : Node());
  return n;
}

/// The undecided boxes: their count, and the first max_listed_boxes with their bounds and geometry ranges.
Node undecidedBoxes(const verify::VerifierResult& r, const RunInfo& info) {
  Node u = Node::object();
  const std::size_t listed = std::min(r.undecided_boxes.size(), info.max_listed_boxes);
  u.set("count", count(r.undecided_box_count));
  u.set("recorded", count(r.undecided_boxes.size()));
  u.set("listed", count(listed));
  Node boxes = Node::array(), upper = Node::array(), geometry = Node::array();
  for (std::size_t i = 0; i < listed; ++i) {
    boxes.push(box(r.undecided_boxes[i].box));
    upper.push(numbers(r.undecided_boxes[i].upper));
    geometry.push(geometryRanges(info, r.undecided_boxes[i].geometry));
  }
  u.set("boxes", boxes);
  u.set("upper", upper);
  u.set("geometry", info.geometry_parameters.empty() ? Node() : geometry);
  return u;
}

/// The domain's kind, its trajectory file, and the times of a trajectory.
void addDomain(Node& d, const verify::VerifierResult& r, const RunInfo& info) {
  d.set("domain", Node::string(info.domain));
  d.set("trajectory", info.trajectory.empty() ? Node() : Node::string(info.trajectory));
  d.set("trajectory_type", info.trajectory.empty() ? Node() : Node::string(info.trajectory_type));
  const bool traj = isTrajectory(info);
  d.set("time_span", traj ? pair(info.time_start, info.time_end) : Node());
  const bool timedWitness = traj && hasWitness(r) && r.witness.size() > 0;
  d.set("witness_t", timedWitness ? Node::number(info.timeOf(r.witness[0])) : Node());
  if (!traj) {
    d.set("undecided_t", Node());
    return;
  }
  Node times = Node::array();
  for (const auto& iv : undecidedTimes(r, info)) times.push(pair(iv.first, iv.second));
  d.set("undecided_t", times);
}

}  // namespace

DocumentNode reportDocument(const verify::VerifierResult& r, const verify::VerifierOptions& o, const RunInfo& info) {
  Node d = Node::object();
  addRun(d, r, o, info);
  addWitness(d, r, info);
  d.set("singular", singular(r, info));
  addSensitive(d, r, info);
  d.set("max_error", maxError(r, o, info));
  d.set("stats", stats(r.stats, o.self_check));
  d.set("undecided_boxes", undecidedBoxes(r, info));
  addDomain(d, r, info);
  return d;
}

}  // namespace io
}  // namespace pkm_accuracy
