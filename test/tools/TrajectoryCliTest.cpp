// pkm_verify --trajectory: a trajectory's reports (witness_t, time span, undecided time intervals, the argmax times)
// against dense sampling of the worst error along it; bad trajectory input exits 3 naming the file, key and row; a
// motion variety from the command line.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../core/TrajectorySampling.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;
using test::sample;
using test::Sampled;
using test::worstError;

namespace {

class TrajectoryCli : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/pkm_traj_cli_XXXXXX";
    ASSERT_NE(::mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream f(dir_ + "/" + name);
    f << text;
    return dir_ + "/" + name;
  }
  static std::string read(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  }
  /// Runs pkm_verify; returns the exit code, fills out / err.
  int run(const std::vector<std::string>& args, std::string& out, std::string& err) const {
    std::string cmd = "'" + std::string(PKM_PVERIFY_EXE) + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " > '" + dir_ + "/out.txt' 2> '" + dir_ + "/err.txt' < /dev/null";
    const int status = std::system(cmd.c_str());
    out = read(dir_ + "/out.txt");
    err = read(dir_ + "/err.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  static std::string join(const DVec& v) {
    std::string s;
    char buf[64];
    for (int i = 0; i < v.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g", v[i]);
      s += (i ? "," : "") + std::string(buf);
    }
    return s;
  }
  std::string dir_;
};

const char* kSlerpFile =
    "interpolation: slerp\n"
    "waypoints:\n"
    "  - [0.0, -0.10, 0.05, 0.46, 0.25, -0.20, 0.15]\n"
    "  - [1.0,  0.00, 0.00, 0.47, 0.00,  0.10, 0.00]\n"
    "  - [3.0,  0.12, -0.08, 0.49, -0.20, 0.30, -0.25]\n";

}  // namespace

TEST_F(TrajectoryCli, VerifiesATrajectoryAndReportsTheWitnessTime) {
  const std::string file = write("slerp.yaml", kSlerpFile);
  const io::TrajectoryFile traj = io::loadTrajectoryFile(file);
  const Sampled s = sample(*traj.trajectory, 20000);
  const std::string robot = test::configPath("ref6.yaml");
  std::string out, err;
  // SAFE at +10%: empty list of undecided time intervals.
  ASSERT_EQ(
      run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.1), "--json", dir_ + "/safe.json"},
          out, err),
      0)
      << out << err;
  EXPECT_NE(out.find("trajectory: " + file + " (waypoints (slerp), 3 waypoints), t in [0, 3] s"), std::string::npos)
      << out;
  const YAML::Node safe = YAML::LoadFile(dir_ + "/safe.json");  // JSON is YAML
  EXPECT_EQ(safe["verdict"].as<std::string>(), "SAFE");
  EXPECT_EQ(safe["domain"].as<std::string>(), "trajectory");
  EXPECT_EQ(safe["trajectory"].as<std::string>(), file);
  EXPECT_TRUE(safe["workspace"].IsNull());
  EXPECT_TRUE(safe["witness_t"].IsNull());
  EXPECT_EQ(safe["time_span"][1].as<double>(), 3.0);
  EXPECT_EQ(safe["undecided_t"].size(), 0u);
  EXPECT_EQ(safe["variables"][0].as<std::string>(), "u");

  // UNSAFE at -5%: witness_t is the time of witness_variables[0] and its nominal pose exceeds the threshold.
  const DVec thresholds = s.max * 0.95;
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--thresholds", join(thresholds), "--json",
                 dir_ + "/unsafe.json", "--yaml", dir_ + "/unsafe.yaml"},
                out, err),
            1)
      << out << err;
  EXPECT_NE(out.find("witness:   t = "), std::string::npos) << out;
  const YAML::Node j = YAML::LoadFile(dir_ + "/unsafe.json");
  EXPECT_EQ(j["verdict"].as<std::string>(), "UNSAFE");
  const double t = j["witness_t"].as<double>(), u = j["witness_variables"][0].as<double>();
  EXPECT_NEAR(t, 3.0 * u, 1e-12);
  const int k = j["witness_component"].as<int>();
  EXPECT_GT(worstError(traj.trajectory->pointAtTime(t).pose)[k], thresholds[k]);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(j["witness"][i].as<double>(), traj.trajectory->pointAtTime(t).pose[i], 1e-9);
  }
  EXPECT_TRUE(j["undecided_t"].IsSequence());
  const YAML::Node y = YAML::LoadFile(dir_ + "/unsafe.yaml");
  EXPECT_EQ(y["witness_t"].as<double>(), t);

  // A time limit far too small: UNDECIDED, with the undecided part of the trajectory as time intervals.
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.0001), "--max-boxes", "3",
                 "--json", dir_ + "/undecided.json"},
                out, err),
            2)
      << out << err;
  const YAML::Node und = YAML::LoadFile(dir_ + "/undecided.json");
  ASSERT_GE(und["undecided_t"].size(), 1u);
  for (std::size_t i = 0; i < und["undecided_t"].size(); ++i) {
    const double lo = und["undecided_t"][i][0].as<double>(), hi = und["undecided_t"][i][1].as<double>();
    EXPECT_LE(0.0, lo);
    EXPECT_LE(lo, hi);
    EXPECT_LE(hi, 3.0);
  }
  EXPECT_NE(out.find("in time: ["), std::string::npos) << out;

  // max-error: the argmax of every component as a parameter, a time and a pose (which attains the lower bound).
  ASSERT_EQ(run({"--robot", robot, "--trajectory", file, "--mode", "max-error", "--alpha", "0.02", "--json",
                 dir_ + "/max.json"},
                out, err),
            0)
      << out << err;
  const YAML::Node mx = YAML::LoadFile(dir_ + "/max.json");
  ASSERT_EQ(mx["max_error"]["argmax_t"].size(), 6u);
  for (int c = 0; c < 6; ++c) {
    const double tc = mx["max_error"]["argmax_t"][c].as<double>();
    EXPECT_NEAR(tc, 3.0 * mx["max_error"]["argmax_variables"][c][0].as<double>(), 1e-12);
    EXPECT_GE(mx["max_error"]["upper"][c].as<double>(), s.max[c] * (1 - 1e-9));
    ASSERT_EQ(mx["max_error"]["argmax"][c].size(), 6u);
    DVec pose(6);
    for (int i = 0; i < 6; ++i) pose[i] = mx["max_error"]["argmax"][c][i].as<double>();
    EXPECT_LT((pose - traj.trajectory->pointAtTime(tc).pose).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_GE(worstError(pose)[c], mx["max_error"]["lower"][c].as<double>() * (1 - 1e-9));
  }

  // --min-width takes one value per parameter.
  EXPECT_EQ(
      run({"--robot", robot, "--trajectory", file, "--thresholds", join(s.max * 1.1), "--min-width", "1e-6"}, out, err),
      0)
      << err;
}

