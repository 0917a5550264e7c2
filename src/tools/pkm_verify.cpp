// pkm_verify: command-line verifier of the worst-case positioning accuracy of a parallel robot over a workspace, a
// trajectory or a motion variety (no ROS), and of single poses (--at). See usage() for the arguments and the exit
// codes, docs/cli.md, docs/models.md and docs/trajectories.md.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "CommandLine.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/Version.hpp"
#include "pkm_accuracy/core/domain/PoseBox.hpp"
#include "pkm_accuracy/core/domain/TransformedDomain.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/ModelRegistry.hpp"
#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"
#include "pkm_accuracy/io/ModelPlugin.hpp"
#include "pkm_accuracy/io/ResultWriter.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

namespace {

using namespace pkm_accuracy;
using tools::badArgument;

enum ExitCode : int { kSafe = 0, kUnsafe = 1, kUndecided = 2, kBadInput = 3, kInternal = 4 };

const char* const kComponents[6] = {"dx", "dy", "dz", "drx", "dry", "drz"};
const char* const kUnits[6] = {"m", "m", "m", "rad", "rad", "rad"};
const char* const kVariables[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

std::string methodList() {
  std::string list;
  for (const auto& n : enclosure::enclosureNames()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

// ---- usage ---------------------------------------------------------------------------------------------------------
// --help: one function per section of the text (each is the text of its section and nothing else).

void usageSynopsis(std::ostream& os) {
  os << "Usage: pkm_verify --robot FILE [--workspace NAME|FILE | --trajectory FILE]\n"
        "                  [--thresholds dx,dy,dz,drx,dry,drz] [--mode verify|max_error] [--alpha A]\n"
        "                  [--uncertainty H] [--method NAME] [--threads N]\n"
        "                  [--time-limit S] [--max-boxes N] [--min-width w1,..,w6]\n"
        "                  [--geometry-splitting auto|never|always] [--json OUT] [--yaml OUT]\n"
        "                  [--self-check] [--quiet] [--progress]\n"
        "       pkm_verify --robot FILE --list-workspaces\n"
        "       pkm_verify --robot FILE --at v1,v2,...\n"
        "       pkm_verify --list-types\n"
        "       pkm_verify --help | --version\n"
        "\n"
        "Certifies the worst-case positioning error of a parallel robot over a workspace (interval analysis and\n"
        "branch-and-bound; no ROS). Units: m and rad. Options also accept the form --name=value.\n"
        "\n";
}

void usageInput(std::ostream& os) {
  os << "Input:\n"
        "  --robot FILE           robot file (required): a Gough platform as config/ref6.yaml, or any registered\n"
        "                         type named by its `type:` key (gough, planar3rpr, delta3, rus6, prs3, or a\n"
        "                         plugin's; docs/models.md); the lists of values per pose coordinate or error\n"
        "                         component below then have the robot's number of degrees of freedom\n"
        "  --plugin LIB           load a shared library that registers robot types (pkm_accuracy_register_models;\n"
        "                         docs/models.md); may be repeated\n"
        "  --at LIST              one pose (the robot's pose coordinates, comma-separated): print the joint\n"
        "                         coordinates, J^-1 and each component's worst error, in double and certified\n"
        "  --list-types           print the registered robot types and exit\n"
        "  --workspace NAME|FILE  a workspace of the robot file's `workspaces:` map, or a workspace YAML file\n"
        "                         (keys x, y, z, roll, pitch, yaw, optional region and frame: {translation, rpy} of\n"
        "                         the workspace's frame in the base frame: the reports' poses are in the base\n"
        "                         frame, the points in the workspace's variables in its frame); default: the robot\n"
        "                         file's only workspace, else the one named `paper`\n"
        "  --trajectory FILE      verify every pose along a trajectory or motion variety instead of a workspace\n"
        "                         (YAML in the robot's pose coordinates: waypoints [t, x, y, z, roll, pitch, yaw]\n"
        "                         for gough, [t, x, y, z] for delta3, ..., with interpolation slerp or linear_rpy\n"
        "                         (rigid-body pose) or linear (any type), polynomial_segments, or variety; optional\n"
        "                         region and frame: {translation, rpy} of the file's frame in the base frame;\n"
        "                         docs/trajectories.md);\n"
        "                         the reports add witness_t (s) and the undecided time intervals; their poses are\n"
        "                         in the base frame\n"
        "  --list-workspaces      print the workspaces of the robot file and exit\n"
        "  --uncertainty H        half-width (m, >= 0) of every anchor coordinate (other types: of every geometry\n"
        "                         value in m); overrides the file's\n"
        "                         anchor half-widths (anchor_uncertainty, base_anchor_uncertainty,\n"
        "                         platform_anchor_uncertainty; its tool_point_uncertainty is kept)\n";
}

void usageProblem(std::ostream& os) {
  os << "Problem:\n"
        "  --mode MODE            verify (default): SAFE / UNSAFE / UNDECIDED against the thresholds;\n"
        "                         max_error (also written max-error): certified bracket [lower, upper] of the\n"
        "                         maximal error of every component\n"
        "  --thresholds LIST      6 comma-separated finite numbers > 0: dx,dy,dz (m), drx,dry,drz (rad); required\n"
        "                         in verify mode, optional in max_error mode (then the verdict compares the bracket)\n"
        "  --alpha A              max_error: stop when upper - lower <= A * lower for every component (default 0.01)\n";
}

void usageAlgorithm(std::ostream& os) {
  os << "Algorithm:\n"
        "  --method NAME          enclosure method: "
     << methodList()
     << " (default: the first)\n"
        "  --min-width LIST       6 numbers >= 0: boxes narrower than this in every variable are not split (m, m, m,\n"
        "                         rad, rad, rad; default 1e-5 of the workspace's width); with --trajectory one\n"
        "                         number per parameter (u in [0, 1]; u, v, ... for a variety)\n"
        "  --threads N            worker threads (default 0: all hardware threads)\n"
        "  --geometry-splitting M with anchor uncertainty: auto (default: a box whose bound stops improving under\n"
        "                         bisection switches to the faces of the geometry box, then to bisecting the\n"
        "                         geometry parameters), never (never bisect the geometry), always (the geometry\n"
        "                         parameters compete with the box variables for every split)\n"
        "  --time-limit S         stop after S seconds of wall time (default 0: no limit)\n"
        "  --max-boxes N          stop after N boxes (default 0: no limit)\n"
        "  --self-check           check the enclosures while the run goes on: for every box enclosed, 4 points of\n"
        "                         the box (centre, a vertex, random points; with anchor uncertainty each with a\n"
        "                         vertex or a random point of the geometry ranges) are evaluated in plain double;\n"
        "                         a value outside the box's certified bounds beyond round-off (relative 1e-9 plus\n"
        "                         1e-14 x the condition number of J^-1) stops the run with exit code 4 and a\n"
        "                         message naming the enclosure method, the box and the point (a defect of this\n"
        "                         program). The summary and stats.self_check_points count the points checked\n";
}

void usageOutput(std::ostream& os) {
  os << "Output:\n"
        "  --json OUT             write the result as JSON to OUT ('-': standard output; the summary then goes\n"
        "                         to stderr)\n"
        "  --yaml OUT             write the result as YAML to OUT ('-': standard output)\n"
        "  --quiet                no summary on standard output, no progress line (unless --progress)\n"
        "  --progress             show the progress line on stderr even if stderr is not a terminal (default: only\n"
        "                         on a terminal, for runs longer than a second)\n"
        "  --help                 this text\n"
        "  --version              print the version and exit\n"
        "\n"
        "Ctrl-C stops the run: the result is UNDECIDED (cancelled) and the reports are still written.\n"
        "\n";
}

void usageExitCodes(std::ostream& os) {
  os << "Exit codes:\n"
        "  0  SAFE: every pose of the workspace is certified within every threshold\n"
        "     (max_error mode without thresholds: the bracket converged to alpha)\n"
        "  1  UNSAFE: a certified witness pose exceeds a threshold\n"
        "  2  UNDECIDED: neither (budget exhausted, precision limit or interrupted; with anchor uncertainty also\n"
        "     uncertainty_sensitive: a certified pose exceeds a threshold for some admissible geometries but none was\n"
        "     found exceeding it for every geometry; max_error mode without thresholds: the bracket did not\n"
        "     converge)\n"
        "  3  bad input: bad arguments, unreadable files or invalid values (one line on stderr names the argument\n"
        "     or field)\n"
        "  4  internal error (also: the self-check found a bound contradicted by a point evaluation)\n"
        "\n"
        "Example:\n"
        "  pkm_verify --robot config/ref6.yaml --workspace paper_40deg \\\n"
        "             --thresholds 1e-4,1e-4,1e-4,1e-3,1e-3,1e-3 --json result.json\n";
}

void usage(std::ostream& os) {
  usageSynopsis(os);
  usageInput(os);
  usageProblem(os);
  usageAlgorithm(os);
  usageOutput(os);
  usageExitCodes(os);
}

// ---- arguments -----------------------------------------------------------------------------------------------------
struct Arguments {
  bool help = false;
  bool version = false;
  bool list_workspaces = false;
  bool list_types = false;
  bool quiet = false;
  bool progress = false;
  std::string robot;
  std::string workspace;
  std::string trajectory;
  std::string type = "gough";                  // the robot file's type
  std::vector<std::string> plugins;            // --plugin
  std::optional<std::string> at_text;          // --at, parsed once the robot is known
  std::optional<std::string> thresholds_text;  // --thresholds, parsed once the robot's type is known
  std::optional<double> uncertainty;
  std::string json, yaml;
  verify::VerifierOptions options;
  std::vector<double> min_width;              // validated against the domain's variables later
  std::optional<std::string> min_width_text;  // parsed after the loop (--trajectory: once the domain is known)
};

/// 6 comma-separated numbers, one per error component (names = kComponents) or per workspace variable.
/// n comma-separated numbers, one per name (with its unit); `bounded`: each >= lo (> lo if `strict`), else any finite
/// number. `what` describes the list in the count message (default: the names joined by commas).
std::vector<double> parseValues(const std::string& arg, const std::string& text, const std::vector<std::string>& names,
                                const std::vector<std::string>& units, double lo, bool strict, bool bounded = true,
                                const std::string& what = "") {
  const auto items = tools::splitList(text);
  std::string list = what;
  for (std::size_t k = 0; what.empty() && k < names.size(); ++k) list += (k ? "," : "") + names[k];
  if (items.size() != names.size()) {
    badArgument(arg, "expected " + std::to_string(names.size()) + " comma-separated values (" + list + "), got " +
                         std::to_string(items.size()) + " in '" + text + "'");
  }
  std::vector<double> v;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const std::string item = arg + "[" + std::to_string(k) + "] (" + names[k] + ")";
    if (bounded) {
      v.push_back(tools::parseBounded(item, items[k], lo, strict, units[k]));
      continue;
    }
    const double x = tools::parseNumber(item, items[k]);
    if (!std::isfinite(x)) badArgument(item, "expected a finite number (" + units[k] + "), got '" + items[k] + "'");
    v.push_back(x);
  }
  return v;
}

std::vector<double> parseSix(const std::string& arg, const std::string& text, double lo, bool strict,
                             const char* const* names, const std::string& what) {
  return parseValues(arg, text, std::vector<std::string>(names, names + 6),
                     std::vector<std::string>(std::begin(kUnits), std::end(kUnits)), lo, strict, true, what);
}

/// Loads every --plugin library into the registry (exit 3 naming the library on failure).
void loadPlugins(const std::vector<std::string>& plugins) {
  for (const std::string& path : plugins) {
    try {
      io::loadModelPlugin(path, model::ModelRegistry::global());
    } catch (const InvalidArgument& e) {
      badArgument("--plugin", e.what());
    }
  }
}

/// The robot file's type (exit 3 naming the file on failure or for an unregistered type).
std::string robotType(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) badArgument("--robot", path + ": not a regular file");
  std::string type;
  try {
    type = io::robotFileType(path);
  } catch (const InvalidArgument& e) {
    badArgument("--robot", e.what());
  } catch (const std::exception& e) {
    badArgument("--robot", path + ": cannot read: " + e.what());
  }
  if (!model::ModelRegistry::global().find(type)) {
    std::string list;
    for (const std::string& n : model::ModelRegistry::global().names()) list += (list.empty() ? "" : ", ") + n;
    badArgument("--robot", path + ": type: unknown robot type '" + type + "' (registered: " + list +
                               "; a plugin's types need --plugin LIB)");
  }
  return type;
}

/// One command-line option and its value ("" for a flag).
struct Option {
  std::string name;
  std::string value;
};

/// Options that take a value (as the next argument or as --name=value).
const std::vector<std::string> kOptionsWithValue = {
    "--robot",     "--workspace",  "--thresholds",         "--mode",   "--alpha", "--uncertainty",
    "--method",    "--threads",    "--time-limit",         "--json",   "--yaml",  "--max-boxes",
    "--min-width", "--trajectory", "--geometry-splitting", "--plugin", "--at"};
/// Options that take no value.
const std::vector<std::string> kFlags = {"--help",  "-h", "--version",  "--list-workspaces", "--list-types",
                                         "--quiet", "-q", "--progress", "--self-check"};

bool isOneOf(const std::string& name, const std::vector<std::string>& names) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// The option at argv[i] with its value (argv[i + 1] unless given as --name=value; i then moves past it). Refuses
/// unknown options, values given to flags and missing values.
Option nextOption(int argc, char** argv, int& i) {
  Option o{argv[i], ""};
  bool inlineValue = false;
  if (o.name.rfind("--", 0) == 0) {
    const auto eq = o.name.find('=');
    if (eq != std::string::npos) {
      o.value = o.name.substr(eq + 1);
      o.name = o.name.substr(0, eq);
      inlineValue = true;
    }
  }
  const bool takesValue = isOneOf(o.name, kOptionsWithValue);
  const bool isFlag = isOneOf(o.name, kFlags);
  if (!takesValue && !isFlag) {
    if (o.name.empty() || o.name[0] != '-') {
      badArgument(o.name, "unexpected argument (options start with --; see --help)");
    }
    badArgument(o.name, "unknown option (see --help)");
  }
  if (isFlag && inlineValue) badArgument(o.name, "takes no value");
  if (takesValue && !inlineValue) {
    if (i + 1 >= argc) badArgument(o.name, "missing value");
    o.value = argv[++i];
  }
  return o;
}

/// A value that must not be empty (`what`: what is expected instead).
std::string nonEmpty(const Option& o, const std::string& what) {
  if (o.value.empty()) badArgument(o.name, "expected " + what + ", got an empty value");
  return o.value;
}

/// The flags (options without a value). @return whether `o` is one.
bool applyFlag(Arguments& a, const Option& o) {
  if (o.name == "--help" || o.name == "-h") {
    a.help = true;
  } else if (o.name == "--version") {
    a.version = true;
  } else if (o.name == "--list-workspaces") {
    a.list_workspaces = true;
  } else if (o.name == "--list-types") {
    a.list_types = true;
  } else if (o.name == "--quiet" || o.name == "-q") {
    a.quiet = true;
  } else if (o.name == "--progress") {
    a.progress = true;
  } else if (o.name == "--self-check") {
    a.options.self_check = true;
  } else {
    return false;
  }
  return true;
}

/// What is verified: the robot, its types' plugins, the domain, the uncertainty, a single pose. @return whether `o`
/// is one of these options.
bool applyInputOption(Arguments& a, const Option& o) {
  if (o.name == "--robot") {
    a.robot = nonEmpty(o, "a file name");
  } else if (o.name == "--plugin") {
    a.plugins.push_back(nonEmpty(o, "a shared library file"));
  } else if (o.name == "--at") {
    a.at_text = o.value;
  } else if (o.name == "--workspace") {
    a.workspace = nonEmpty(o, "a workspace name or file");
  } else if (o.name == "--trajectory") {
    a.trajectory = nonEmpty(o, "a trajectory file");
  } else if (o.name == "--uncertainty") {
    a.uncertainty = tools::parseBounded(o.name, o.value, 0.0, false, "m");
  } else {
    return false;
  }
  return true;
}

verify::Mode parseMode(const Option& o) {
  if (o.value == "verify") return verify::Mode::Verify;
  if (o.value == "max_error" || o.value == "max-error") return verify::Mode::MaxError;
  badArgument(o.name, "expected verify or max_error, got '" + o.value + "'");
}

verify::GeometrySplitting parseGeometrySplitting(const Option& o) {
  if (o.value == "auto") return verify::GeometrySplitting::Auto;
  if (o.value == "never") return verify::GeometrySplitting::Never;
  if (o.value == "always") return verify::GeometrySplitting::Always;
  badArgument(o.name, "expected auto, never or always, got '" + o.value + "'");
}

/// The question asked and how the search answers it: mode, thresholds, method, budgets, threads. @return whether
/// `o` is one of these options.
bool applyProblemOption(Arguments& a, const Option& o) {
  verify::VerifierOptions& options = a.options;
  if (o.name == "--thresholds") {
    a.thresholds_text = o.value;
  } else if (o.name == "--mode") {
    options.mode = parseMode(o);
  } else if (o.name == "--alpha") {
    options.alpha = tools::parseBounded(o.name, o.value, 0.0, true);
  } else if (o.name == "--method") {
    const auto names = enclosure::enclosureNames();
    if (!isOneOf(o.value, names)) {
      badArgument(o.name, "unknown method '" + o.value + "' (expected one of " + methodList() + ")");
    }
    options.method = o.value;
  } else if (o.name == "--threads") {
    options.threads = static_cast<int>(tools::parseCount(o.name, o.value, 4096));
  } else if (o.name == "--time-limit") {
    options.time_limit_s = tools::parseBounded(o.name, o.value, 0.0, false, "s");
  } else if (o.name == "--max-boxes") {
    options.max_boxes = static_cast<std::size_t>(tools::parseCount(o.name, o.value));
  } else if (o.name == "--min-width") {
    a.min_width_text = o.value;
  } else if (o.name == "--geometry-splitting") {
    options.geometry_splitting = parseGeometrySplitting(o);
  } else {
    return false;
  }
  return true;
}

/// The reports. @return whether `o` is one of their options.
bool applyOutputOption(Arguments& a, const Option& o) {
  if (o.name == "--json") {
    a.json = nonEmpty(o, "a file name or -");
  } else if (o.name == "--yaml") {
    a.yaml = nonEmpty(o, "a file name or -");
  } else {
    return false;
  }
  return true;
}

/// The checks of the arguments of a gough robot, and its lists of six values (thresholds, min widths of a workspace).
void finishGoughArguments(Arguments& a) {
  if (a.at_text) return;
  if (a.json == "-" && a.yaml == "-") badArgument("--yaml", "only one of --json and --yaml may write to stdout (-)");
  if (!a.trajectory.empty() && !a.workspace.empty()) {
    badArgument("--trajectory", "cannot be combined with --workspace (a run verifies a workspace or a trajectory)");
  }
  if (a.min_width_text && a.trajectory.empty()) {
    a.min_width =
        parseSix("--min-width", *a.min_width_text, 0.0, false, kVariables, "x,y,z in m, roll,pitch,yaw in rad");
  }
  if (a.thresholds_text) {
    const auto t =
        parseSix("--thresholds", *a.thresholds_text, 0.0, true, kComponents, "dx,dy,dz in m, drx,dry,drz in rad");
    a.options.thresholds = DVec::Zero(6);
    for (int k = 0; k < 6; ++k) a.options.thresholds[k] = t[k];
  } else if (a.options.mode == verify::Mode::Verify && !a.list_workspaces) {
    badArgument("--thresholds",
                "required in verify mode: 6 comma-separated values > 0, dx,dy,dz (m) and drx,dry,drz (rad), e.g. "
                "--thresholds 1e-4,1e-4,1e-4,1e-3,1e-3,1e-3 (or use --mode max_error)");
  }
}

/// The checks of the arguments of a robot of another type (its values per pose coordinate and error component are
/// parsed once the robot, its dof and names, is known).
void finishModelArguments(const Arguments& a) {
  if (!a.trajectory.empty() && !a.workspace.empty()) {
    badArgument("--trajectory", "cannot be combined with --workspace (a run verifies a workspace or a trajectory)");
  }
  if (a.json == "-" && a.yaml == "-") badArgument("--yaml", "only one of --json and --yaml may write to stdout (-)");
}

Arguments parseArguments(int argc, char** argv) {
  Arguments a;
  for (int i = 1; i < argc; ++i) {
    const Option o = nextOption(argc, argv, i);
    const bool applied =
        applyFlag(a, o) || applyInputOption(a, o) || applyProblemOption(a, o) || applyOutputOption(a, o);
    if (!applied) throw InternalError(o.name + ": an accepted option that no step applies");
  }
  if (a.help || a.version) return a;
  loadPlugins(a.plugins);
  if (a.list_types) return a;
  if (a.robot.empty()) badArgument("--robot", "required (the robot file, e.g. config/ref6.yaml; see --help)");
  a.type = robotType(a.robot);
  if (a.type == "gough") {
    finishGoughArguments(a);
  } else {
    finishModelArguments(a);
  }
  return a;
}

// ---- robot and workspace -------------------------------------------------------------------------------------------
std::string workspaceNames(const io::RobotFile& robot) {
  std::string names;
  for (const auto& kv : robot.workspaces) names += (names.empty() ? "" : ", ") + kv.first;
  return names.empty() ? "none" : names;
}

bool isRegularFile(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/// The frame of a named workspace of the robot file (nullopt: the base frame).
std::optional<domain::RigidTransform> frameOf(const io::RobotFile& robot, const std::string& name) {
  const auto f = robot.workspace_frames.find(name);
  return f == robot.workspace_frames.end() ? std::nullopt : std::optional<domain::RigidTransform>(f->second);
}

/// Resolves --workspace: a name of the robot file, else an existing file; default: the only one, else `paper`.
/// `frame`: the workspace's frame in the base frame (its `frame` key), or nullopt.
domain::Workspace resolveWorkspace(const io::RobotFile& robot, const Arguments& a, std::string& label,
                                   std::optional<domain::RigidTransform>& frame) {
  if (a.workspace.empty()) {
    if (robot.workspaces.size() == 1) {
      label = robot.workspaces.begin()->first;
      frame = frameOf(robot, label);
      return robot.workspaces.begin()->second;
    }
    const auto paper = robot.workspaces.find("paper");
    if (paper != robot.workspaces.end()) {
      label = paper->first;
      frame = frameOf(robot, label);
      return paper->second;
    }
    badArgument("--workspace", "required: " + a.robot + " has " +
                                   (robot.workspaces.empty() ? std::string("no workspaces")
                                                             : "several workspaces (" + workspaceNames(robot) + ")") +
                                   "; pass --workspace NAME or --workspace FILE");
  }
  label = a.workspace;
  const auto named = robot.workspaces.find(a.workspace);
  if (named != robot.workspaces.end()) {
    frame = frameOf(robot, label);
    return named->second;
  }
  if (isRegularFile(a.workspace)) {
    try {
      return io::parseWorkspaceFile(a.workspace, &frame);
    } catch (const InvalidArgument& e) {
      badArgument("--workspace", e.what());
    } catch (const std::exception& e) {
      badArgument("--workspace", a.workspace + ": cannot read: " + e.what());
    }
  }
  badArgument("--workspace", "'" + a.workspace + "' is neither a workspace of " + a.robot + " (" +
                                 workspaceNames(robot) + ") nor a readable workspace file");
}

/// The run info's summary of the geometry's uncertainty (the largest half-widths, and whether they are uniform).
void describeUncertainty(const model::GoughGeometry& g, io::RunInfo& info) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto* list : {&g.base_anchor_halfwidth, &g.platform_anchor_halfwidth}) {
    if (list->empty()) lo = 0.0;
    for (const Eigen::Vector3d& h : *list) {
      lo = std::min(lo, h.minCoeff());
      hi = std::max(hi, h.maxCoeff());
    }
  }
  info.anchor_uncertainty = hi;
  info.tool_point_uncertainty = g.tool_point_halfwidth.maxCoeff();
  info.uniform_uncertainty = (lo == hi || hi == 0.0) && info.tool_point_uncertainty == 0.0;
}

void listWorkspaces(const io::RobotFile& robot, const std::string& path) {
  std::cout << path << ": " << robot.workspaces.size() << " workspace" << (robot.workspaces.size() == 1 ? "" : "s")
            << "\n";
  for (const auto& kv : robot.workspaces) {
    const IVec& b = kv.second.initialBox();
    std::cout << "  " << kv.first << " (" << kv.second.region().typeName()
              << (robot.workspace_frames.count(kv.first) ? ", in its own frame" : "") << "):";
    for (int i = 0; i < b.size(); ++i) {
      std::cout << " " << kv.second.variableName(i).substr(0, kv.second.variableName(i).find(' ')) << " ["
                << tools::shortNumber(b[i].lower()) << ", " << tools::shortNumber(b[i].upper()) << "]";
    }
    std::cout << "\n";
  }
}

/// Loads --trajectory in the robot's pose coordinates (exit 3 with the file, key and row on any problem).
io::TrajectoryFile loadTrajectory(const std::string& path, const domain::PoseCoordinates& pose) {
  if (!isRegularFile(path)) {
    struct stat st;
    badArgument("--trajectory",
                path + (::stat(path.c_str(), &st) == 0 ? ": not a regular file" : ": cannot open file"));
  }
  try {
    return io::loadTrajectoryFile(path, pose);
  } catch (const InvalidArgument& e) {
    badArgument("--trajectory", e.what());
  } catch (const std::exception& e) {
    badArgument("--trajectory", path + ": cannot read: " + e.what());
  }
}

/// The domain of --trajectory in the robot's pose coordinates; fills the trajectory's keys of the reports.
std::shared_ptr<const domain::Domain> trajectoryDomain(const std::string& path, const domain::PoseCoordinates& pose,
                                                       io::RunInfo& info) {
  const io::TrajectoryFile file = loadTrajectory(path, pose);
  info.domain = file.kind == io::TrajectoryFile::Kind::Variety ? "variety" : "trajectory";
  info.trajectory = path;
  info.trajectory_type = file.description;
  info.workspace_region = file.region;
  if (file.trajectory) {
    info.time_start = file.trajectory->startTime();
    info.time_end = file.trajectory->endTime();
  }
  return file.domain;
}

/// --min-width for a trajectory or variety: one number >= 0 per parameter of the domain.
std::vector<double> parseList(const std::string& arg, const std::string& text, const domain::Domain& d) {
  const auto items = tools::splitList(text);
  if (static_cast<int>(items.size()) != d.variables()) {
    badArgument(arg, "expected " + std::to_string(d.variables()) + " comma-separated value" +
                         (d.variables() == 1 ? "" : "s") + " (one per parameter of the trajectory), got " +
                         std::to_string(items.size()) + " in '" + text + "'");
  }
  std::vector<double> v;
  for (std::size_t k = 0; k < items.size(); ++k) {
    v.push_back(tools::parseBounded(arg + "[" + std::to_string(k) + "] (" + d.variableName(static_cast<int>(k)) + ")",
                                    items[k], 0.0, false));
  }
  return v;
}

/// Checks that an output file can be written before a possibly long run (creates it if missing, keeps contents).
void checkWritable(const std::string& arg, const std::string& path) {
  if (path == "-") return;
  std::ofstream f(path, std::ios::out | std::ios::app);
  if (!f) badArgument(arg, "cannot open '" + path + "' for writing");
}

// ---- progress and interruption -------------------------------------------------------------------------------------
std::atomic<bool> g_cancel{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void onSignal(int) { g_cancel.store(true); }

void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second Ctrl-C terminates at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

/// Status line on stderr: redrawn in place on a terminal, one line per report otherwise (only with --progress).
class ProgressLine {
 public:
  explicit ProgressLine(bool terminal) : terminal_(terminal) {}

  void update(const verify::Progress& p) {
    if (p.stats.seconds < 1.0) return;  // short runs stay silent
    const auto& s = p.stats;
    const double done = std::min(1.0, s.safe_fraction + s.unsafe_fraction + s.undecided_fraction + s.outside_fraction);
    constexpr int kWidth = 20;
    const int filled = static_cast<int>(done * kWidth);
    char line[256];
    std::snprintf(line, sizeof line, "[%s%s] %6.2f%% closed, %zu boxes, %.1f s, depth %d%s",
                  std::string(static_cast<std::size_t>(filled), '#').c_str(),
                  std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(), 100.0 * done, s.boxes, s.seconds,
                  s.max_depth, terminal_ ? " (Ctrl-C stops)" : "");
    std::lock_guard<std::mutex> lock(mutex_);
    if (terminal_) {
      std::fprintf(stderr, "\r\033[K%s", line);
    } else {
      std::fprintf(stderr, "pkm_verify: %s\n", line);
    }
    std::fflush(stderr);
    shown_ = true;
  }

  /// Clears the status line (terminal) before the summary.
  void finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (terminal_ && shown_) std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }

 private:
  const bool terminal_;
  bool shown_ = false;
  std::mutex mutex_;
};

// ---- the run -------------------------------------------------------------------------------------------------------
int exitCodeOf(const verify::VerifierResult& r, const verify::VerifierOptions& o) {
  if (o.mode == verify::Mode::MaxError && o.thresholds.size() == 0) return r.converged ? kSafe : kUndecided;
  switch (r.verdict) {
    case verify::Verdict::Safe:
      return kSafe;
    case verify::Verdict::Unsafe:
      return kUnsafe;
    case verify::Verdict::Undecided:
      return kUndecided;
  }
  return kInternal;
}

/// Sets the remaining options, runs the verifier with progress and interruption, writes the reports and the
/// summary. @return the exit code.
int runAndReport(Arguments& a, const model::RobotModel& model, const domain::Domain& target, io::RunInfo& info) {
  verify::VerifierOptions& options = a.options;
  if (!a.min_width.empty()) {
    if (static_cast<int>(a.min_width.size()) != target.variables()) {
      badArgument("--min-width", "expected " + std::to_string(target.variables()) + " values, got " +
                                     std::to_string(a.min_width.size()));
    }
    options.min_width = DVec::Zero(target.variables());
    for (int i = 0; i < target.variables(); ++i) options.min_width[i] = a.min_width[i];
  }
  verify::Verifier::validate(model, target, options);  // anything left: the message names the field
  if (!a.json.empty()) checkWritable("--json", a.json);
  if (!a.yaml.empty()) checkWritable("--yaml", a.yaml);

  const bool stdoutReport = a.json == "-" || a.yaml == "-";
  const bool terminal = ::isatty(STDERR_FILENO) == 1;
  std::unique_ptr<ProgressLine> progress;
  if (a.progress || (!a.quiet && terminal)) {
    progress = std::make_unique<ProgressLine>(terminal);
    options.progress = [&progress](const verify::Progress& p) { progress->update(p); };
    options.progress_period_s = terminal ? 0.25 : 1.0;
  }
  options.cancel = &g_cancel;
  installSignalHandlers();

  const verify::VerifierResult result = verify::Verifier::run(model, target, options);
  if (progress) progress->finish();
  const int code = exitCodeOf(result, options);
  info.exit_code = code;

  if (!a.json.empty()) {
    try {
      io::writeTextFile(a.json, io::toJson(result, options, info));
    } catch (const InvalidArgument& e) {
      badArgument("--json", e.what());
    }
  }
  if (!a.yaml.empty()) {
    try {
      io::writeTextFile(a.yaml, io::toYaml(result, options, info));
    } catch (const InvalidArgument& e) {
      badArgument("--yaml", e.what());
    }
  }
  if (!a.quiet) {
    std::ostringstream summary;
    io::writeSummary(summary, result, options, info);
    (stdoutReport ? std::cerr : std::cout) << summary.str() << std::flush;
  }
  return code;
}

// ---- one pose (--at) -----------------------------------------------------------------------------------------------
/// The pose of --at (one value per pose coordinate of the robot's description).
DVec parsePose(const std::string& text, const model::RobotModel& m, const model::RobotDescription& d) {
  std::vector<std::string> names, units;
  for (const model::PoseComponent& c : d.pose) {
    names.push_back(c.name);
    units.push_back(c.unit);
  }
  const std::vector<double> v = parseValues("--at", text, names, units, 0.0, false, false);
  DVec q(m.dof());
  for (int k = 0; k < m.dof(); ++k) q[k] = v[static_cast<std::size_t>(k)];
  return q;
}

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "% .9e", x);
  return buf;
}

