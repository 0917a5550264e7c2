#include "pkm_accuracy/io/ResultWriter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <ostream>
#include <sstream>
#include <utility>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

/// Plain YAML keys for identifiers, double-quoted otherwise.
std::string yamlKey(const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
  return plain ? key : jsonString(key);
}

// ---- a small document tree, written both as JSON and as YAML ------------------------------------------------------
class Node {
 public:
  enum class Kind { Null, Bool, Number, Integer, String, Array, Object };

  Node() = default;
  static Node number(double x) {
    Node n(Kind::Number);
    n.number_ = x;
    return n;
  }
  static Node integer(long long x) {
    Node n(Kind::Integer);
    n.integer_ = x;
    return n;
  }
  static Node boolean(bool b) {
    Node n(Kind::Bool);
    n.bool_ = b;
    return n;
  }
  static Node string(std::string s) {
    Node n(Kind::String);
    n.string_ = std::move(s);
    return n;
  }
  static Node array() { return Node(Kind::Array); }
  static Node object() { return Node(Kind::Object); }

  Node& push(Node n) {
    items_.push_back(std::move(n));
    return *this;
  }
  Node& set(const std::string& key, Node n) {
    members_.emplace_back(key, std::move(n));
    return *this;
  }

  Kind kind() const { return kind_; }
  /// Arrays holding no object (printed on one line).
  bool flat() const {
    if (kind_ == Kind::Object) return false;
    for (const Node& n : items_)
      if (!n.flat()) return false;
    return true;
  }

  void writeJson(std::ostream& os, int indent) const {
    switch (kind_) {
      case Kind::Null:
        os << "null";
        return;
      case Kind::Bool:
        os << (bool_ ? "true" : "false");
        return;
      case Kind::Number:
        os << jsonNumber(number_);
        return;
      case Kind::Integer:
        os << integer_;
        return;
      case Kind::String:
        os << jsonString(string_);
        return;
      case Kind::Array: {
        if (flat()) {
          os << '[';
          for (std::size_t i = 0; i < items_.size(); ++i) {
            if (i > 0) os << ", ";
            items_[i].writeJson(os, indent);
          }
          os << ']';
          return;
        }
        os << "[\n";
        for (std::size_t i = 0; i < items_.size(); ++i) {
          os << std::string(indent + 2, ' ');
          items_[i].writeJson(os, indent + 2);
          os << (i + 1 < items_.size() ? ",\n" : "\n");
        }
        os << std::string(indent, ' ') << ']';
        return;
      }
      case Kind::Object: {
        if (members_.empty()) {
          os << "{}";
          return;
        }
        os << "{\n";
        for (std::size_t i = 0; i < members_.size(); ++i) {
          os << std::string(indent + 2, ' ') << jsonString(members_[i].first) << ": ";
          members_[i].second.writeJson(os, indent + 2);
          os << (i + 1 < members_.size() ? ",\n" : "\n");
        }
        os << std::string(indent, ' ') << '}';
        return;
      }
    }
  }

  /// YAML: objects in block style, arrays in flow style (they never hold objects here), strings double-quoted with
  /// JSON escapes (a subset of YAML's double-quoted escapes), numbers as in JSON but with .inf / -.inf / .nan.
  void writeYamlScalarOrFlow(std::ostream& os) const {
    switch (kind_) {
      case Kind::Null:
        os << "null";
        return;
      case Kind::Bool:
        os << (bool_ ? "true" : "false");
        return;
      case Kind::Number:
        if (std::isnan(number_)) {
          os << ".nan";
        } else if (std::isinf(number_)) {
          os << (number_ > 0 ? ".inf" : "-.inf");
        } else {
          os << jsonNumber(number_);
        }
        return;
      case Kind::Integer:
        os << integer_;
        return;
      case Kind::String:
        os << jsonString(string_);
        return;
      case Kind::Array:
        os << '[';
        for (std::size_t i = 0; i < items_.size(); ++i) {
          if (i > 0) os << ", ";
          items_[i].writeYamlScalarOrFlow(os);
        }
        os << ']';
        return;
      case Kind::Object:
        os << "{}";  // only reached for empty objects
        return;
    }
  }

