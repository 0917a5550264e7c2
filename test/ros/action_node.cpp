// rostest (action.test): the ~verify_workspace action. Its goal and result are the service's request and response
// field for field (same checksums; the node's conversions copy every field); goals succeed with the service's
// verdicts, invalid goals are rejected naming the field, a running goal publishes feedback, shares the job limit with
// the service (busy answer), stops promptly on cancel with its partial result (PREEMPTED, UNDECIDED,
// "cancelled"), and is aborted by ~cancel. ~boxes draws every finished job: the workspace, the witness of an UNSAFE
// verdict, the undecided boxes of a cancelled one.
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include "ActionHelpers.hpp"
#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerifyWorkspaceAction.h"
#include "pkm_accuracy/ros/VerifyWorkspaceConversion.hpp"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::VerifyWorkspaceAction;
using pkm_accuracy::VerifyWorkspaceFeedback;
using pkm_accuracy::VerifyWorkspaceGoal;
using pkm_accuracy::VerifyWorkspaceResult;
using Client = actionlib::SimpleActionClient<VerifyWorkspaceAction>;
using State = actionlib::SimpleClientGoalState;

constexpr const char* kAction = "/pkm_accuracy/verify_workspace";

VerifyWorkspaceGoal goalOf(const VerifyWorkspace::Request& r) { return convert<VerifyWorkspaceGoal>(r); }

VerifyWorkspaceGoal longGoal() {
  // (k38deg: more than 20 s on one thread; at +-15 deg it converges to 1e-4 in about a second, which would race with
  // the cancel.)
  auto req = boxRequest(0.15, 0.45, 0.50, k38deg, kNone, "max_error");
  req.alpha = 1e-4;
  req.time_budget = 30.0;
  req.threads = 1;
  return goalOf(req);
}

std::unique_ptr<Client> g_client;  // created in main() after ros::init, destroyed before ros shuts down

Client& client() { return *g_client; }

using Feedbacks = pkm_accuracy_test::FeedbackLog<VerifyWorkspaceFeedback>;

/// The last ~boxes message.
class Boxes {
 public:
  Boxes()
      : sub_(ros::NodeHandle().subscribe<visualization_msgs::MarkerArray>(
            "/pkm_accuracy/boxes", 10, [this](const visualization_msgs::MarkerArrayConstPtr& m) {
              std::lock_guard<std::mutex> lock(mutex_);
              last_ = m;
            })) {}
  /// Waits for the markers of a job (label "job <id>: ...").
  visualization_msgs::MarkerArrayConstPtr forJob(std::uint64_t id, double timeout = 10.0) {
    const std::string prefix = "job " + std::to_string(id) + ":";
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (last_) {
          for (const auto& m : last_->markers)
            if (m.ns == "label" && m.text.find(prefix) == 0) return last_;
        }
      }
      ros::WallDuration(0.02).sleep();
    }
    return nullptr;
  }

 private:
  std::mutex mutex_;
  visualization_msgs::MarkerArrayConstPtr last_;
  ros::Subscriber sub_;
};

std::vector<visualization_msgs::Marker> inNs(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  std::vector<visualization_msgs::Marker> out;
  for (const auto& m : a.markers)
    if (m.ns == ns) out.push_back(m);
  return out;
}

TEST(Action, GoalAndResultAreTheServicesRequestAndResponse) {
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyWorkspaceGoal>(),
               ros::message_traits::md5sum<VerifyWorkspace::Request>());
  EXPECT_STREQ(ros::message_traits::md5sum<VerifyWorkspaceResult>(),
               ros::message_traits::md5sum<VerifyWorkspace::Response>());
  // The node's conversions copy every field: a request with a distinct value in every field survives
  // request -> goal (wire format) -> toRequest byte for byte; an outcome gives identical response and result.
  VerifyWorkspace::Request r = smallRequest(kPaper, "max_error");
  r.center.x = 1.5;
  r.center.y = 2.5;
  r.center.z = 3.5;
  r.radius = 4.5;
  r.z_min = 5.5;
  r.z_max = 6.5;
  r.halfspace_normals.resize(2);
  r.halfspace_normals[1].z = 7.5;
  r.halfspace_offsets = {8.5, 9.5};
  r.alpha = 0.25;
  r.time_budget = 11.5;
  r.min_width = 12.5;
  r.threads = 13;
  r.method = "precond";
  r.frame_id = "somewhere";
  r.geometry_splitting = "always";
  r.pose_min = {14.5, 15.5};
  r.pose_max = {16.5};
  EXPECT_EQ(bytes(pkm_accuracy::ros_layer::toRequest(goalOf(r))), bytes(r));

  const pkm_accuracy::ros_layer::WorkspaceOutcome o = filledOutcome();
  VerifyWorkspace::Response res;
  VerifyWorkspaceResult result;
  pkm_accuracy::ros_layer::toResponse(o, res);
  pkm_accuracy::ros_layer::toResult(o, result);
  EXPECT_EQ(bytes(result), bytes(res));
  // The geometric-uncertainty fields reach the response.
  EXPECT_EQ(res.lower_bound_geometries, (std::vector<double>{29.5, 30.5, 31.5}));
  EXPECT_EQ(res.geometry_switches, 14u);
  EXPECT_EQ(res.geometry_splits, 15u);
  EXPECT_EQ(res.sensitive_poses, 16u);
  EXPECT_EQ(res.sensitive_component, 2);
  EXPECT_EQ(res.sensitive_failing_lower, 17.5);
  EXPECT_EQ(res.sensitive_failing_geometry, (std::vector<double>{18.5, 19.5}));
  EXPECT_EQ(res.sensitive_passing_geometry, (std::vector<double>{20.5, 21.5}));
  EXPECT_EQ(res.sensitive_passing_upper, 22.5);
  EXPECT_TRUE(res.sensitive_passes_all);
  EXPECT_EQ(res.sensitive_pose[5], 28.0);
  EXPECT_EQ(res.sensitive_region_min[0], 24.0);
  EXPECT_EQ(res.sensitive_region_max[5], 30.0);
}

