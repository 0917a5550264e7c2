// rostest (clients.test): who waits for a job. A client in another process (this executable run again with
// --client service|action: it sends a long job and waits) killed with SIGKILL: the node sees its XML-RPC address
// refuse connections and stops its job (~verdict: UNDECIDED, "cancelled"), so that the single job slot is free again
// within about a second instead of at the end of the job's time budget. A goal of another client that is alive is
// refused busy. A new goal of this process's client preempts its own running goal (PREEMPTED, its partial result),
// with an ActionClient that tracks both goals and with a SimpleActionClient that drops the first; goals sent without
// an id belong to no client and do not preempt each other. A goal that leaves time_budget at 0 runs with the node's
// default, 10 s.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <memory>
#include <mutex>
#include <regex>
#include <string>
#include <vector>

#include <actionlib/client/action_client.h>
#include <actionlib/client/simple_action_client.h>
#include <actionlib_msgs/GoalStatus.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "ActionHelpers.hpp"
#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerificationResult.h"
#include "pkm_accuracy/VerifyWorkspaceAction.h"

extern char** environ;

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::VerificationResult;
using pkm_accuracy::VerifyWorkspaceAction;
using pkm_accuracy::VerifyWorkspaceFeedback;
using pkm_accuracy::VerifyWorkspaceGoal;
using SimpleClient = actionlib::SimpleActionClient<VerifyWorkspaceAction>;
using State = actionlib::SimpleClientGoalState;

constexpr const char* kAction = "/pkm_accuracy/verify_workspace";

/// max_error to 1e-4 at +-38 deg on one thread: runs far longer than any wait of this test.
VerifyWorkspace::Request longRequest(double time_budget) {
  auto req = boxRequest(0.15, 0.45, 0.50, k38deg, kNone, "max_error");
  req.alpha = 1e-4;
  req.time_budget = time_budget;
  req.threads = 1;
  return req;
}

VerifyWorkspaceGoal goalOf(const VerifyWorkspace::Request& r) { return convert<VerifyWorkspaceGoal>(r); }

/// Every ~verdict since the test started.
class Verdicts {
 public:
  Verdicts()
      : sub_(ros::NodeHandle().subscribe<VerificationResult>("/pkm_accuracy/verdict", 100,
                                                             [this](const pkm_accuracy::VerificationResultConstPtr& m) {
                                                               std::lock_guard<std::mutex> lock(mutex_);
                                                               got_.push_back(*m);
                                                             })) {}
  bool waitFor(std::uint64_t job_id, VerificationResult& out, double timeout = 10.0) {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& v : got_) {
          if (v.job_id == job_id) {
            out = v;
            return true;
          }
        }
      }
      ros::WallDuration(0.02).sleep();
    }
    return false;
  }

 private:
  std::mutex mutex_;
  std::vector<VerificationResult> got_;
  ros::Subscriber sub_;
};

Verdicts& verdicts() {
  static Verdicts v;
  return v;
}

/// This executable run again as a client of the node (`mode`: "service" or "action").
class ChildClient {
 public:
  explicit ChildClient(const std::string& mode) {
    std::vector<std::string> args = {"clients_node", "--client", mode};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(&a[0]);
    argv.push_back(nullptr);
    EXPECT_EQ(posix_spawn(&pid_, "/proc/self/exe", nullptr, nullptr, argv.data(), environ), 0);
  }
  ~ChildClient() { kill9(); }
  void kill9() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

/// Waits until a request is refused busy by a job of a client named "/clients_test_child...", and returns that job's
/// number (0 if none within the timeout).
std::uint64_t waitForChildJob(double timeout) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  const std::regex job("job ([0-9]+)[^;]* of /clients_test_child");
  while (ros::WallTime::now() < deadline) {
    const auto r = verify(smallRequest(kGenerous));
    std::smatch m;
    if (r.busy && std::regex_search(r.message, m, job)) return std::stoull(m[1]);
    ros::WallDuration(0.1).sleep();
  }
  return 0;
}

/// Seconds until a small request is accepted again (not busy); -1 after `timeout`.
double secondsUntilServed(double timeout) {
  const ros::WallTime t0 = ros::WallTime::now();
  while ((ros::WallTime::now() - t0).toSec() < timeout) {
    const auto r = verify(smallRequest(kGenerous));
    if (r.success) return (ros::WallTime::now() - t0).toSec();
    EXPECT_TRUE(r.busy) << r.message;
    ros::WallDuration(0.05).sleep();
  }
  return -1.0;
}

