// rostest (planner.test): the example planner client executes its motion only when the node proves it SAFE. Reads
// the latched ~decision of the six planner_client_example instances of the .test file (workspace mode through the
// action and the service, trajectory mode through /verify_trajectory, also in a tf2 frame and in an unknown one).
#include <mutex>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/String.h>

namespace {

/// The decision published on `topic` (latched), or "" if none within the timeout.
std::string decisionOf(const std::string& topic, double timeout) {
  std::mutex m;
  std::string got;
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<std_msgs::String>(topic, 1, [&](const std_msgs::StringConstPtr& msg) {
    std::lock_guard<std::mutex> lock(m);
    got = msg->data;
  });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (!got.empty()) return got;
    }
    ros::WallDuration(0.05).sleep();
  }
  return "";
}

TEST(PlannerClientExample, ExecutesOnSafe) { EXPECT_EQ(decisionOf("/planner_safe/decision", 40.0), "executing"); }

TEST(PlannerClientExample, DoesNotExecuteOnUnsafeAndSaysWhy) {
  const std::string d = decisionOf("/planner_unsafe/decision", 40.0);
  EXPECT_EQ(d.find("not executing: UNSAFE, the "), 0u) << d;
  EXPECT_NE(d.find("tolerance is exceeded at x="), std::string::npos) << d;
}

TEST(PlannerClientExample, TrajectoryModeExecutesOnSafe) {
  EXPECT_EQ(decisionOf("/planner_trajectory_safe/decision", 40.0), "executing");
}

TEST(PlannerClientExample, TrajectoryModeDoesNotExecuteOnUnsafeAndSaysWhen) {
  const std::string d = decisionOf("/planner_trajectory_unsafe/decision", 40.0);
  EXPECT_EQ(d.find("not executing: UNSAFE, the "), 0u) << d;
  EXPECT_NE(d.find("tolerance is exceeded at t="), std::string::npos) << d;
}

TEST(PlannerClientExample, TrajectoryModeInAFrameExecutesOnSafe) {
  EXPECT_EQ(decisionOf("/planner_trajectory_in_frame/decision", 40.0), "executing");
}

TEST(PlannerClientExample, TrajectoryModeInAnUnknownFrameDoesNotExecute) {
  const std::string d = decisionOf("/planner_trajectory_unknown_frame/decision", 40.0);
  EXPECT_EQ(d.find("not executing: the check failed: frame_id: no transform from frame \"nowhere\""), 0u) << d;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "planner_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