  void writeYamlMembers(std::ostream& os, int indent) const {
    for (const auto& m : members_) {
      os << std::string(indent, ' ') << yamlKey(m.first) << ':';
      if (m.second.kind_ == Kind::Object && !m.second.members_.empty()) {
        os << '\n';
        m.second.writeYamlMembers(os, indent + 2);
      } else if (m.second.kind_ == Kind::Array && !m.second.flat()) {
        os << '\n';
        for (const Node& item : m.second.items_) {
          os << std::string(indent + 2, ' ') << "-";
          if (item.kind_ == Kind::Object && !item.members_.empty()) {
            os << '\n';
            item.writeYamlMembers(os, indent + 4);
          } else {
            os << ' ';
            item.writeYamlScalarOrFlow(os);
            os << '\n';
          }
        }
      } else {
        os << ' ';
        m.second.writeYamlScalarOrFlow(os);
        os << '\n';
      }
    }
  }

 private:
  explicit Node(Kind k) : kind_(k) {}
  Kind kind_ = Kind::Null;
  bool bool_ = false;
  double number_ = 0.0;
  long long integer_ = 0;
  std::string string_;
  std::vector<Node> items_;
  std::vector<std::pair<std::string, Node>> members_;
};

Node numbers(const DVec& v) {
  Node a = Node::array();
  for (int i = 0; i < v.size(); ++i) a.push(Node::number(v[i]));
  return a;
}

Node numbersOrNull(const DVec& v) { return v.size() > 0 ? numbers(v) : Node(); }

Node box(const IVec& b) {
  Node a = Node::array();
  for (int i = 0; i < b.size(); ++i) {
    if (b[i].isEmpty()) {
      a.push(Node());
    } else {
      a.push(Node::array().push(Node::number(b[i].lower())).push(Node::number(b[i].upper())));
    }
  }
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
  for (std::size_t p = 0; p < g.size(); ++p) {
    m.set(parameterName(info, p), Node::array().push(Node::number(g[p].lower())).push(Node::number(g[p].upper())));
  }
  return m;
}

/// Midpoints of a pose enclosure.
DVec midpoints(const IVec& v) {
  DVec p(v.size());
  for (int i = 0; i < v.size(); ++i) p[i] = v[i].mid();
  return p;
}

/// The pose of the witness: the midpoints of its enclosure (exact for a workspace, whose poses are the variables).
DVec witnessPose(const verify::VerifierResult& r) {
  if (r.witness_pose.size() == 0) return r.witness;
  DVec p(r.witness_pose.size());
  for (int i = 0; i < r.witness_pose.size(); ++i) p[i] = r.witness_pose[i].mid();
  return p;
}

bool hasWitness(const verify::VerifierResult& r) {
  return r.verdict == verify::Verdict::Unsafe && r.witness_component >= 0 && r.witness.size() > 0;
}

bool isTrajectory(const RunInfo& info) { return info.domain == "trajectory"; }