TEST(Action, GoalsGetTheServicesVerdicts) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  for (const auto& [th, expected] : {std::make_pair(kGenerous, "SAFE"), std::make_pair(kTiny, "UNSAFE")}) {
    const auto req = smallRequest(th);
    const State state = client().sendGoalAndWait(goalOf(req), ros::Duration(20.0));
    EXPECT_EQ(state, State::SUCCEEDED) << state.toString() << ": " << state.getText();
    const auto result = client().getResult();
    ASSERT_TRUE(result);
    ASSERT_TRUE(result->success) << result->message;
    const auto srv = verify(req);
    EXPECT_EQ(result->verdict, srv.verdict);
    EXPECT_EQ(result->verdict, expected);
    EXPECT_GT(result->job_id, 0u);
    EXPECT_EQ(srv.job_id, result->job_id + 1);  // one job counter for both interfaces
    EXPECT_EQ(result->has_witness, srv.has_witness);
    if (result->has_witness) {
      EXPECT_TRUE(poseInWorkspace(to6(result->witness_pose), req));
    }
  }
}

TEST(Action, InvalidGoalsAreRejectedNamingTheField) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  auto req = smallRequest(kGenerous);
  req.region_type = "cube";
  State state = client().sendGoalAndWait(goalOf(req), ros::Duration(10.0));
  EXPECT_EQ(state, State::REJECTED) << state.toString();
  ASSERT_TRUE(client().getResult());
  EXPECT_FALSE(client().getResult()->success);
  EXPECT_EQ(client().getResult()->job_id, 0u);
  EXPECT_NE(client().getResult()->message.find("region_type"), std::string::npos) << client().getResult()->message;
  EXPECT_NE(state.getText().find("region_type"), std::string::npos) << state.getText();

  // The geometric-uncertainty options are checked as the service's.
  req = smallRequest(kGenerous);
  req.geometry_splitting = "sometimes";
  state = client().sendGoalAndWait(goalOf(req), ros::Duration(10.0));
  EXPECT_EQ(state, State::REJECTED) << state.toString();
  ASSERT_TRUE(client().getResult());
  EXPECT_NE(client().getResult()->message.find("geometry_splitting"), std::string::npos)
      << client().getResult()->message;

  // A frame unknown to tf2: rejected after the lookup (which happens before the goal takes a job slot), naming it.
  req = smallRequest(kGenerous);
  req.frame_id = "nowhere";
  state = client().sendGoalAndWait(goalOf(req), ros::Duration(10.0));
  EXPECT_EQ(state, State::REJECTED) << state.toString();
  EXPECT_FALSE(client().getResult()->success);
  EXPECT_EQ(client().getResult()->job_id, 0u);
  EXPECT_NE(client().getResult()->message.find("frame_id: no transform from frame \"nowhere\""), std::string::npos)
      << client().getResult()->message;
}