/// Prints the joint coordinates, J^-1 and the worst error of every component at one pose, in double and certified
/// (the certified worst errors: the verifier's max-error bracket over the single pose). @return the exit code.
int printAt(const model::RobotModel& m, const std::string& robot, const std::string& type, const DVec& q) {
  std::ostream& os = std::cout;
  os << "robot: " << robot << " (" << type << ", " << m.dof() << " dof"
     << (m.hasGeometryUncertainty() ? ", uncertain geometry" : "") << ")\n";
  os << "pose:";
  for (int k = 0; k < m.dof(); ++k) os << " " << tools::shortNumber(q[k]);
  os << "\n";
  IVec box(m.dof());
  for (int k = 0; k < m.dof(); ++k) box[k] = Interval(q[k]);
  const DVec joints = m.legLengths(q);
  os << "joint coordinates (double):\n";
  const domain::PoseBox point(std::vector<std::string>(static_cast<std::size_t>(m.dof()), "pose"), box);
  const IMat jinvI = m.inverseJacobian(box);
  for (int j = 0; j < m.dof(); ++j) os << "  " << m.jointName(j) << "  " << number(joints[j]) << "\n";
  os << "J^-1 (double; rows: joints, columns: pose components):\n";
  const DMat jinv = m.inverseJacobian(q);
  for (int i = 0; i < m.dof(); ++i) {
    os << " ";
    for (int j = 0; j < m.dof(); ++j) os << " " << number(jinv(i, j));
    os << "\n";
  }
  os << "J^-1 (certified: the largest radius of an entry's enclosure): ";
  double radius = 0.0;
  for (int i = 0; i < m.dof(); ++i)
    for (int j = 0; j < m.dof(); ++j) radius = std::max(radius, jinvI(i, j).rad());
  os << tools::shortNumber(radius) << "\n";
  os << "worst error sum_j |J_kj| e_j: double, certified [lower, upper]\n";
  DVec worst;
  bool singular = false;
  try {
    worst = m.worstErrorAt(q);
  } catch (const SingularMatrix&) {
    singular = true;
  }
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.threads = 1;
  o.alpha = 1e-6;
  o.max_boxes = 1;
  const verify::VerifierResult r = verify::Verifier::run(m, point, o);
  for (int k = 0; k < m.dof(); ++k) {
    os << "  " << m.componentName(k) << "  " << (singular ? std::string("singular") : number(worst[k])) << "  ["
       << number(r.max_lower.size() ? r.max_lower[k] : 0.0) << ", " << number(r.max_upper.size() ? r.max_upper[k] : 0.0)
       << "]\n";
  }
  const bool bounded = r.max_upper.size() == m.dof() && r.max_upper.allFinite();
  if (!bounded) os << "the certified bound is unbounded: J^-1 is singular or the pose unreachable there\n";
  return bounded ? kSafe : kUndecided;
}