void expectKilledClientFreesTheSlot(const std::string& mode) {
  ChildClient child(mode);
  const std::uint64_t job = waitForChildJob(30.0);
  ASSERT_GT(job, 0u) << "the child's job never ran";
  child.kill9();
  const double freed = secondsUntilServed(10.0);
  EXPECT_GE(freed, 0.0) << "the slot was still taken 10 s after the client died";
  EXPECT_LT(freed, 3.0);
  VerificationResult v;
  ASSERT_TRUE(verdicts().waitFor(job, v)) << "no ~verdict for job " << job;
  EXPECT_TRUE(v.success) << v.message;
  EXPECT_EQ(v.reason, "cancelled");
  EXPECT_EQ(v.time_budget, 60.0);
  EXPECT_LT(v.seconds, 30.0);
}

TEST(Clients, AServiceClientThatDiesFreesTheSlot) { expectKilledClientFreesTheSlot("service"); }

TEST(Clients, AnActionClientThatDiesFreesTheSlot) { expectKilledClientFreesTheSlot("action"); }

TEST(Clients, AGoalOfAnotherLivingClientIsRefusedBusy) {
  ChildClient child("action");
  const std::uint64_t job = waitForChildJob(30.0);
  ASSERT_GT(job, 0u);
  SimpleClient client(kAction, true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(20.0)));
  const State state = client.sendGoalAndWait(goalOf(smallRequest(kGenerous)), ros::Duration(10.0));
  EXPECT_EQ(state, State::REJECTED) << state.toString();
  ASSERT_TRUE(client.getResult());
  EXPECT_TRUE(client.getResult()->busy);
  child.kill9();
  EXPECT_GE(secondsUntilServed(10.0), 0.0);
}

TEST(Clients, ANewGoalOfTheSameClientPreemptsItsRunningGoal) {
  actionlib::ActionClient<VerifyWorkspaceAction> client(kAction);
  ASSERT_TRUE(client.waitForActionServerToStart(ros::Duration(20.0)));
  FeedbackLog<VerifyWorkspaceFeedback> log;
  using Handle = actionlib::ClientGoalHandle<VerifyWorkspaceAction>;
  auto feedback = log.callback();
  Handle first = client.sendGoal(
      goalOf(longRequest(0.0)), [](Handle) {},
      [&](Handle, const pkm_accuracy::VerifyWorkspaceFeedbackConstPtr& f) { feedback(f); });
  ASSERT_TRUE(log.waitForBoxes(20.0)) << "the first goal never ran";
  {
    std::lock_guard<std::mutex> lock(log.mutex);
    EXPECT_EQ(log.got.back().time_budget, 10.0) << "time_budget 0 runs with the node's default, 10 s";
  }
  const ros::WallTime t0 = ros::WallTime::now();
  Handle second = client.sendGoal(goalOf(smallRequest(kGenerous)));
  const ros::WallTime deadline = t0 + ros::WallDuration(10.0);
  while (ros::WallTime::now() < deadline &&
         (first.getCommState() != actionlib::CommState::DONE || second.getCommState() != actionlib::CommState::DONE)) {
    ros::WallDuration(0.02).sleep();
  }
  ASSERT_EQ(first.getCommState(), actionlib::CommState::DONE) << first.getCommState().toString();
  ASSERT_EQ(second.getCommState(), actionlib::CommState::DONE) << second.getCommState().toString();
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 3.0);
  EXPECT_EQ(first.getTerminalState(), actionlib::TerminalState::PREEMPTED) << first.getTerminalState().toString();
  EXPECT_NE(first.getTerminalState().getText().find("preempted by a newer goal of the same client"), std::string::npos)
      << first.getTerminalState().getText();
  ASSERT_TRUE(first.getResult());
  EXPECT_TRUE(first.getResult()->success);
  EXPECT_EQ(first.getResult()->reason, "cancelled");
  EXPECT_EQ(second.getTerminalState(), actionlib::TerminalState::SUCCEEDED) << second.getTerminalState().getText();
  ASSERT_TRUE(second.getResult());
  EXPECT_EQ(second.getResult()->verdict, "SAFE");
}

