// rostest (diagnostics.test): the node's status on /diagnostics. Before any job: OK, robot loaded, its file, no job,
// no busy answer, no verdict yet. After a job: its verdict and a small age. While a long job runs and another request
// is refused: the job counted, the busy answer counted, level WARN.
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "VerifyHelpers.hpp"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)

constexpr const char* kStatusName = "pkm_accuracy: verification jobs";

struct Status {
  std::uint8_t level = 255;
  std::string message, hardware_id;
  std::map<std::string, std::string> values;
};

/// The node's status messages on /diagnostics, in order.
class Diagnostics {
 public:
  Diagnostics()
      : sub_(ros::NodeHandle().subscribe<diagnostic_msgs::DiagnosticArray>(
            "/diagnostics", 100, [this](const diagnostic_msgs::DiagnosticArrayConstPtr& a) {
              for (const auto& s : a->status) {
                if (s.name != kStatusName) continue;
                Status st;
                st.level = s.level;
                st.message = s.message;
                st.hardware_id = s.hardware_id;
                for (const auto& kv : s.values) st.values[kv.key] = kv.value;
                std::lock_guard<std::mutex> lock(mutex_);
                got_.push_back(st);
              }
            })) {}
  /// The first status received after now that satisfies `pred` (within `timeout` s).
  template <class Pred>
  bool next(Pred pred, Status& out, double timeout = 10.0) {
    std::size_t from = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      from = got_.size();
    }
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (std::size_t i = from; i < got_.size(); ++i) {
          if (pred(got_[i])) {
            out = got_[i];
            return true;
          }
        }
      }
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }

 private:
  std::mutex mutex_;
  std::vector<Status> got_;
  ros::Subscriber sub_;
};

TEST(Diagnostics, RobotJobsBusyAnswersAndTheLastVerdict) {
  Diagnostics diagnostics;
  ASSERT_TRUE(ros::service::waitForService(kVerifyService, ros::Duration(30.0)));
  Status s;
  ASSERT_TRUE(diagnostics.next([](const Status&) { return true; }, s)) << "no " << kStatusName << " on /diagnostics";
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::OK) << s.message;
  EXPECT_EQ(s.values["robot loaded"], "true");
  EXPECT_NE(s.values["robot file"].find("config/ref6.yaml"), std::string::npos) << s.values["robot file"];
  EXPECT_NE(s.hardware_id.find("config/ref6.yaml"), std::string::npos) << s.hardware_id;
  EXPECT_EQ(s.values["jobs running"], "0");
  EXPECT_EQ(s.values["job slots"], "1");
  EXPECT_EQ(s.values["busy answers"], "0");
  EXPECT_EQ(s.values["last verdict"], "");
  EXPECT_EQ(s.values["default time budget (s)"], "10");

  // A job: its verdict, a few tenths of a second old at the next report.
  const auto ok = verify(smallRequest(kGenerous));
  ASSERT_TRUE(ok.success) << ok.message;
  ASSERT_TRUE(diagnostics.next([](const Status& st) { return st.values.at("last verdict") == "SAFE"; }, s));
  EXPECT_EQ(s.values["jobs finished"], "1");
  const double age = std::atof(s.values["last verdict age (s)"].c_str());
  EXPECT_GE(age, 0.0);
  EXPECT_LT(age, 3.0);

  // A long job and a request refused busy meanwhile.
  auto longReq = boxRequest(0.15, 0.45, 0.50, k38deg, kNone, "max_error");
  longReq.alpha = 1e-4;
  longReq.time_budget = 30.0;
  longReq.threads = 1;
  VerifyWorkspace::Response longRes;
  std::thread t([&] { longRes = verify(longReq); });
  ASSERT_TRUE(diagnostics.next([](const Status& st) { return st.values.at("jobs running") == "1"; }, s));
  const auto busy = verify(smallRequest(kGenerous));
  EXPECT_TRUE(busy.busy) << busy.message;
  ASSERT_TRUE(diagnostics.next([](const Status& st) { return st.values.at("busy answers") == "1"; }, s));
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::WARN) << s.message;
  EXPECT_NE(s.message.find("refused busy"), std::string::npos) << s.message;
  EXPECT_EQ(s.values["jobs running"], "1");
  // The next report, without new refusals, is OK again.
  ASSERT_TRUE(diagnostics.next([](const Status&) { return true; }, s));
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::OK) << s.message;
  EXPECT_TRUE(cancel(0).success);
  t.join();
  EXPECT_EQ(longRes.reason, "cancelled");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "diagnostics_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