// ---- robots of any registered type ---------------------------------------------------------------------------------
io::ModelFile loadModel(const Arguments& a) {
  try {
    return io::loadModelFile(a.robot);
  } catch (const InvalidArgument& e) {
    badArgument("--robot", e.what());
  } catch (const std::exception& e) {
    badArgument("--robot", a.robot + ": cannot read: " + e.what());
  }
}

/// --workspace for a non-gough robot: a name of the file's workspaces (default: the only one, else `reference`), or a
/// YAML file keyed by the pose coordinates.
std::shared_ptr<const domain::Domain> resolveModelWorkspace(const io::ModelFile& file, const Arguments& a,
                                                            std::string& label) {
  std::string names;
  for (const auto& kv : file.workspaces) names += (names.empty() ? "" : ", ") + kv.first;
  if (a.workspace.empty()) {
    if (file.workspaces.size() == 1) {
      label = file.workspaces.begin()->first;
      return file.workspaces.begin()->second;
    }
    if (file.workspaces.count("reference")) {
      label = "reference";
      return file.workspaces.at(label);
    }
    badArgument("--workspace",
                "required: " + a.robot + " has " +
                    (names.empty() ? std::string("no workspaces") : "several workspaces (" + names + ")") +
                    "; pass --workspace NAME or --workspace FILE");
  }
  label = a.workspace;
  if (file.workspaces.count(a.workspace)) return file.workspaces.at(a.workspace);
  if (isRegularFile(a.workspace)) {
    try {
      return io::loadPoseBoxFile(a.workspace, *file.model, file.description);
    } catch (const InvalidArgument& e) {
      badArgument("--workspace", e.what());
    } catch (const std::exception& e) {
      badArgument("--workspace", a.workspace + ": cannot read: " + e.what());
    }
  }
  badArgument("--workspace", "'" + a.workspace + "' is neither a workspace of " + a.robot + " (" +
                                 (names.empty() ? std::string("none") : names) + ") nor a readable workspace file");
}

