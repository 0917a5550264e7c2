// rostest (trajectory_action.test): the ~verify_trajectory action. Its goal and result are /verify_trajectory's
// request and response field for field (same checksums; the node's conversions copy every field); a SAFE goal
// succeeds with the service's verdict, a malformed goal is rejected naming the field, a long goal publishes feedback,
// shares the job limit (the service is answered busy), and stops promptly on cancel with its partial result
// (PREEMPTED, UNDECIDED, "cancelled").
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "ActionHelpers.hpp"
#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyTrajectoryAction.h"
#include "pkm_accuracy/ros/VerifyTrajectoryConversion.hpp"

namespace {

using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy::VerifyTrajectoryAction;
using pkm_accuracy::VerifyTrajectoryFeedback;
using pkm_accuracy::VerifyTrajectoryGoal;
using pkm_accuracy::VerifyTrajectoryResult;
using pkm_accuracy_test::bytes;
using pkm_accuracy_test::convert;
using pkm_accuracy_test::filledOutcome;
using pkm_accuracy_test::kGenerous;
using pkm_accuracy_test::kNone;
using pkm_accuracy_test::shortTrajectory;
using Client = actionlib::SimpleActionClient<VerifyTrajectoryAction>;
using State = actionlib::SimpleClientGoalState;

constexpr const char* kAction = "/pkm_accuracy/verify_trajectory";
constexpr const char* kService = "/verify_trajectory";

VerifyTrajectoryGoal goalOf(const VerifyTrajectory::Request& r) { return convert<VerifyTrajectoryGoal>(r); }

/// 20000 waypoints (1 s apart) wandering through x, y in [-0.1, 0.1], z in [0.46, 0.49] (m), angles within 0.1 rad:
/// max_error with a tiny alpha and min_width keeps one thread busy far beyond the time the test waits (budget 30 s).
VerifyTrajectoryGoal longGoal() {
  VerifyTrajectory::Request r;
  for (int i = 0; i < 20000; ++i) {
    const double t = static_cast<double>(i);
    r.times.push_back(t);
    r.x.push_back(0.1 * std::sin(0.03 * t));
    r.y.push_back(0.1 * std::cos(0.02 * t));
    r.z.push_back(0.475 + 0.015 * std::sin(0.01 * t));
    r.roll.push_back(0.1 * std::sin(0.05 * t));
    r.pitch.push_back(0.1 * std::cos(0.04 * t));
    r.yaw.push_back(0.1 * std::sin(0.07 * t));
  }
  for (std::size_t k = 0; k < 6; ++k) r.thresholds[k] = kNone[k];
  r.mode = "max_error";
  r.alpha = 1e-9;
  r.min_width = 1e-9;
  r.time_budget = 30.0;
  r.threads = 1;
  return goalOf(r);
}

std::unique_ptr<Client> g_client;  // created in main() after ros::init, destroyed before ros shuts down

Client& client() { return *g_client; }

using Feedbacks = pkm_accuracy_test::FeedbackLog<VerifyTrajectoryFeedback>;

TEST(TrajectoryAction, GoalAndResultAreTheServicesRequestAndResponse) {
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyTrajectoryGoal>(),
               ros::message_traits::md5sum<VerifyTrajectory::Request>());
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyTrajectoryResult>(),
               ros::message_traits::md5sum<VerifyTrajectory::Response>());
  VerifyTrajectory::Request r = shortTrajectory(kGenerous);
  r.interpolation = "linear_rpy";
  r.mode = "max_error";
  r.alpha = 0.25;
  r.time_budget = 11.5;
  r.min_width = 12.5;
  r.threads = 13;
  r.method = "precond";
  r.frame_id = "somewhere";
  r.polynomial_segments.resize(2);
  r.polynomial_segments[1].t = {3.5, 4.5};
  r.polynomial_segments[1].yaw = {5.5, 6.5, 7.5};
  r.geometry_splitting = "never";
  EXPECT_EQ(bytes(pkm_accuracy::ros_layer::toRequest(goalOf(r))), bytes(r));

  const pkm_accuracy::ros_layer::WorkspaceOutcome o = filledOutcome();
  VerifyTrajectory::Response res;
  VerifyTrajectoryResult result;
  pkm_accuracy::ros_layer::toResponse(o, res);
  pkm_accuracy::ros_layer::toResult(o, result);
  EXPECT_EQ(bytes(result), bytes(res));
  // The geometric-uncertainty fields reach the response (a trajectory's region is a time interval).
  EXPECT_EQ(res.lower_bound_times, (std::vector<double>(6, 0.75)));
  EXPECT_EQ(res.lower_bound_geometries, (std::vector<double>{29.5, 30.5, 31.5}));
  EXPECT_EQ(res.geometry_switches, 14u);
  EXPECT_EQ(res.geometry_splits, 15u);
  EXPECT_EQ(res.sensitive_poses, 16u);
  EXPECT_EQ(res.sensitive_component, 2);
  EXPECT_EQ(res.sensitive_failing_geometry, (std::vector<double>{18.5, 19.5}));
  EXPECT_EQ(res.sensitive_pose[0], 23.0);
  EXPECT_EQ(res.sensitive_t, 26.5);
  EXPECT_EQ(res.sensitive_t_start, 27.5);
  EXPECT_EQ(res.sensitive_t_end, 28.5);
}

