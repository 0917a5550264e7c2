// The human summary of a run (io::writeSummary): one section per aspect of the result, each written only where it
// applies.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>

#include "ReportValues.hpp"
#include "pkm_accuracy/io/ResultWriter.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

// ---- formatting ----------------------------------------------------------------------------------------------------
std::string num(double x, int digits = 6) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

std::string percent(double fraction) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g%%", 100.0 * fraction);
  return buf;
}

/// "s" unless n is 1 (also "es" for the words that take it).
std::string plural(std::size_t n, const char* ending = "s") { return n == 1 ? "" : ending; }

std::string unitOf(const RunInfo& info, int k) {
  return k >= 0 && k < static_cast<int>(info.units.size()) ? info.units[k] : "";
}

std::string componentOf(const RunInfo& info, int k) {
  return k >= 0 && k < static_cast<int>(info.components.size()) ? info.components[k] : "c" + std::to_string(k);
}

/// "x [m]" -> ("x", "m").
std::pair<std::string, std::string> splitName(const std::string& name) {
  const auto open = name.find(" [");
  if (open == std::string::npos || name.back() != ']') return {name, ""};
  return {name.substr(0, open), name.substr(open + 2, name.size() - open - 3)};
}

/// The name and unit of variable i of the run info ("t<i>" if it does not know it).
std::pair<std::string, std::string> variableOf(const RunInfo& info, int i) {
  return splitName(i < static_cast<int>(info.variables.size()) ? info.variables[i] : "t" + std::to_string(i));
}

/// "x = 0.1 m, y = ..." for a point of the run info's variables.
std::string variables(const RunInfo& info, const DVec& t) {
  std::ostringstream os;
  for (int i = 0; i < t.size(); ++i) {
    const auto nu = variableOf(info, i);
    os << (i > 0 ? ", " : "") << nu.first << " = " << num(t[i], 9) << (nu.second.empty() ? "" : " " + nu.second);
  }
  return os.str();
}

/// "x [lo, hi] m, y ..." for a box of the run info's variables.
std::string boxText(const RunInfo& info, const IVec& b) {
  std::ostringstream os;
  for (int i = 0; i < b.size(); ++i) {
    const auto nu = variableOf(info, i);
    os << (i > 0 ? ", " : "") << nu.first << " [" << num(b[i].lower()) << ", " << num(b[i].upper()) << "]"
       << (nu.second.empty() ? "" : " " + nu.second);
  }
  return os.str();
}

/// The run info with the robot's pose coordinates as variables (for the poses of a trajectory or variety).
RunInfo poseNames(const RunInfo& info) {
  RunInfo names = info;
  names.variables = info.pose_coordinates;
  return names;
}

std::string pad(const std::string& s, std::size_t w) {
  return s.size() >= w ? s + " " : s + std::string(w - s.size(), ' ');
}

/// " > threshold T unit" if component k has a threshold, else "".
std::string thresholdText(const verify::VerifierOptions& o, const RunInfo& info, int k) {
  if (k < 0 || k >= o.thresholds.size()) return "";
  return " > threshold " + num(o.thresholds[k]) + " " + unitOf(info, k);
}

// ---- sections ------------------------------------------------------------------------------------------------------
/// The robot line: its file and its geometric uncertainty.
void writeRobot(std::ostream& os, const RunInfo& info) {
  const std::size_t parameters = info.geometry_parameters.size();
  os << "robot:     " << info.robot;
  if (info.robot_type != "gough") {
    os << " (" << info.robot_type << "; " << parameters << " uncertain geometry value" << plural(parameters) << ")\n";
  } else if (info.uniform_uncertainty) {
    os << " (anchor uncertainty " << num(info.anchor_uncertainty) << " m)\n";
  } else {
    os << " (uncertainty per coordinate: anchors up to " << num(info.anchor_uncertainty) << " m, tool point up to "
       << num(info.tool_point_uncertainty) << " m; " << parameters << " uncertain coordinate" << plural(parameters)
       << ")\n";
  }
}

/// Verdict, message, robot, domain and method.
void writeHeader(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                 const RunInfo& info) {
  os << "verdict:   " << verify::toString(r.verdict);
  if (r.verdict == verify::Verdict::Undecided) os << " (" << verify::toString(r.reason) << ")";
  os << "\nmessage:   " << r.message << "\n";
  writeRobot(os, info);
  if (info.trajectory.empty()) {
    os << "workspace: " << info.workspace << " (" << info.workspace_region << "): " << boxText(info, info.workspace_box)
       << "\n";
  } else {
    os << pad(info.domain + ":", 11) << info.trajectory << " (" << info.trajectory_type << ")";
    if (isTrajectory(info)) os << ", t in [" << num(info.time_start) << ", " << num(info.time_end) << "] s";
    if (info.workspace_region != "none") os << ", region " << info.workspace_region;
    os << "\n";
  }
  os << "method:    " << o.method << ", mode " << modeName(o.mode);
  if (o.mode == verify::Mode::MaxError) os << ", alpha " << num(o.alpha) << (o.alpha_relative ? " (relative)" : "");
  os << "\n";
}