/// --list-workspaces for a robot of another type.
void listModelWorkspaces(const io::ModelFile& file, const std::string& path) {
  std::cout << path << ": " << file.workspaces.size() << " workspace" << (file.workspaces.size() == 1 ? "" : "s")
            << "\n";
  for (const auto& kv : file.workspaces) {
    std::cout << "  " << kv.first << ":";
    const IVec& b = kv.second->initialBox();
    for (int i = 0; i < b.size(); ++i) {
      const std::string n = kv.second->variableName(i);
      std::cout << " " << n.substr(0, n.find(' ')) << " [" << tools::shortNumber(b[i].lower()) << ", "
                << tools::shortNumber(b[i].upper()) << "]";
    }
    std::cout << "\n";
  }
}

/// --uncertainty for a robot of another type: every geometry value in m becomes +-h (the model is rebuilt).
void applyModelUncertainty(io::ModelFile& file, double h) {
  model::RobotDescription d = file.description;
  for (model::GeometryValue& g : d.geometry) {
    if (g.unit != "m") continue;
    g.lo = -h;
    g.hi = h;
  }
  try {
    file.model = model::ModelRegistry::global().find(file.type)->make(d);
  } catch (const InvalidArgument& e) {
    badArgument("--uncertainty", e.what());
  }
  file.description = d;
}