// A SimpleActionClient tracks one goal: sending a new one drops the old, which the node then preempts rather than
// refusing the new one busy.
TEST(Clients, ASimpleActionClientsNewGoalReplacesItsOldOne) {
  SimpleClient client(kAction, true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(20.0)));
  FeedbackLog<VerifyWorkspaceFeedback> log;
  client.sendGoal(goalOf(longRequest(60.0)), SimpleClient::SimpleDoneCallback(), SimpleClient::SimpleActiveCallback(),
                  log.callback());
  ASSERT_TRUE(log.waitForBoxes(20.0));
  std::uint64_t first_job = 0;
  {
    std::lock_guard<std::mutex> lock(log.mutex);
    first_job = log.got.back().job_id;
  }
  const State state = client.sendGoalAndWait(goalOf(smallRequest(kGenerous)), ros::Duration(10.0));
  EXPECT_EQ(state, State::SUCCEEDED) << state.getText();
  VerificationResult v;
  ASSERT_TRUE(verdicts().waitFor(first_job, v));
  EXPECT_EQ(v.reason, "cancelled");
}

// Goals sent without an id (rostopic pub of a goal) get theirs from the server: they belong to no client and do not
// preempt one another; the second is refused busy.
TEST(Clients, GoalsWithoutAnIdDoNotPreemptEachOther) {
  std::mutex mutex;
  std::vector<pkm_accuracy::VerifyWorkspaceActionResult> results;
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe<pkm_accuracy::VerifyWorkspaceActionResult>(
      std::string(kAction) + "/result", 10, [&](const pkm_accuracy::VerifyWorkspaceActionResultConstPtr& r) {
        std::lock_guard<std::mutex> lock(mutex);
        results.push_back(*r);
      });
  ros::Publisher pub = nh.advertise<pkm_accuracy::VerifyWorkspaceActionGoal>(std::string(kAction) + "/goal", 10);
  const ros::WallTime connect = ros::WallTime::now() + ros::WallDuration(10.0);
  while ((pub.getNumSubscribers() == 0 || sub.getNumPublishers() == 0) && ros::WallTime::now() < connect) {
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_GT(pub.getNumSubscribers(), 0u);
  pkm_accuracy::VerifyWorkspaceActionGoal first, second;
  first.goal = goalOf(longRequest(60.0));
  second.goal = goalOf(smallRequest(kGenerous));
  pub.publish(first);
  const std::uint64_t job = [] {  // the first goal's job runs (a service request is refused busy)
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
    const std::regex re("job ([0-9]+) \\(action goal\\)");
    while (ros::WallTime::now() < deadline) {
      const auto r = verify(smallRequest(kGenerous));
      std::smatch m;
      if (r.busy && std::regex_search(r.message, m, re)) return static_cast<std::uint64_t>(std::stoull(m[1]));
      ros::WallDuration(0.1).sleep();
    }
    return std::uint64_t{0};
  }();
  ASSERT_GT(job, 0u);
  pub.publish(second);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  bool refused = false;
  while (!refused && ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& r : results) {
        refused = refused || (r.status.status == actionlib_msgs::GoalStatus::REJECTED && r.result.busy);
      }
    }
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_TRUE(refused) << "the second goal was not refused busy";
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& r : results) EXPECT_NE(r.result.job_id, job) << "the first goal ended: preempted";
  }
  EXPECT_TRUE(cancel(job).success);
  EXPECT_GE(secondsUntilServed(10.0), 0.0);
}

/// --client service|action: send a long job to the node and wait (until killed).
int runAsClient(int argc, char** argv, const std::string& mode) {
  ros::init(argc, argv, "clients_test_child", ros::init_options::AnonymousName);
  ros::NodeHandle nh;
  if (mode == "service") {
    VerifyWorkspace srv;
    srv.request = longRequest(60.0);
    ros::service::waitForService(kVerifyService, ros::Duration(20.0));
    ros::service::call(kVerifyService, srv);
    return 0;
  }
  SimpleClient client(kAction, true);
  client.waitForServer(ros::Duration(20.0));
  client.sendGoal(goalOf(longRequest(60.0)));
  client.waitForResult(ros::Duration(120.0));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::strcmp(argv[1], "--client") == 0) return runAsClient(argc, argv, argv[2]);
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "clients_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  verdicts();
  return RUN_ALL_TESTS();
}