void writeWitness(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                  const RunInfo& info) {
  if (!hasWitness(r)) return;
  const int k = r.witness_component;
  if (info.trajectory.empty()) {
    os << "witness:   " << variables(info, witnessPose(r)) << "\n";
  } else {
    os << "witness:   ";
    if (isTrajectory(info)) os << "t = " << num(info.timeOf(r.witness[0]), 9) << " s (";
    os << variables(info, r.witness) << (isTrajectory(info) ? ")" : "") << "\n";
    os << "           pose " << variables(poseNames(info), witnessPose(r)) << "\n";
  }
  os << "           " << componentOf(info, k) << " worst error >= " << num(r.witness_lower_bound, 9) << " "
     << unitOf(info, k) << thresholdText(o, info, k) << " (certified)\n";
}

void writeSingular(std::ostream& os, const verify::VerifierResult& r, const RunInfo& info) {
  if (!r.singular) return;
  os << "singular:  det J^-1 has certified opposite signs, for "
     << (r.singular_geometry.empty() ? "every admissible geometry" : "the nominal geometry")
     << ", at the two ends of a segment inside the domain: J^-1 is singular between them\n";
  const RunInfo names = poseNames(info);
  for (const auto& end :
       {std::make_pair(&r.singular_from, &r.singular_pose_from), std::make_pair(&r.singular_to, &r.singular_pose_to)}) {
    os << "           ";
    if (isTrajectory(info) && end.first->size() > 0) os << "t = " << num(info.timeOf((*end.first)[0]), 9) << " s: ";
    os << variables(names, midpoints(*end.second)) << "\n";
  }
}

/// The first uncertainty-sensitive pose: where, how far above its threshold, and for which geometries.
void writeSensitive(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                    const RunInfo& info) {
  if (r.sensitive.empty()) return;
  const verify::SensitivePose& p = r.sensitive.front();
  const int k = p.component;
  os << "sensitive: " << r.sensitive_count << " certified pose" << plural(r.sensitive_count)
     << " where the answer depends on the geometric uncertainty, e.g.\n";
  const DVec pose = p.pose.size() > 0 ? midpoints(p.pose) : p.point;
  if (info.trajectory.empty()) {
    os << "           pose " << variables(info, pose) << "\n";
  } else {
    os << "           ";
    if (isTrajectory(info) && p.point.size() > 0) os << "t = " << num(info.timeOf(p.point[0]), 9) << " s, ";
    os << "pose " << variables(poseNames(info), pose) << "\n";
  }
  os << "           " << componentOf(info, k) << " worst error >= " << num(p.failing_lower, 9) << " " << unitOf(info, k)
     << thresholdText(o, info, k) << " for an admissible geometry (certified)\n";
  if (!p.passing_geometry.empty()) {
    os << "           another admissible geometry keeps it <= " << num(p.passing_upper, 9) << " " << unitOf(info, k)
       << " there (certified" << (p.passes_all ? "; every component within its threshold" : "") << ")\n";
  }
  os << "           in the region " << boxText(info, p.region);
  if (isTrajectory(info) && p.region.size() > 0 && !p.region[0].isEmpty()) {
    os << " (t in [" << num(info.timeOf(p.region[0].lower())) << ", " << num(info.timeOf(p.region[0].upper()))
       << "] s)";
  }
  os << "\n           (no pose was found that exceeds for every admissible geometry; the geometries are in the "
        "--json / --yaml reports)\n";
}

/// The table of the components: max-error brackets, thresholds, the witness's lower bounds (whichever apply).
void writeComponents(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                     const RunInfo& info) {
  const int n = static_cast<int>(
      std::max<Eigen::Index>({o.thresholds.size(), r.max_lower.size(), r.witness_error_lower.size(), Eigen::Index(0)}));
  if (n == 0) return;
  const bool maxError = r.max_lower.size() == n;
  const bool thresholds = o.thresholds.size() == n;
  const bool atWitness = !maxError && r.witness_error_lower.size() == n;
  os << "\n  " << pad("component", 11) << pad("unit", 6);
  if (maxError) os << pad("max >= lower", 18) << pad("max <= upper", 18) << pad("gap", 10);
  if (thresholds) os << pad("threshold", 14);
  if (atWitness) os << "at witness >=";
  os << "\n";
  for (int k = 0; k < n; ++k) {
    os << "  " << pad(componentOf(info, k), 11) << pad(unitOf(info, k), 6);
    if (maxError) {
      const double gap = r.max_upper[k] - r.max_lower[k];
      os << pad(num(r.max_lower[k], 10), 18) << pad(num(r.max_upper[k], 10), 18)
         << pad(r.max_lower[k] > 0 && std::isfinite(gap) ? percent(gap / r.max_lower[k]) : num(gap, 3), 10);
    }
    if (thresholds) os << pad(num(o.thresholds[k]), 14);
    if (atWitness) os << num(r.witness_error_lower[k], 10);
    os << "\n";
  }
  if (maxError) {
    os << "  (max: the largest worst-case error over the " << info.domain << "; certified bracket [lower, upper])\n";
  }
  os << "\n";
}