TEST_F(TrajectoryCli, BadTrajectoryInputExitsThree) {
  const std::string robot = test::configPath("ref6.yaml");
  const std::string good = write("good.yaml", kSlerpFile);
  const std::string t6 = "1e-4,1e-4,1e-4,1e-3,1e-3,1e-3";
  const std::string decreasing = write("decreasing.yaml",
                                       "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [2, 0, 0, 0.47, 0, 0, 0]\n"
                                       "  - [1, 0, 0, 0.47, 0, 0, 0]\n");
  const std::string shortRow = write("short.yaml", "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, 0, 0]\n");
  const std::string nan =
      write("nan.yaml", "waypoints:\n  - [0, 0, 0, 0.47, 0, 0, 0]\n  - [1, .nan, 0, 0.47, 0, 0, 0]\n");
  const std::vector<std::pair<std::vector<std::string>, std::vector<std::string>>> cases = {
      {{"--robot", robot, "--workspace", "paper", "--trajectory", good, "--thresholds", t6},
       {"--trajectory", "--workspace"}},
      {{"--robot", robot, "--trajectory", decreasing, "--thresholds", t6},
       {"--trajectory", "decreasing.yaml: waypoints[2][0]", "not greater"}},
      {{"--robot", robot, "--trajectory", shortRow, "--thresholds", t6},
       {"--trajectory", "short.yaml: waypoints[1]", "expected 7 numbers"}},
      {{"--robot", robot, "--trajectory", nan, "--thresholds", t6}, {"nan.yaml: waypoints[1][1]", "finite"}},
      {{"--robot", robot, "--trajectory", dir_ + "/missing.yaml", "--thresholds", t6},
       {"--trajectory", "missing.yaml"}},
      {{"--robot", robot, "--trajectory", dir_, "--thresholds", t6}, {"--trajectory", "not a regular file"}},
      {{"--robot", robot, "--trajectory", good, "--thresholds", t6, "--min-width", "1,2"},
       {"--min-width", "expected 1 comma-separated value", "got 2"}},
      {{"--robot", robot, "--trajectory", good, "--thresholds", t6, "--min-width", "-1"}, {"--min-width[0] (u)"}},
      {{"--robot", robot, "--trajectory", "", "--thresholds", t6}, {"--trajectory", "empty"}},
  };
  for (const auto& c : cases) {
    std::string line;
    for (const auto& a : c.first) line += a + " ";
    SCOPED_TRACE(line);
    std::string out, err;
    EXPECT_EQ(run(c.first, out, err), 3) << out << err;
    EXPECT_TRUE(out.empty()) << out;
    EXPECT_EQ(err.rfind("pkm_verify: error: ", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    for (const auto& m : c.second) EXPECT_NE(err.find(m), std::string::npos) << "'" << m << "' in: " << err;
  }
}

TEST_F(TrajectoryCli, VarietyFromTheCommandLine) {
  const std::string file = write("variety.yaml",
                                 "variety:\n"
                                 "  parameters: 2\n"
                                 "  x: [[-0.05, 0, 0], [0.1, 1, 0]]\n"
                                 "  y: [[-0.05, 0, 0], [0.1, 0, 1]]\n"
                                 "  z: [[0.47, 0, 0]]\n"
                                 "  yaw: [[0.2, 1, 1]]\n");
  std::string out, err;
  ASSERT_EQ(run({"--robot", test::configPath("ref6.yaml"), "--trajectory", file, "--thresholds",
                 "1e-3,1e-3,1e-3,1e-2,1e-2,1e-2", "--json", dir_ + "/v.json"},
                out, err),
            0)
      << out << err;
  const YAML::Node j = YAML::LoadFile(dir_ + "/v.json");
  EXPECT_EQ(j["domain"].as<std::string>(), "variety");
  EXPECT_TRUE(j["witness_t"].IsNull());
  EXPECT_TRUE(j["time_span"].IsNull());
  EXPECT_EQ(j["variables"].size(), 2u);
  EXPECT_NE(out.find("variety:   " + file), std::string::npos) << out;
}