TEST(Action, FeedbackSharedJobLimitAndPromptCancelWithThePartialResult) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Boxes boxes;
  Feedbacks log;
  const ros::WallTime started = ros::WallTime::now();
  client().sendGoal(longGoal(), Client::SimpleDoneCallback(), Client::SimpleActiveCallback(), log.callback());
  ASSERT_TRUE(log.waitForBoxes(15.0)) << "no feedback with boxes > 0";
  EXPECT_EQ(client().getState(), State::ACTIVE);

  // The running goal counts against ~max_parallel_jobs = 1 for both interfaces (a goal of another client is
  // refused busy as well: clients.test; a goal of this client would preempt it).
  const auto busy = verify(smallRequest(kGenerous));
  EXPECT_FALSE(busy.success);
  EXPECT_TRUE(busy.busy);
  EXPECT_NE(busy.message.find("action goal"), std::string::npos) << busy.message;

  // Cancel: the job stops promptly and the goal ends PREEMPTED with what it had.
  const ros::WallTime t0 = ros::WallTime::now();
  client().cancelGoal();
  ASSERT_TRUE(client().waitForResult(ros::Duration(10.0)));
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 3.0);
  EXPECT_EQ(client().getState(), State::PREEMPTED) << client().getState().getText();
  const auto r = client().getResult();
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->success) << r->message;
  EXPECT_EQ(r->verdict, "UNDECIDED");
  EXPECT_EQ(r->reason, "cancelled");
  EXPECT_GT(r->boxes, 0u);
  EXPECT_LT(r->seconds, (ros::WallTime::now() - started).toSec());
  for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(r->lower_bound[k], r->upper_bound[k]) << k;
  EXPECT_GT(r->undecided_boxes, 0u);

  {
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
        EXPECT_GE(f.seconds, log.got[i - 1].seconds);
      }
    }
  }

  // ~boxes: the undecided boxes left by the cancelled job, as orange cubes in the base frame inside the workspace.
  const auto a = boxes.forJob(r->job_id);
  ASSERT_TRUE(a) << "no ~boxes for job " << r->job_id;
  const auto cubes = inNs(*a, "undecided");
  ASSERT_FALSE(cubes.empty());
  EXPECT_LE(cubes.size(), r->undecided_boxes);
  for (const auto& c : cubes) {
    EXPECT_EQ(c.header.frame_id, "base_link");
    EXPECT_EQ(c.type, visualization_msgs::Marker::CUBE);
    EXPECT_EQ(c.color.r, 1.0f);
    EXPECT_GT(c.color.g, 0.4f);
    EXPECT_EQ(c.color.b, 0.0f);
    EXPECT_LE(std::abs(c.pose.position.x) + c.scale.x / 2, 0.15 + 1e-9);
    EXPECT_GE(c.pose.position.z - c.scale.z / 2, 0.45 - 1e-9);
  }
  EXPECT_TRUE(inNs(*a, "witness").empty());

  // Serving again.
  const auto ok = verify(smallRequest(kGenerous));
  EXPECT_TRUE(ok.success) << ok.message;
}

TEST(Action, CancelServiceAbortsARunningGoal) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Feedbacks log;
  client().sendGoal(longGoal(), Client::SimpleDoneCallback(), Client::SimpleActiveCallback(), log.callback());
  ASSERT_TRUE(log.waitForBoxes(15.0));
  const auto c = cancel(0);
  EXPECT_TRUE(c.success) << c.message;
  ASSERT_TRUE(client().waitForResult(ros::Duration(10.0)));
  EXPECT_EQ(client().getState(), State::ABORTED) << client().getState().getText();
  EXPECT_NE(client().getState().getText().find("/pkm_accuracy/cancel"), std::string::npos);
  const auto r = client().getResult();
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->success) << r->message;
  EXPECT_EQ(r->reason, "cancelled");
}

