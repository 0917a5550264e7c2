// rostests (concurrency.test, concurrency_parallel.test): requests beyond ~max_parallel_jobs (private parameter
// ~max_parallel_jobs of this test = the node's) are answered "busy" at once while the running jobs go on; ~describe
// stays responsive; ~cancel stops running jobs (they answer UNDECIDED, reason "cancelled"); afterwards the node
// serves again. Each long job is the paper workspace at +-40 deg in max_error mode with a 30 s budget, cancelled after
// ~1 s.
#include <atomic>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "VerifyHelpers.hpp"
#include "pkm_accuracy/Progress.h"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::Progress;

int expectedParallelJobs() { return ros::NodeHandle("~").param("max_parallel_jobs", 1); }

VerifyWorkspace::Request longRequest() {
  // (k38deg: more than 20 s on one thread; at +-15 deg it converges to 1e-4 in about a second, which would race with
  // the cancel.)
  auto req = boxRequest(0.15, 0.45, 0.50, k38deg, kNone, "max_error");
  req.alpha = 1e-4;
  req.time_budget = 30.0;
  req.threads = 1;
  return req;
}

TEST(Concurrency, BusyAnswersDescribeAndCancelWhileJobsRun) {
  const int parallel = expectedParallelJobs();
  ros::NodeHandle nh;
  std::mutex m;
  std::set<std::uint64_t> running;  // job ids seen on ~progress
  ros::Subscriber sub =
      nh.subscribe<Progress>("/pkm_accuracy/progress", 100, [&](const pkm_accuracy::ProgressConstPtr& msg) {
        std::lock_guard<std::mutex> lock(m);
        running.insert(msg->job_id);
      });
  ASSERT_TRUE(ros::service::waitForService(kVerifyService, ros::Duration(20.0)));
  ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (sub.getNumPublishers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.05).sleep();
  ros::WallDuration(0.3).sleep();

  // Start `parallel` long jobs, each from its own thread (service calls block).
  std::vector<VerifyWorkspace::Response> long_res(static_cast<std::size_t>(parallel));
  std::vector<std::thread> threads;
  const ros::WallTime started = ros::WallTime::now();
  for (int i = 0; i < parallel; ++i) {
    threads.emplace_back([&long_res, i] { long_res[static_cast<std::size_t>(i)] = verify(longRequest()); });
  }
  deadline = ros::WallTime::now() + ros::WallDuration(15.0);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (static_cast<int>(running.size()) >= parallel) break;
    }
    ASSERT_LT(ros::WallTime::now(), deadline) << "the long jobs did not all start";
    ros::WallDuration(0.05).sleep();
  }

  // One more request: refused at once as busy, not queued behind the running jobs.
  ros::WallTime t0 = ros::WallTime::now();
  const auto busy = verify(smallRequest(kGenerous));
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 3.0);
  EXPECT_FALSE(busy.success);
  EXPECT_TRUE(busy.busy);
  EXPECT_EQ(busy.verdict, "");
  EXPECT_EQ(busy.job_id, 0u);
  EXPECT_NE(busy.message.find("busy"), std::string::npos) << busy.message;

  // ~describe answers while the jobs run.
  t0 = ros::WallTime::now();
  EXPECT_TRUE(describe().success);
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 3.0);

  // Cancel every running job; they end promptly with what they had.
  const auto c = cancel(0);
  EXPECT_TRUE(c.success) << c.message;
  EXPECT_EQ(static_cast<int>(c.cancelled.size()), parallel);
  for (auto& t : threads) t.join();
  EXPECT_LT((ros::WallTime::now() - started).toSec(), 20.0);
  std::set<std::uint64_t> ids;
  for (const auto& r : long_res) {
    ASSERT_TRUE(r.success) << r.message;
    EXPECT_EQ(r.verdict, "UNDECIDED");
    EXPECT_EQ(r.reason, "cancelled");
    EXPECT_LT(r.seconds, 20.0);
    EXPECT_GT(r.boxes, 0u);
    for (std::size_t k = 0; k < 6; ++k) EXPECT_LE(r.lower_bound[k], r.upper_bound[k]) << k;
    ids.insert(r.job_id);
  }
  EXPECT_EQ(static_cast<int>(ids.size()), parallel);
  EXPECT_EQ(ids.count(0), 0u);

  // Nothing left to cancel; the node serves again.
  EXPECT_FALSE(cancel(0).success);
  const auto ok = verify(smallRequest(kGenerous));
  EXPECT_TRUE(ok.success) << ok.message;
  EXPECT_EQ(ok.verdict, "SAFE");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "concurrency_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
