// rostest (relaunch.test): roslaunch pkm_accuracy accuracy_checker.launch, run by this test as a child process on the
// test's master, three times in a row: (1) a robot file with a tool point, a base frame, platform anchor uncertainty
// and sensor_error written 2e-5 (a string in YAML 1.1), plus anchor_uncertainty:=1e-4 on the command line; (2) a robot
// file without any of these keys: the node must describe that robot alone, with nothing left from (1); (3) the URDF
// source with sensor_error:=3e-5 on the command line (a string to <rosparam>).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "Ref6.hpp"
#include "pkm_accuracy/Describe.h"

extern char** environ;

namespace {

using pkm_accuracy::Describe;
using pkm_accuracy_test::loadRef6;
using pkm_accuracy_test::sourcePath;

constexpr const char* kDescribe = "/pkm_accuracy/describe";

/// A roslaunch of accuracy_checker.launch with `args`, stopped (SIGINT, as Ctrl-C) when it goes out of scope.
class Launch {
 public:
  explicit Launch(const std::vector<std::string>& args, const std::string& log) {
    std::vector<std::string> argv = {"roslaunch", "pkm_accuracy", "accuracy_checker.launch"};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(&a[0]);
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    const int rc = posix_spawnp(&pid_, "roslaunch", &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    EXPECT_EQ(rc, 0) << "could not start roslaunch";
    if (rc != 0) pid_ = -1;
  }
  ~Launch() {
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    for (int i = 0; i < 300; ++i) {  // roslaunch stops its nodes, then exits (a few seconds)
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) return;
      usleep(100000);
    }
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  bool running() const {
    int status = 0;
    return pid_ > 0 && waitpid(pid_, &status, WNOHANG) == 0;
  }

 private:
  pid_t pid_ = -1;
};

std::string logPath(const std::string& name) {
  const char* dir = std::getenv("ROS_LOG_DIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/relaunch_" + name + ".log";
}

/// Waits for the node of a launch and describes its robot.
Describe::Response describeLaunched(const Launch& launch, const std::string& log) {
  Describe srv;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::WallTime::now() < deadline) {
    if (!launch.running()) {
      ADD_FAILURE() << "roslaunch exited; its output is in " << log;
      return srv.response;
    }
    if (ros::service::exists(kDescribe, false) && ros::service::call(kDescribe, srv)) return srv.response;
    ros::WallDuration(0.2).sleep();
  }
  ADD_FAILURE() << "no " << kDescribe << " within 60 s; roslaunch's output is in " << log;
  return srv.response;
}

void waitUntilGone() {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::service::exists(kDescribe, false) && ros::WallTime::now() < deadline) ros::WallDuration(0.2).sleep();
  ASSERT_FALSE(ros::service::exists(kDescribe, false)) << "the node of the previous launch is still there";
}

TEST(Relaunch, ASecondLaunchInheritsNothingFromTheFirst) {
  {
    const std::string log = logPath("1");
    Launch first({"robot_yaml:=" + sourcePath("test/ros/ref6_tool.yaml"), "anchor_uncertainty:=1e-4"}, log);
    const auto d = describeLaunched(first, log);
    ASSERT_TRUE(d.success) << d.message;
    EXPECT_EQ(d.tool_point.z, 0.05);
    EXPECT_EQ(d.base_frame, "world");
    ASSERT_EQ(d.sensor_error.size(), 6u);
    EXPECT_EQ(d.sensor_error[3], 2e-5);
    ASSERT_EQ(d.base_anchor_halfwidth.size(), 6u);
    EXPECT_EQ(d.base_anchor_halfwidth[2].y, 1e-4);      // anchor_uncertainty:=1e-4
    EXPECT_EQ(d.platform_anchor_halfwidth[2].y, 2e-4);  // the file's platform_anchor_uncertainty replaces it
  }
  waitUntilGone();
  {
    const std::string log = logPath("2");
    Launch second({"robot_yaml:=" + sourcePath("test/ros/ref6_scaled.yaml")}, log);
    const auto d = describeLaunched(second, log);
    ASSERT_TRUE(d.success) << d.message;
    const auto scaled = loadRef6("test/ros/ref6_scaled.yaml");
    ASSERT_EQ(d.base_anchors.size(), 6u);
    EXPECT_EQ(d.base_anchors[0].x, scaled.base_anchors[0].x());
    EXPECT_EQ(d.tool_point.z, 0.0) << "tool_point carried over from the first launch";
    EXPECT_EQ(d.base_frame, "base_link") << "base_frame carried over from the first launch";
    EXPECT_EQ(d.sensor_error[3], 1e-5);
    EXPECT_TRUE(d.base_anchor_halfwidth.empty()) << "anchor_uncertainty carried over from the first launch";
    EXPECT_TRUE(d.platform_anchor_halfwidth.empty()) << "platform_anchor_uncertainty carried over";
    EXPECT_TRUE(d.geometry_parameters.empty());
  }
  waitUntilGone();
  {
    const std::string log = logPath("3");
    Launch third({"robot_source:=urdf", "sensor_error:=3e-5"}, log);
    const auto d = describeLaunched(third, log);
    ASSERT_TRUE(d.success) << d.message;
    EXPECT_EQ(d.robot_source, "urdf");
    ASSERT_EQ(d.sensor_error.size(), 6u);
    EXPECT_EQ(d.sensor_error[0], 3e-5);
    EXPECT_EQ(d.base_anchors[0].x, loadRef6().base_anchors[0].x());
    EXPECT_TRUE(d.base_anchor_halfwidth.empty());
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "relaunch_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