TEST(TrajectoryAction, SafeGoalSucceedsWithTheServicesVerdict) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  const auto req = shortTrajectory(kGenerous);
  const State state = client().sendGoalAndWait(goalOf(req), ros::Duration(20.0));
  EXPECT_EQ(state, State::SUCCEEDED) << state.toString() << ": " << state.getText();
  const auto result = client().getResult();
  ASSERT_TRUE(result);
  ASSERT_TRUE(result->success) << result->message;
  EXPECT_EQ(result->verdict, VerifyTrajectoryResult::VERDICT_SAFE) << result->message;
  EXPECT_FALSE(result->has_witness);
  EXPECT_GT(result->job_id, 0u);
  EXPECT_DOUBLE_EQ(result->safe_fraction, 1.0);

  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(20.0)));
  VerifyTrajectory srv;
  srv.request = req;
  ASSERT_TRUE(ros::service::call(kService, srv));
  EXPECT_EQ(srv.response.verdict, result->verdict);
  EXPECT_EQ(srv.response.job_id, result->job_id + 1);  // one job counter for every interface
}

TEST(TrajectoryAction, MalformedGoalIsRejectedNamingTheField) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  auto req = shortTrajectory(kGenerous);
  req.times = {1.0, 3.0, 2.0};
  const State state = client().sendGoalAndWait(goalOf(req), ros::Duration(10.0));
  EXPECT_EQ(state, State::REJECTED) << state.toString();
  const auto result = client().getResult();
  ASSERT_TRUE(result);
  EXPECT_FALSE(result->success);
  EXPECT_FALSE(result->busy);
  EXPECT_EQ(result->job_id, 0u);
  EXPECT_NE(result->message.find("times[2]"), std::string::npos) << result->message;
  EXPECT_NE(state.getText().find("times[2]"), std::string::npos) << state.getText();
}

TEST(TrajectoryAction, FeedbackSharedJobLimitAndPromptCancelWithThePartialResult) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Feedbacks log;
  client().sendGoal(longGoal(), Client::SimpleDoneCallback(), Client::SimpleActiveCallback(), log.callback());
  ASSERT_TRUE(log.waitForBoxes(15.0)) << "no feedback with boxes > 0";
  EXPECT_EQ(client().getState(), State::ACTIVE) << client().getState().getText();

  // The running goal counts against ~max_parallel_jobs = 1 (a goal of another client is refused busy as well:
  // clients.test; a goal of this client would preempt it).
  VerifyTrajectory srv;
  srv.request = shortTrajectory(kGenerous);
  ASSERT_TRUE(ros::service::call(kService, srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_TRUE(srv.response.busy);
  EXPECT_NE(srv.response.message.find("action goal"), std::string::npos) << srv.response.message;

  // Cancel: the job stops promptly and the goal ends PREEMPTED with what it had.
  const ros::WallTime t0 = ros::WallTime::now();
  client().cancelGoal();
  ASSERT_TRUE(client().waitForResult(ros::Duration(10.0)));
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 3.0);
  EXPECT_EQ(client().getState(), State::PREEMPTED) << client().getState().getText();
  const auto r = client().getResult();
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->success) << r->message;
  EXPECT_EQ(r->verdict, VerifyTrajectoryResult::VERDICT_UNDECIDED);
  EXPECT_EQ(r->reason, "cancelled");
  EXPECT_GT(r->boxes, 0u);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(r->lower_bound[k], r->upper_bound[k]) << k;

  std::lock_guard<std::mutex> lock(log.mutex);
  ASSERT_FALSE(log.got.empty());
  for (std::size_t i = 0; i < log.got.size(); ++i) {
    const auto& f = log.got[i];
    EXPECT_EQ(f.job_id, r->job_id);
    EXPECT_EQ(f.mode, "max_error");
    EXPECT_EQ(f.time_budget, 30.0);
    EXPECT_EQ(f.lower.size(), 6u);
    EXPECT_EQ(f.upper.size(), 6u);
    EXPECT_LE(f.boxes, r->boxes);
    if (i > 0) {
      EXPECT_GE(f.boxes, log.got[i - 1].boxes);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "trajectory_action_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  g_client.reset(new Client(kAction, true));
  const int status = RUN_ALL_TESTS();
  g_client.reset();
  return status;
}