TEST(Action, BoxesShowTheWorkspaceAndTheWitness) {
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Boxes boxes;
  const auto req = smallRequest(kTiny);
  ASSERT_EQ(client().sendGoalAndWait(goalOf(req), ros::Duration(20.0)), State::SUCCEEDED);
  const auto r = client().getResult();
  ASSERT_EQ(r->verdict, "UNSAFE");
  const auto a = boxes.forJob(r->job_id);
  ASSERT_TRUE(a) << "no ~boxes for job " << r->job_id;
  ASSERT_FALSE(a->markers.empty());
  EXPECT_EQ(a->markers.front().action, visualization_msgs::Marker::DELETEALL);  // clears the previous job's

  const auto ws = inNs(*a, "workspace");
  ASSERT_EQ(ws.size(), 1u);
  EXPECT_EQ(ws[0].header.frame_id, "base_link");
  EXPECT_EQ(ws[0].type, visualization_msgs::Marker::CUBE);
  EXPECT_NEAR(ws[0].pose.position.z, 0.475, 1e-12);
  EXPECT_NEAR(ws[0].scale.x, 0.02, 1e-12);
  EXPECT_NEAR(ws[0].scale.z, 0.01, 1e-12);
  EXPECT_LT(ws[0].color.a, 0.5f);  // translucent

  const auto bounds = inNs(*a, "workspace_bounds");
  ASSERT_EQ(bounds.size(), 1u);
  EXPECT_EQ(bounds[0].type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(bounds[0].points.size(), 24u);  // 12 edges

  const auto witness = inNs(*a, "witness");
  ASSERT_EQ(witness.size(), 1u);
  EXPECT_EQ(witness[0].type, visualization_msgs::Marker::SPHERE);
  EXPECT_EQ(witness[0].color.r, 1.0f);
  EXPECT_EQ(witness[0].color.g, 0.0f);
  EXPECT_EQ(witness[0].pose.position.x, r->witness_pose[0]);
  EXPECT_EQ(witness[0].pose.position.y, r->witness_pose[1]);
  EXPECT_EQ(witness[0].pose.position.z, r->witness_pose[2]);
}

TEST(Action, BoxesShowTheBoxesProvenSafe) {
  // The paper workspace at the demo's thresholds: SAFE after a few hundred boxes, every one of them drawn (position
  // projections, ~max_safe_box_markers = 2000 by default).
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Boxes boxes;
  const auto req = boxRequest(0.15, 0.45, 0.5, k15deg, {3e-4, 3e-4, 2e-4, 1e-3, 1e-3, 3e-3}, "verify");
  ASSERT_EQ(client().sendGoalAndWait(goalOf(req), ros::Duration(30.0)), State::SUCCEEDED);
  const auto r = client().getResult();
  ASSERT_EQ(r->verdict, "SAFE") << r->message;
  ASSERT_GT(r->boxes, 10u);
  const auto a = boxes.forJob(r->job_id);
  ASSERT_TRUE(a) << "no ~boxes for job " << r->job_id;
  const auto safe = inNs(*a, "safe");
  ASSERT_GT(safe.size(), 1u);
  EXPECT_LT(safe.size(), r->boxes);  // leaves only, one per distinct position projection
  double volume = 0.0;
  for (const auto& m : safe) {
    EXPECT_EQ(m.type, visualization_msgs::Marker::CUBE);
    EXPECT_GT(m.color.g, m.color.r);
    EXPECT_LT(m.color.a, 0.5f);
    // Inside the workspace's position box.
    EXPECT_GE(m.pose.position.x - 0.5 * m.scale.x, -0.15 - 1e-12);
    EXPECT_LE(m.pose.position.x + 0.5 * m.scale.x, 0.15 + 1e-12);
    EXPECT_GE(m.pose.position.z - 0.5 * m.scale.z, 0.45 - 1e-12);
    EXPECT_LE(m.pose.position.z + 0.5 * m.scale.z, 0.5 + 1e-12);
    volume += m.scale.x * m.scale.y * m.scale.z;
  }
  // The safe leaves tile the 6-D workspace, so their position projections cover its position box.
  EXPECT_GE(volume, 0.3 * 0.3 * 0.05 * (1 - 1e-9));
  EXPECT_TRUE(inNs(*a, "undecided").empty());
  EXPECT_TRUE(inNs(*a, "witness").empty());
}

TEST(Action, BoxesShowTheSingularSegment) {
  // paper_40deg contains singular poses: with thresholds no pose can be certified above, UNSAFE through the singular
  // segment, drawn in namespace "singular" between the positions of singular_poses.
  ASSERT_TRUE(client().waitForServer(ros::Duration(20.0)));
  Boxes boxes;
  const auto req = boxRequest(0.15, 0.45, 0.50, k40deg, {1e15, 1e15, 1e15, 1e15, 1e15, 1e15}, "verify");
  ASSERT_EQ(client().sendGoalAndWait(goalOf(req), ros::Duration(20.0)), State::SUCCEEDED);
  const auto r = client().getResult();
  ASSERT_EQ(r->verdict, "UNSAFE") << r->message;
  ASSERT_TRUE(r->singular) << r->message;
  const auto a = boxes.forJob(r->job_id);
  ASSERT_TRUE(a) << "no ~boxes for job " << r->job_id;
  const auto line = inNs(*a, "singular");
  ASSERT_EQ(line.size(), 1u);
  EXPECT_EQ(line[0].type, visualization_msgs::Marker::LINE_LIST);
  ASSERT_EQ(line[0].points.size(), 2u);
  EXPECT_EQ(line[0].pose.position.x, r->singular_poses[0]);
  EXPECT_EQ(line[0].pose.position.z, r->singular_poses[2]);
  EXPECT_NEAR(line[0].pose.position.x + line[0].points[1].x, r->singular_poses[6], 1e-12);
  EXPECT_NEAR(line[0].pose.position.z + line[0].points[1].z, r->singular_poses[8], 1e-12);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "action_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  g_client.reset(new Client(kAction, true));
  const int status = RUN_ALL_TESTS();
  g_client.reset();
  return status;
}