Node document(const verify::VerifierResult& r, const verify::VerifierOptions& o, const RunInfo& info) {
  Node d = Node::object();
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
  d.set("bisection", Node::string(bisectionName(o.tuning.bisection)));
  d.set("thresholds", numbersOrNull(o.thresholds));
  d.set("alpha", o.mode == verify::Mode::MaxError ? Node::number(o.alpha) : Node());
  d.set("alpha_relative", o.mode == verify::Mode::MaxError ? Node::boolean(o.alpha_relative) : Node());
  d.set("anchor_uncertainty", Node::number(info.anchor_uncertainty));
  d.set("max_boxes", count(o.max_boxes));
  d.set("time_limit", Node::number(o.time_limit_s));
  d.set("min_width", numbersOrNull(o.min_width));
  d.set("geometry_splitting", Node::string(geometrySplittingName(o.geometry_splitting)));
  d.set("stall_levels", Node::integer(o.tuning.stall_levels));
  d.set("faces", Node::boolean(o.tuning.faces));
  d.set("skip_hopeless", Node::boolean(o.tuning.skip_hopeless));
  d.set("geometry_form", Node::string(o.tuning.decompose_geometry ? "decomposed" : "combined"));
  d.set("geometry_parameters", info.geometry_parameters.empty() ? Node() : strings(info.geometry_parameters));
  d.set("geometry_ranges", geometryRanges(info, info.geometry_ranges));

  const bool witness = hasWitness(r);
  d.set("witness", witness ? numbers(witnessPose(r)) : Node());
  d.set("witness_variables", witness ? numbers(r.witness) : Node());
  d.set("witness_component", witness ? Node::integer(r.witness_component) : Node());
  const bool named = witness && r.witness_component < static_cast<int>(info.components.size());
  d.set("witness_component_name", named ? Node::string(info.components[r.witness_component]) : Node());
  d.set("witness_lower_bound", witness ? Node::number(r.witness_lower_bound) : Node());
  d.set("witness_error_lower", witness ? numbersOrNull(r.witness_error_lower) : Node());

  // A certified singular pose (either mode): the two points where det J^-1 has opposite certified signs.
  if (r.singular) {
    Node s = Node::object();
    s.set("from", numbers(r.singular_from));
    s.set("to", numbers(r.singular_to));
    s.set("from_pose", numbers(midpoints(r.singular_pose_from)));
    s.set("to_pose", numbers(midpoints(r.singular_pose_to)));
    const bool t = isTrajectory(info) && r.singular_from.size() > 0 && r.singular_to.size() > 0;
    s.set("from_t", t ? Node::number(info.timeOf(r.singular_from[0])) : Node());
    s.set("to_t", t ? Node::number(info.timeOf(r.singular_to[0])) : Node());
    s.set("geometry", geometryValues(info, r.singular_geometry));
    d.set("singular", s);
  } else {
    d.set("singular", Node());
  }

  // Uncertainty-sensitive poses (verify mode with uncertain geometry).
  d.set("sensitive_count", count(r.sensitive_count));
  Node sensitive = Node::array();
  for (std::size_t i = 0; i < r.sensitive.size() && i < info.max_listed_boxes; ++i) {
    const verify::SensitivePose& p = r.sensitive[i];
    Node e = Node::object();
    e.set("point", numbers(p.point));
    e.set("pose", p.pose.size() > 0 ? numbers(midpoints(p.pose)) : numbers(p.point));
    e.set("region", box(p.region));
    e.set("component", Node::integer(p.component));
    e.set("component_name", p.component >= 0 && p.component < static_cast<int>(info.components.size())
                                ? Node::string(info.components[p.component])
                                : Node());
    e.set("failing_lower", Node::number(p.failing_lower));
    e.set("failing_geometry", geometryValues(info, p.failing_geometry));
    const bool passing = !p.passing_geometry.empty();
    e.set("passing_geometry", geometryValues(info, p.passing_geometry));
    e.set("passing_upper", passing ? Node::number(p.passing_upper) : Node());
    e.set("passes_all", Node::boolean(passing && p.passes_all));
    const bool timed = isTrajectory(info) && p.point.size() > 0;
    e.set("t", timed ? Node::number(info.timeOf(p.point[0])) : Node());
    e.set("region_t", timed && p.region.size() > 0 && !p.region[0].isEmpty()
                          ? Node::array()
                                .push(Node::number(info.timeOf(p.region[0].lower())))
                                .push(Node::number(info.timeOf(p.region[0].upper())))
                          : Node());
    sensitive.push(e);
  }
  d.set("sensitive", sensitive);

  if (o.mode == verify::Mode::MaxError && r.max_lower.size() > 0) {
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
    d.set("max_error", m);
  } else {
    d.set("max_error", Node());
  }

  Node s = Node::object();
  s.set("boxes", count(r.stats.boxes));
  s.set("seconds", Node::number(r.stats.seconds));
  s.set("max_depth", Node::integer(r.stats.max_depth));
  s.set("safe_fraction", Node::number(r.stats.safe_fraction));
  s.set("unsafe_fraction", Node::number(r.stats.unsafe_fraction));
  s.set("undecided_fraction", Node::number(r.stats.undecided_fraction));
  s.set("outside_fraction", Node::number(r.stats.outside_fraction));
  s.set("threads", Node::integer(r.stats.threads));
  s.set("geometry_switches", count(r.stats.geometry_switches));
  s.set("geometry_splits", count(r.stats.geometry_splits));
  s.set("face_switches", count(r.stats.face_switches));
  s.set("face_boxes", count(r.stats.face_boxes));
  s.set("unenclosed_boxes", count(r.stats.unenclosed_boxes));
  s.set("self_check_points", o.self_check ? count(r.stats.self_check_points) : Node());
  d.set("stats", s);

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
  d.set("undecided_boxes", u);

  d.set("domain", Node::string(info.domain));
  d.set("trajectory", info.trajectory.empty() ? Node() : Node::string(info.trajectory));
  d.set("trajectory_type", info.trajectory.empty() ? Node() : Node::string(info.trajectory_type));
  const bool traj = isTrajectory(info);
  d.set("time_span",
        traj ? Node::array().push(Node::number(info.time_start)).push(Node::number(info.time_end)) : Node());
  d.set("witness_t", traj && witness && r.witness.size() > 0 ? Node::number(info.timeOf(r.witness[0])) : Node());
  if (traj) {
    Node times = Node::array();
    for (const auto& iv : undecidedTimes(r, info)) {
      times.push(Node::array().push(Node::number(iv.first)).push(Node::number(iv.second)));
    }
    d.set("undecided_t", times);
  } else {
    d.set("undecided_t", Node());
  }
  return d;
}