/// Boxes, time, threads, the self-check and the geometry's search paths.
void writeStats(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                const RunInfo& info) {
  const auto& s = r.stats;
  os << "stats:     " << s.boxes << (s.boxes == 1 ? " box in " : " boxes in ") << num(s.seconds, 3) << " s on "
     << s.threads << " thread" << plural(static_cast<std::size_t>(s.threads)) << ", max depth " << s.max_depth;
  if (s.unenclosed_boxes > 0) os << "; " << s.unenclosed_boxes << " split without an enclosure";
  os << "\n";
  if (o.self_check) {
    os << "self-check: " << s.self_check_points << " point" << plural(s.self_check_points)
       << " of the boxes evaluated in double, each within its box's certified bounds\n";
  }
  const std::size_t parameters = info.geometry_parameters.size();
  if (parameters == 0) return;
  os << "geometry:  " << parameters << " uncertain parameter" << plural(parameters) << ", splitting "
     << geometrySplittingName(o.geometry_splitting) << ": " << s.geometry_switches << " box"
     << plural(s.geometry_switches, "es") << " switched to bisecting the geometry, " << s.geometry_splits
     << " geometry split" << plural(s.geometry_splits) << "; " << s.face_switches << " path" << plural(s.face_switches)
     << " switched to the faces (" << s.face_boxes << " box" << plural(s.face_boxes, "es") << ")\n";
}

/// The volume fractions, and the boxes left undecided (or not examined after a stop at the first witness).
void writeVolumeAndUndecided(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                             const RunInfo& info) {
  const auto& s = r.stats;
  const bool sensitiveStop =
      r.verdict == verify::Verdict::Undecided && r.reason == verify::UndecidedReason::UncertaintySensitive;
  const bool stoppedAtWitness = (r.verdict == verify::Verdict::Unsafe || sensitiveStop) &&
                                o.mode == verify::Mode::Verify && o.stop_at_first_witness;
  os << "volume:    " << percent(s.safe_fraction) << (o.mode == verify::Mode::MaxError ? " settled, " : " safe, ")
     << percent(s.unsafe_fraction) << " unsafe, " << percent(s.undecided_fraction)
     << (stoppedAtWitness ? (sensitiveStop ? " undecided or not examined, " : " not examined, ") : " undecided, ")
     << percent(s.outside_fraction) << " outside the region\n";
  const std::size_t left = r.undecided_box_count;
  if (stoppedAtWitness) {
    os << "left:      " << left << " box" << plural(left, "es")
       << (sensitiveStop ? " undecided or not examined (the search stops at the first certified uncertainty-sensitive "
                           "poses)\n"
                         : " not examined (the search stops at the first certified witness)\n");
    return;
  }
  os << "undecided: " << left << " box" << plural(left, "es") << "\n";
  if (isTrajectory(info) && !r.undecided_boxes.empty()) {
    const auto times = undecidedTimes(r, info);
    os << "           in time:";
    for (std::size_t i = 0; i < std::min<std::size_t>(times.size(), 5); ++i) {
      os << " [" << num(times[i].first) << ", " << num(times[i].second) << "] s";
    }
    if (times.size() > 5) os << " ... (" << times.size() << " intervals)";
    os << "\n";
  }
  const std::size_t shown = std::min<std::size_t>(r.undecided_boxes.size(), 3);
  for (std::size_t i = 0; i < shown; ++i) os << "           " << boxText(info, r.undecided_boxes[i].box) << "\n";
  if (left > shown) {
    os << "           ... (the reports list the first " << std::min(r.undecided_boxes.size(), info.max_listed_boxes)
       << ")\n";
  }
}

}  // namespace

void writeSummary(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                  const RunInfo& info) {
  writeHeader(os, r, o, info);
  writeWitness(os, r, o, info);
  writeSingular(os, r, info);
  writeSensitive(os, r, o, info);
  writeComponents(os, r, o, info);
  if (r.verdict == verify::Verdict::Safe && o.mode == verify::Mode::Verify) {
    os << "every component is certified below its threshold at every pose of the " << info.domain << "\n";
  }
  writeStats(os, r, o, info);
  writeVolumeAndUndecided(os, r, o, info);
}

}  // namespace io
}  // namespace pkm_accuracy