/// The run info of a robot of another type over `target`: its components, units and geometry parameters.
void describeModelRun(const io::ModelFile& file, const domain::Domain& target, const Arguments& a, io::RunInfo& info) {
  const model::RobotModel& model = *file.model;
  info.version = pkm_accuracy::version();
  info.robot = a.robot;
  info.robot_type = file.type;
  if (a.trajectory.empty()) info.workspace_region = "box";
  info.workspace_box = target.initialBox();
  for (int i = 0; i < target.variables(); ++i) info.variables.push_back(target.variableName(i));
  info.components.clear();
  info.units.clear();
  info.pose_coordinates.clear();
  for (int k = 0; k < model.dof(); ++k) {
    const model::PoseComponent& c = file.description.pose[static_cast<std::size_t>(k)];
    info.components.push_back(c.errorName());
    info.units.push_back(c.unit);
    info.pose_coordinates.push_back(c.name + " [" + c.unit + "]");
  }
  for (int p = 0; p < model.geometryParameterCount(); ++p) {
    info.geometry_parameters.push_back(model.geometryParameterName(p));
    info.geometry_ranges.push_back(model.geometryParameterRange(p));
    info.anchor_uncertainty = std::max(info.anchor_uncertainty, model.geometryParameterRange(p).rad());
  }
  info.uniform_uncertainty = false;
}