// ---- human summary -----------------------------------------------------------------------------------------------
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

std::string variables(const RunInfo& info, const DVec& t) {
  std::ostringstream os;
  for (int i = 0; i < t.size(); ++i) {
    const auto nu =
        splitName(i < static_cast<int>(info.variables.size()) ? info.variables[i] : "t" + std::to_string(i));
    os << (i > 0 ? ", " : "") << nu.first << " = " << num(t[i], 9) << (nu.second.empty() ? "" : " " + nu.second);
  }
  return os.str();
}

std::string boxText(const RunInfo& info, const IVec& b) {
  std::ostringstream os;
  for (int i = 0; i < b.size(); ++i) {
    const auto nu =
        splitName(i < static_cast<int>(info.variables.size()) ? info.variables[i] : "t" + std::to_string(i));
    os << (i > 0 ? ", " : "") << nu.first << " [" << num(b[i].lower()) << ", " << num(b[i].upper()) << "]"
       << (nu.second.empty() ? "" : " " + nu.second);
  }
  return os.str();
}

std::string pad(const std::string& s, std::size_t w) {
  return s.size() >= w ? s + " " : s + std::string(w - s.size(), ' ');
}

}  // namespace

double RunInfo::timeOf(double u) const {
  const double t = time_start + u * (time_end - time_start);
  return std::min(std::max(t, time_start), time_end);
}

std::vector<std::pair<double, double>> undecidedTimes(const verify::VerifierResult& result, const RunInfo& info) {
  std::vector<std::pair<double, double>> t;
  for (const auto& b : result.undecided_boxes) {
    if (b.box.size() < 1 || b.box[0].isEmpty()) continue;
    t.emplace_back(info.timeOf(b.box[0].lower()), info.timeOf(b.box[0].upper()));
  }
  std::sort(t.begin(), t.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& iv : t) {
    if (!merged.empty() && iv.first <= merged.back().second) {
      merged.back().second = std::max(merged.back().second, iv.second);
    } else {
      merged.push_back(iv);
    }
  }
  return merged;
}

std::string modeName(verify::Mode mode) { return mode == verify::Mode::MaxError ? "max_error" : "verify"; }

std::string bisectionName(verify::Bisection bisection) {
  switch (bisection) {
    case verify::Bisection::Smear:
      return "smear";
    case verify::Bisection::LargestScaledWidth:
      return "width";
    case verify::Bisection::RoundRobin:
      return "round-robin";
  }
  return "smear";
}

std::string geometrySplittingName(verify::GeometrySplitting splitting) {
  switch (splitting) {
    case verify::GeometrySplitting::Auto:
      return "auto";
    case verify::GeometrySplitting::Never:
      return "never";
    case verify::GeometrySplitting::Always:
      return "always";
  }
  return "auto";
}

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string toJson(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info) {
  std::ostringstream os;
  document(result, options, info).writeJson(os, 0);
  os << '\n';
  return os.str();
}

std::string toYaml(const verify::VerifierResult& result, const verify::VerifierOptions& options, const RunInfo& info) {
  std::ostringstream os;
  os << "# " << info.tool << " result (units: m and rad; see components / units)\n";
  document(result, options, info).writeYamlMembers(os, 0);
  return os.str();
}

