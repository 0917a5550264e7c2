// io::ResultWriter: the JSON and YAML reports of a result, read back by independent parsers (nlohmann-json, yaml-cpp):
// numbers round-trip and never print as bare inf / nan, both documents hold the same keys and values, every key of the
// report table of docs/cli.md is there (and no other), the search's tuning is written as run; the human summary's
// sections. The results are built by hand (the writer translates whatever it is given; pkm_verify's end-to-end runs
// are in test/tools/CliTest.cpp).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pkm_accuracy/io/ResultWriter.hpp"

namespace {

using namespace pkm_accuracy;
using nlohmann::json;

constexpr double kInf = std::numeric_limits<double>::infinity();

IVec pointBox(const DVec& p) {
  IVec b(p.size());
  for (int i = 0; i < p.size(); ++i) b[i] = Interval(p[i]);
  return b;
}

/// A run over a 1-parameter trajectory with two uncertain geometry parameters.
io::RunInfo trajectoryInfo() {
  io::RunInfo info;
  info.version = "1.2.3";
  info.robot = "robot.yaml";
  info.domain = "trajectory";
  info.trajectory = "path.yaml";
  info.trajectory_type = "waypoints (slerp), 3 waypoints";
  info.workspace_region = "none";
  info.workspace_box = IVec(1);
  info.workspace_box[0] = Interval(0.0, 1.0);
  info.variables = {"u"};
  info.time_start = 0.0;
  info.time_end = 4.0;
  info.geometry_parameters = {"base_anchors[0].x", "platform_anchors[5].z"};
  info.geometry_ranges = {Interval(-0.001, 0.001), Interval(0.2, 0.3)};
  info.anchor_uncertainty = 0.05;
  info.uniform_uncertainty = false;
  return info;
}

/// Every section of a report filled: an UNSAFE max-error run with thresholds, a witness, a singular pose, an
/// uncertainty-sensitive pose, brackets (one unbounded), undecided boxes.
verify::VerifierResult fullResult() {
  verify::VerifierResult r;
  r.verdict = verify::Verdict::Unsafe;
  r.message = "UNSAFE: \"dy\" exceeds\ta threshold";  // characters that JSON and YAML must escape
  r.witness = DVec::Constant(1, 0.25);
  r.witness_pose = pointBox((DVec(6) << 0.1, 0.0, 0.47, 0.0, 0.0, 0.1).finished());
  r.witness_component = 1;
  r.witness_lower_bound = 1.25e-4;
  r.witness_error_lower = DVec::Constant(6, 1e-5);
  r.singular = true;
  r.singular_from = DVec::Constant(1, 0.5);
  r.singular_to = DVec::Constant(1, 0.625);
  r.singular_pose_from = pointBox(DVec::Constant(6, 0.01));
  r.singular_pose_to = pointBox(DVec::Constant(6, 0.02));
  r.singular_geometry = {0.0005, 0.25};
  r.max_lower = DVec::Constant(6, 1e-4);
  r.max_upper = DVec::Constant(6, 2e-4);
  r.max_upper[2] = kInf;
  r.max_argmax.assign(6, DVec::Constant(1, 0.75));
  r.max_argmax_pose.assign(6, pointBox(DVec::Constant(6, 0.03)));
  r.max_argmax_geometry.assign(6, std::vector<double>{});
  r.max_argmax_geometry[3] = {-0.001, 0.3};
  verify::SensitivePose p;
  p.point = DVec::Constant(1, 0.125);
  p.pose = pointBox(DVec::Constant(6, 0.04));
  p.region = IVec(1);
  p.region[0] = Interval(0.0, 0.25);
  p.component = 0;
  p.failing_geometry = {0.001, 0.2};
  p.failing_lower = 3e-4;
  r.sensitive = {p};
  r.sensitive_count = 4;
  verify::BoxRecord b;
  b.box = p.region;
  b.upper = DVec::Constant(6, kInf);
  r.undecided_boxes = {b, b};
  r.undecided_boxes[1].box[0] = Interval(0.25, 0.5);
  r.undecided_boxes[1].geometry = {Interval(0.0, 0.001), Interval(0.2, 0.25)};
  r.undecided_box_count = 7;
  r.stats.boxes = 12;
  r.stats.threads = 2;
  return r;
}

verify::VerifierOptions maxErrorOptions() {
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.thresholds = DVec::Constant(6, 1e-4);
  return o;
}

/// The keys of the report table of docs/cli.md (first column: the keys in backquotes).
std::set<std::string> documentedKeys() {
  std::ifstream f(std::string(PKM_SOURCE_DIR) + "/docs/cli.md");
  std::set<std::string> keys;
  bool inTable = false;
  for (std::string line; std::getline(f, line);) {
    if (line == "| Key | Meaning |") inTable = true;
    if (!inTable) continue;
    if (line.rfind("| `", 0) != 0) {
      if (line.rfind("|---", 0) != 0 && line.rfind("| Key", 0) != 0) break;  // the table's end
      continue;
    }
    const std::string cell = line.substr(2, line.find(" |", 2) - 2);
    for (std::size_t open = cell.find('`'); open != std::string::npos; open = cell.find('`', open)) {
      const std::size_t close = cell.find('`', open + 1);
      keys.insert(cell.substr(open + 1, close - open - 1));
      open = close + 1;
    }
  }
  return keys;
}

/// The JSON value and the YAML node say the same (JSON null where YAML has .inf / -.inf / .nan).
void expectSame(const json& j, const YAML::Node& y, const std::string& where) {
  SCOPED_TRACE(where);
  if (j.is_object()) {
    ASSERT_TRUE(y.IsMap());
    ASSERT_EQ(y.size(), j.size());
    for (auto it = j.begin(); it != j.end(); ++it) {
      ASSERT_TRUE(y[it.key()]) << it.key();
      expectSame(it.value(), y[it.key()], where + "." + it.key());
    }
  } else if (j.is_array()) {
    ASSERT_TRUE(y.IsSequence());
    ASSERT_EQ(y.size(), j.size());
    for (std::size_t i = 0; i < j.size(); ++i) expectSame(j[i], y[i], where + "[" + std::to_string(i) + "]");
  } else if (j.is_null()) {
    EXPECT_TRUE(y.IsNull() || !std::isfinite(y.as<double>())) << y;
  } else if (j.is_string()) {
    EXPECT_EQ(y.as<std::string>(), j.get<std::string>());
  } else if (j.is_boolean()) {
    EXPECT_EQ(y.as<bool>(), j.get<bool>());
  } else {
    EXPECT_EQ(y.as<double>(), j.get<double>());
  }
}

TEST(ResultWriter, NumbersRoundTripAndNeverPrintInfOrNan) {
  using io::jsonNumber;
  for (double x : {0.1, 1e-4, 1.0 / 3.0, 0.6981317007977318, 5e-324, 1.7976931348623157e308, -2.5, 0.0, 12345.0}) {
    EXPECT_EQ(std::strtod(jsonNumber(x).c_str(), nullptr), x) << jsonNumber(x);
  }
  EXPECT_EQ(jsonNumber(1e-4), "0.0001");
  EXPECT_EQ(jsonNumber(kInf), "null");
  EXPECT_EQ(jsonNumber(-kInf), "null");
  EXPECT_EQ(jsonNumber(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(io::jsonString("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
}

TEST(ResultWriter, JsonAndYamlHoldTheSameKeysAndValues) {
  const io::RunInfo info = trajectoryInfo();
  for (const bool full : {true, false}) {
    SCOPED_TRACE(full ? "every section" : "a default result");
    const verify::VerifierResult r = full ? fullResult() : verify::VerifierResult();
    const verify::VerifierOptions o = full ? maxErrorOptions() : verify::VerifierOptions();
    const json j = json::parse(io::toJson(r, o, info));  // strict: no inf / nan / trailing commas
    const std::string yaml = io::toYaml(r, o, info);
    expectSame(j, YAML::Load(yaml), "report");
    if (full) {
      EXPECT_EQ(j["message"], r.message);
      EXPECT_TRUE(j["max_error"]["upper"][2].is_null());
      EXPECT_NE(yaml.find("upper: [0.0002, 0.0002, .inf, "), std::string::npos) << yaml;
      EXPECT_EQ(j["witness_t"], 1.0);  // u = 0.25 of [0, 4] s
      EXPECT_EQ(j["singular"]["geometry"]["platform_anchors[5].z"], 0.25);
      EXPECT_EQ(j["sensitive"][0]["region_t"], json::parse("[0, 1]"));
      EXPECT_TRUE(j["undecided_boxes"]["geometry"][0].is_null());  // every admissible geometry
      EXPECT_EQ(j["undecided_boxes"]["geometry"][1]["base_anchors[0].x"], json::parse("[0, 0.001]"));
      EXPECT_EQ(j["undecided_t"], json::parse("[[0, 2]]"));  // the two boxes touch: merged
    }
  }
}

TEST(ResultWriter, EveryKeyOfTheReportTableOfTheDocsIsWrittenAndNoOther) {
  const std::set<std::string> documented = documentedKeys();
  ASSERT_GT(documented.size(), 40u) << "docs/cli.md: the report table was not found";
  for (const bool full : {true, false}) {
    SCOPED_TRACE(full ? "every section" : "a default result");
    const json j = json::parse(full ? io::toJson(fullResult(), maxErrorOptions(), trajectoryInfo())
                                    : io::toJson(verify::VerifierResult(), {}, io::RunInfo()));
    std::set<std::string> written;
    for (auto it = j.begin(); it != j.end(); ++it) {
      written.insert(it.key());
      EXPECT_EQ(documented.count(it.key()), 1u) << it.key() << " is written but not in the table of docs/cli.md";
    }
    for (const std::string& key : documented) {
      EXPECT_EQ(written.count(key), 1u) << key << " is in the table of docs/cli.md but not written";
    }
  }
}

TEST(ResultWriter, TuningIsWrittenAsRun) {
  verify::VerifierOptions o;
  const json defaults = json::parse(io::toJson(verify::VerifierResult(), o, io::RunInfo()))["tuning"];
  EXPECT_EQ(defaults, json::parse(R"({"bisection": "smear", "stall_levels": 0, "faces": true, "skip_hopeless": true,
                                      "decompose_geometry": true, "centre_check_period": 2})"));
  o.tuning.bisection = verify::Bisection::RoundRobin;
  o.tuning.stall_levels = 3;
  o.tuning.faces = false;
  o.tuning.skip_hopeless = false;
  o.tuning.decompose_geometry = false;
  o.tuning.centre_check_period = 5;
  const json set = json::parse(io::toJson(verify::VerifierResult(), o, io::RunInfo()))["tuning"];
  EXPECT_EQ(set, json::parse(R"({"bisection": "round-robin", "stall_levels": 3, "faces": false, "skip_hopeless": false,
                                  "decompose_geometry": false, "centre_check_period": 5})"));
  o.tuning.bisection = verify::Bisection::LargestScaledWidth;
  EXPECT_EQ(json::parse(io::toJson(verify::VerifierResult(), o, io::RunInfo()))["tuning"]["bisection"], "width");
}

TEST(ResultWriter, SummaryShowsEachSectionThatApplies) {
  std::ostringstream os;
  io::writeSummary(os, fullResult(), maxErrorOptions(), trajectoryInfo());
  const std::string s = os.str();
  for (const char* line : {
           "verdict:   UNSAFE\n",
           "robot:     robot.yaml (uncertainty per coordinate: anchors up to 0.05 m, tool point up to 0 m; 2 uncertain "
           "coordinates)\n",
           "trajectory: path.yaml (waypoints (slerp), 3 waypoints), t in [0, 4] s\n",
           "method:    second_order, mode max_error, alpha 0.01 (relative)\n",
           "witness:   t = 1 s (u = 0.25)\n",
           "           dy worst error >= 0.000125 m > threshold 0.0001 m (certified)\n",
           "singular:  det J^-1 has certified opposite signs, for the nominal geometry,",
           "           t = 2 s: x = 0.01 m,",
           "sensitive: 4 certified poses where the answer depends on the geometric uncertainty, e.g.\n",
           "           in the region u [0, 0.25] (t in [0, 1] s)\n",
           "  dz         m     0.0001            inf               inf",
           "stats:     12 boxes in 0 s on 2 threads, max depth 0\n",
           "geometry:  2 uncertain parameters, splitting auto: 0 boxes switched to bisecting the geometry,",
           "undecided: 7 boxes\n",
           "           in time: [0, 2] s\n",
           "           ... (the reports list the first 2)\n",
       }) {
    EXPECT_NE(s.find(line), std::string::npos) << "'" << line << "' in:\n" << s;
  }
  // A default result over a workspace: no witness, no singular, no sensitive pose, no geometry, no component table.
  std::ostringstream plain;
  io::RunInfo info;
  info.workspace = "paper";
  info.workspace_region = "box";
  io::writeSummary(plain, verify::VerifierResult(), verify::VerifierOptions(), info);
  for (const char* absent : {"witness:", "singular:", "sensitive:", "geometry:", "component"}) {
    EXPECT_EQ(plain.str().find(absent), std::string::npos) << absent << " in:\n" << plain.str();
  }
  EXPECT_NE(plain.str().find("workspace: paper (box): \n"), std::string::npos) << plain.str();
}

}  // namespace