/// --thresholds and --min-width of a robot of another type: one value per error component / domain variable.
void parseModelLists(Arguments& a, const model::RobotModel& model, const domain::Domain& target,
                     const io::RunInfo& info) {
  if (a.thresholds_text) {
    const auto t = parseValues("--thresholds", *a.thresholds_text, info.components, info.units, 0.0, true);
    a.options.thresholds = DVec::Zero(model.dof());
    for (int k = 0; k < model.dof(); ++k) a.options.thresholds[k] = t[static_cast<std::size_t>(k)];
  } else if (a.options.mode == verify::Mode::Verify) {
    std::string list;
    for (const std::string& c : info.components) list += (list.empty() ? "" : ",") + c;
    badArgument("--thresholds", "required in verify mode: " + std::to_string(model.dof()) +
                                    " comma-separated values > 0, " + list + " (or use --mode max_error)");
  }
  if (a.min_width_text && !a.trajectory.empty()) {
    a.min_width = parseList("--min-width", *a.min_width_text, target);
  } else if (a.min_width_text) {
    std::vector<std::string> names, units;
    for (int i = 0; i < target.variables(); ++i) {
      const std::string n = target.variableName(i);
      names.push_back(n.substr(0, n.find(' ')));
      units.push_back(info.units[static_cast<std::size_t>(i)]);
    }
    a.min_width = parseValues("--min-width", *a.min_width_text, names, units, 0.0, false);
  }
}