void writeSummary(std::ostream& os, const verify::VerifierResult& r, const verify::VerifierOptions& o,
                  const RunInfo& info) {
  const int n = static_cast<int>(
      std::max<Eigen::Index>({o.thresholds.size(), r.max_lower.size(), r.witness_error_lower.size(), Eigen::Index(0)}));
  os << "verdict:   " << verify::toString(r.verdict);
  if (r.verdict == verify::Verdict::Undecided) os << " (" << verify::toString(r.reason) << ")";
  os << "\nmessage:   " << r.message << "\n";
  os << "robot:     " << info.robot;
  if (info.robot_type != "gough") {
    os << " (" << info.robot_type << "; " << info.geometry_parameters.size() << " uncertain geometry value"
       << (info.geometry_parameters.size() == 1 ? "" : "s") << ")\n";
  } else if (info.uniform_uncertainty) {
    os << " (anchor uncertainty " << num(info.anchor_uncertainty) << " m)\n";
  } else {
    os << " (uncertainty per coordinate: anchors up to " << num(info.anchor_uncertainty) << " m, tool point up to "
       << num(info.tool_point_uncertainty) << " m; " << info.geometry_parameters.size() << " uncertain coordinate"
       << (info.geometry_parameters.size() == 1 ? "" : "s") << ")\n";
  }
  if (info.trajectory.empty()) {
    os << "workspace: " << info.workspace << " (" << info.workspace_region << "): " << boxText(info, info.workspace_box)
       << "\n";
  } else {
    os << pad(info.domain + ":", 11) << info.trajectory << " (" << info.trajectory_type << ")";
    if (isTrajectory(info)) os << ", t in [" << num(info.time_start) << ", " << num(info.time_end) << "] s";
    if (info.workspace_region != "none") os << ", region " << info.workspace_region;
    os << "\n";
  }
  os << "method:    " << o.method << ", bisection " << bisectionName(o.tuning.bisection) << ", mode "
     << modeName(o.mode);
  if (o.mode == verify::Mode::MaxError) os << ", alpha " << num(o.alpha) << (o.alpha_relative ? " (relative)" : "");
  os << "\n";

  if (hasWitness(r)) {
    const int k = r.witness_component;
    if (info.trajectory.empty()) {
      os << "witness:   " << variables(info, witnessPose(r)) << "\n";
    } else {
      RunInfo poseNames = info;
      poseNames.variables = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
      os << "witness:   ";
      if (isTrajectory(info)) os << "t = " << num(info.timeOf(r.witness[0]), 9) << " s (";
      os << variables(info, r.witness) << (isTrajectory(info) ? ")" : "") << "\n";
      os << "           pose " << variables(poseNames, witnessPose(r)) << "\n";
    }
    os << "           " << componentOf(info, k) << " worst error >= " << num(r.witness_lower_bound, 9) << " "
       << unitOf(info, k);
    if (k < o.thresholds.size()) os << " > threshold " << num(o.thresholds[k]) << " " << unitOf(info, k);
    os << " (certified)\n";
  }

  if (r.singular) {
    os << "singular:  det J^-1 has certified opposite signs, for "
       << (r.singular_geometry.empty() ? "every admissible geometry" : "the nominal geometry")
       << ", at the two ends of a segment inside the domain: J^-1 is singular between them\n";
    RunInfo poseNames = info;
    poseNames.variables = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
    for (const DVec* t : {&r.singular_from, &r.singular_to}) {
      const IVec& pose = t == &r.singular_from ? r.singular_pose_from : r.singular_pose_to;
      os << "           ";
      if (isTrajectory(info) && t->size() > 0) os << "t = " << num(info.timeOf((*t)[0]), 9) << " s: ";
      os << variables(poseNames, midpoints(pose)) << "\n";
    }
  }

  if (!r.sensitive.empty()) {
    const verify::SensitivePose& p = r.sensitive.front();
    const int k = p.component;
    os << "sensitive: " << r.sensitive_count << " certified pose" << (r.sensitive_count == 1 ? "" : "s")
       << " where the answer depends on the geometric uncertainty, e.g.\n";
    const DVec pose = p.pose.size() > 0 ? midpoints(p.pose) : p.point;
    if (info.trajectory.empty()) {
      os << "           pose " << variables(info, pose) << "\n";
    } else {
      RunInfo poseNames = info;
      poseNames.variables = {"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"};
      os << "           ";
      if (isTrajectory(info) && p.point.size() > 0) os << "t = " << num(info.timeOf(p.point[0]), 9) << " s, ";
      os << "pose " << variables(poseNames, pose) << "\n";
    }
    os << "           " << componentOf(info, k) << " worst error >= " << num(p.failing_lower, 9) << " "
       << unitOf(info, k);
    if (k >= 0 && k < o.thresholds.size()) os << " > threshold " << num(o.thresholds[k]) << " " << unitOf(info, k);
    os << " for an admissible geometry (certified)\n";
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

  if (n > 0) {
    const bool maxError = r.max_lower.size() == n;
    os << "\n  " << pad("component", 11) << pad("unit", 6);
    if (maxError) os << pad("max >= lower", 18) << pad("max <= upper", 18) << pad("gap", 10);
    if (o.thresholds.size() == n) os << pad("threshold", 14);
    if (!maxError && r.witness_error_lower.size() == n) os << "at witness >=";
    os << "\n";
    for (int k = 0; k < n; ++k) {
      os << "  " << pad(componentOf(info, k), 11) << pad(unitOf(info, k), 6);
      if (maxError) {
        const double gap = r.max_upper[k] - r.max_lower[k];
        os << pad(num(r.max_lower[k], 10), 18) << pad(num(r.max_upper[k], 10), 18)
           << pad(r.max_lower[k] > 0 && std::isfinite(gap) ? percent(gap / r.max_lower[k]) : num(gap, 3), 10);
      }
      if (o.thresholds.size() == n) os << pad(num(o.thresholds[k]), 14);
      if (!maxError && r.witness_error_lower.size() == n) os << num(r.witness_error_lower[k], 10);
      os << "\n";
    }
    if (maxError)
      os << "  (max: the largest worst-case error over the " << info.domain << "; certified bracket [lower, upper])\n";
    os << "\n";
  }
  if (r.verdict == verify::Verdict::Safe && o.mode == verify::Mode::Verify) {
    os << "every component is certified below its threshold at every pose of the " << info.domain << "\n";
  }

  const auto& s = r.stats;
  os << "stats:     " << s.boxes << (s.boxes == 1 ? " box in " : " boxes in ") << num(s.seconds, 3) << " s on "
     << s.threads << " thread" << (s.threads == 1 ? "" : "s") << ", max depth " << s.max_depth;
  if (s.unenclosed_boxes > 0) os << "; " << s.unenclosed_boxes << " split without an enclosure";
  os << "\n";
  if (o.self_check) {
    os << "self-check: " << s.self_check_points << " point" << (s.self_check_points == 1 ? "" : "s")
       << " of the boxes evaluated in double, each within its box's certified bounds\n";
  }
  if (!info.geometry_parameters.empty()) {
    os << "geometry:  " << info.geometry_parameters.size() << " uncertain parameter"
       << (info.geometry_parameters.size() == 1 ? "" : "s") << ", splitting "
       << geometrySplittingName(o.geometry_splitting) << ": " << s.geometry_switches << " box"
       << (s.geometry_switches == 1 ? "" : "es") << " switched to bisecting the geometry, " << s.geometry_splits
       << " geometry split" << (s.geometry_splits == 1 ? "" : "s") << "; " << s.face_switches << " path"
       << (s.face_switches == 1 ? "" : "s") << " switched to the faces (" << s.face_boxes << " box"
       << (s.face_boxes == 1 ? "" : "es") << ")\n";
  }
  const bool sensitiveStop =
      r.verdict == verify::Verdict::Undecided && r.reason == verify::UndecidedReason::UncertaintySensitive;
  const bool stoppedAtWitness = (r.verdict == verify::Verdict::Unsafe || sensitiveStop) &&
                                o.mode == verify::Mode::Verify && o.stop_at_first_witness;
  os << "volume:    " << percent(s.safe_fraction) << (o.mode == verify::Mode::MaxError ? " settled, " : " safe, ")
     << percent(s.unsafe_fraction) << " unsafe, " << percent(s.undecided_fraction)
     << (stoppedAtWitness ? (sensitiveStop ? " undecided or not examined, " : " not examined, ") : " undecided, ")
     << percent(s.outside_fraction) << " outside the region\n";
  if (stoppedAtWitness) {
    os << "left:      " << r.undecided_box_count << " box" << (r.undecided_box_count == 1 ? "" : "es")
       << (sensitiveStop ? " undecided or not examined (the search stops at the first certified uncertainty-sensitive "
                           "poses)\n"
                         : " not examined (the search stops at the first certified witness)\n");
    return;
  }
  os << "undecided: " << r.undecided_box_count << " box" << (r.undecided_box_count == 1 ? "" : "es") << "\n";
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
  if (r.undecided_box_count > shown) {
    os << "           ... (the reports list the first " << std::min(r.undecided_boxes.size(), info.max_listed_boxes)
       << ")\n";
  }
}

void writeTextFile(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text << std::flush;
    if (!std::cout) throw InvalidArgument("standard output: write failed");
    return;
  }
  std::ofstream f(path, std::ios::out | std::ios::trunc);
  if (!f) throw InvalidArgument(path + ": cannot open for writing");
  f << text;
  f.close();
  if (!f) throw InvalidArgument(path + ": write failed");
}

}  // namespace io
}  // namespace pkm_accuracy