/// A robot of another type than gough (model::ModelRegistry): workspaces of boxes of its pose coordinates.
int runModel(Arguments& a) {
  io::ModelFile file = loadModel(a);
  for (const std::string& key : file.unknown_keys) {
    std::cerr << "pkm_verify: warning: --robot: " << a.robot << ": key '" << key << "' is not used (unknown key)\n";
  }
  if (a.uncertainty) applyModelUncertainty(file, *a.uncertainty);
  const model::RobotModel& model = *file.model;
  if (a.list_workspaces) {
    listModelWorkspaces(file, a.robot);
    return 0;
  }
  if (a.at_text) return printAt(model, a.robot, file.type, parsePose(*a.at_text, model, file.description));

  io::RunInfo info;
  const std::shared_ptr<const domain::Domain> target =
      a.trajectory.empty() ? resolveModelWorkspace(file, a, info.workspace)
                           : trajectoryDomain(a.trajectory, domain::PoseCoordinates::of(file.description), info);
  describeModelRun(file, *target, a, info);
  parseModelLists(a, model, *target, info);
  return runAndReport(a, model, *target, info);
}

/// The gough robot file (exit 3 naming the file on failure); warns of its unknown keys.
io::RobotFile loadGoughRobot(const Arguments& a) {
  struct stat st;
  if (::stat(a.robot.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    badArgument("--robot", a.robot + ": not a regular file");
  }
  io::RobotFile robot = [&] {
    try {
      return io::loadRobotFile(a.robot);
    } catch (const InvalidArgument& e) {
      badArgument("--robot", e.what());
    } catch (const std::exception& e) {  // e.g. an I/O error of the stream under the YAML parser
      badArgument("--robot", a.robot + ": cannot read: " + e.what());
    }
  }();
  for (const std::string& key : robot.unknown_keys) {
    std::cerr << "pkm_verify: warning: --robot: " << a.robot << ": key '" << key << "' is not used (unknown key)\n";
  }
  return robot;
}

/// --uncertainty for a gough robot: every anchor coordinate +-h (the tool point's uncertainty is kept).
void applyGoughUncertainty(io::RobotFile& robot, double h) {
  robot.geometry.setUniformAnchorUncertainty(h);
  try {
    robot.geometry.validate();
  } catch (const InvalidArgument& e) {
    badArgument("--uncertainty", e.what());
  }
}

/// What a gough run verifies: the workspace (in its frame, if it has one) or the trajectory / variety; fills the
/// run info's description of it.
std::shared_ptr<const domain::Domain> goughDomain(const io::RobotFile& robot, const Arguments& a, io::RunInfo& info) {
  if (!a.trajectory.empty()) return trajectoryDomain(a.trajectory, domain::PoseCoordinates(), info);
  std::optional<domain::RigidTransform> frame;
  auto workspace = std::make_shared<domain::Workspace>(resolveWorkspace(robot, a, info.workspace, frame));
  info.workspace_region = workspace->region().typeName();
  if (!frame) return workspace;
  // Given in a frame F: verified in the base frame; the variables stay the workspace's own (in F).
  const auto framed = std::make_shared<domain::TransformedDomain>(workspace, *frame);
  info.workspace += ", in " + framed->frameDescription();
  return framed;
}

/// A gough robot: workspaces (any region, in any frame), trajectories and motion varieties.
int runGough(Arguments& a) {
  io::RobotFile robot = loadGoughRobot(a);
  if (a.list_workspaces) {
    listWorkspaces(robot, a.robot);
    return 0;
  }
  if (a.uncertainty) applyGoughUncertainty(robot, *a.uncertainty);
  const model::GoughPlatform model(robot.geometry);
  if (a.at_text) {
    return printAt(model, a.robot, "gough", parsePose(*a.at_text, model, model::GoughKinematics::description()));
  }

  io::RunInfo info;
  info.version = pkm_accuracy::version();
  const std::shared_ptr<const domain::Domain> domainPtr = goughDomain(robot, a, info);
  const domain::Domain& target = *domainPtr;  // what is verified
  info.robot = a.robot;
  info.workspace_box = target.initialBox();
  for (int i = 0; i < target.variables(); ++i) info.variables.push_back(target.variableName(i));
  info.components.assign(std::begin(kComponents), std::end(kComponents));
  info.units.assign(std::begin(kUnits), std::end(kUnits));
  for (int p = 0; p < model.geometryParameterCount(); ++p) {
    info.geometry_parameters.push_back(model.geometryParameterName(p));
    info.geometry_ranges.push_back(model.geometryParameterRange(p));
  }
  describeUncertainty(robot.geometry, info);

  if (a.min_width_text && !a.trajectory.empty()) a.min_width = parseList("--min-width", *a.min_width_text, target);
  return runAndReport(a, model, target, info);
}

/// --help, --version, --list-types: what they print. @return whether one of them was given.
bool printInformation(const Arguments& a) {
  if (a.help) {
    usage(std::cout);
  } else if (a.version) {
    std::cout << "pkm_verify " << pkm_accuracy::version() << "\n";
  } else if (a.list_types) {
    for (const std::string& n : model::ModelRegistry::global().names()) {
      std::cout << n << ": " << model::ModelRegistry::global().find(n)->summary << "\n";
    }
  } else {
    return false;
  }
  return true;
}

int run(int argc, char** argv) {
  Arguments a = parseArguments(argc, argv);
  if (printInformation(a)) return 0;
  return a.type == "gough" ? runGough(a) : runModel(a);
}

/// One line: newlines of nested messages (e.g. YAML parser errors) become spaces.
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const pkm_accuracy::InvalidArgument& e) {  // also ParseError, InvalidGeometry
    std::cerr << "pkm_verify: error: " << oneLine(e.what()) << "\n";
    return kBadInput;
  } catch (const pkm_accuracy::InternalError& e) {  // e.g. the self-check
    std::cerr << "pkm_verify: internal error: " << oneLine(e.what()) << " (a defect of pkm_verify: please report it)\n";
    return kInternal;
  } catch (const std::exception& e) {
    std::cerr << "pkm_verify: internal error: " << oneLine(e.what()) << "\n";
    return kInternal;
  } catch (...) {
    std::cerr << "pkm_verify: internal error: unknown exception\n";
    return kInternal;
  }
}
