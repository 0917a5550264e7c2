// rostest (namespaces.test): two nodes in the namespaces robot1 (config/ref6.yaml) and robot2 (ref6_scaled.yaml).
// Their services and actions are advertised in their namespaces (nothing at the root), each describes its own robot,
// each answers a max_error request with the bracket the core computes for its own geometry (computed here from the
// robot files, and disjoint from the other geometry's), and each publishes its anchors under its frame prefix.
#include <array>
#include <string>
#include <vector>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "VerifyHelpers.hpp"
#include "pkm_accuracy/VerifyWorkspaceAction.h"
#include "pkm_accuracy/ros/CoreBridge.hpp"
#include "pkm_accuracy/ros/VerifyWorkspaceConversion.hpp"

namespace {

using namespace pkm_accuracy_test;  // NOLINT(build/namespaces)
using pkm_accuracy::VerifyWorkspaceAction;

struct Robot {
  std::string ns;    ///< "/robot1"
  std::string file;  ///< relative to the source directory
};
const Robot kRobots[2] = {{"/robot1", "config/ref6.yaml"}, {"/robot2", "test/ros/ref6_scaled.yaml"}};

pkm_accuracy::model::GoughGeometry geometryOf(const Robot& r) {
  const Ref6 y = loadRef6(r.file);
  pkm_accuracy::model::GoughGeometry g;
  g.base_anchors = y.base_anchors;
  g.platform_anchors = y.platform_anchors;
  g.sensor_error = y.sensor_error;
  g.tool_point = y.tool_point;
  return g;
}

/// max_error over a small box of the paper workspace, one thread (the same search every time).
VerifyWorkspace::Request bracketRequest() {
  auto req = boxRequest(0.02, 0.46, 0.48, 0.05, kNone, "max_error");
  req.alpha = 0.01;
  req.threads = 1;
  return req;
}

/// The core's bracket for the robot file's geometry, computed in this process.
pkm_accuracy::ros_layer::WorkspaceOutcome coreBracket(const Robot& r) {
  const pkm_accuracy::model::GoughPlatform model(geometryOf(r));
  pkm_accuracy::ros_layer::WorkspaceQuery q;
  std::string error;
  EXPECT_TRUE(pkm_accuracy::ros_layer::fromRequest(bracketRequest(), "base_link",
                                                   pkm_accuracy::ros_layer::QueryDefaults(), q, error))
      << error;
  return pkm_accuracy::ros_layer::runWorkspaceQuery(model, q);
}

template <class A, class B>
bool overlap(const A& lo1, const A& hi1, const B& lo2, const B& hi2, std::size_t k) {
  return lo1[k] <= hi2[k] && lo2[k] <= hi1[k];
}

TEST(Namespaces, ServicesAndActionsLiveInTheNodesNamespace) {
  for (const auto& r : kRobots) {
    for (const char* s : {"/verify_workspace", "/verify_trajectory", "/verify_variety", "/pkm_accuracy/describe",
                          "/pkm_accuracy/cancel"}) {
      EXPECT_TRUE(ros::service::waitForService(r.ns + s, ros::Duration(30.0))) << r.ns + s;
    }
    actionlib::SimpleActionClient<VerifyWorkspaceAction> client(r.ns + "/pkm_accuracy/verify_workspace", true);
    EXPECT_TRUE(client.waitForServer(ros::Duration(20.0))) << r.ns;
  }
  for (const char* s : {"/verify_workspace", "/verify_trajectory", "/verify_variety"}) {
    EXPECT_FALSE(ros::service::exists(s, false)) << s << " is advertised at the root";
  }
}

TEST(Namespaces, EachNodeDescribesItsOwnRobot) {
  for (const auto& r : kRobots) {
    const std::string name = r.ns + "/pkm_accuracy/describe";
    ASSERT_TRUE(ros::service::waitForService(name, ros::Duration(30.0)));
    Describe srv;
    ASSERT_TRUE(ros::service::call(name, srv));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
    const Ref6 y = loadRef6(r.file);
    ASSERT_EQ(srv.response.base_anchors.size(), 6u);
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_EQ(srv.response.base_anchors[i].x, y.base_anchors[i].x()) << r.ns << " " << i;
      EXPECT_EQ(srv.response.platform_anchors[i].y, y.platform_anchors[i].y()) << r.ns << " " << i;
    }
    EXPECT_EQ(srv.response.base_frame, r.ns.substr(1) + "/base_link");
    EXPECT_EQ(srv.response.platform_frame, r.ns.substr(1) + "/platform");
  }
}

TEST(Namespaces, EachNodeAnswersForItsOwnGeometry) {
  const auto core1 = coreBracket(kRobots[0]);
  const auto core2 = coreBracket(kRobots[1]);
  ASSERT_TRUE(core1.success) << core1.message;
  ASSERT_TRUE(core2.success) << core2.message;
  // The two geometries are told apart: some component's brackets are disjoint.
  std::vector<std::size_t> distinct;
  for (std::size_t k = 0; k < 6; ++k) {
    if (!overlap(core1.lower_bound, core1.upper_bound, core2.lower_bound, core2.upper_bound, k)) distinct.push_back(k);
  }
  ASSERT_FALSE(distinct.empty()) << "the fixture's two geometries give overlapping brackets";
  const pkm_accuracy::ros_layer::WorkspaceOutcome* own[2] = {&core1, &core2};
  for (int i = 0; i < 2; ++i) {
    const std::string name = kRobots[i].ns + "/verify_workspace";
    ASSERT_TRUE(ros::service::waitForService(name, ros::Duration(30.0)));
    VerifyWorkspace srv;
    srv.request = bracketRequest();
    ASSERT_TRUE(ros::service::call(name, srv));
    const auto& res = srv.response;
    ASSERT_TRUE(res.success) << name << ": " << res.message;
    const auto& mine = *own[i];
    const auto& other = *own[1 - i];
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_TRUE(overlap(res.lower_bound, res.upper_bound, mine.lower_bound, mine.upper_bound, k))
          << name << " component " << k << ": [" << res.lower_bound[k] << ", " << res.upper_bound[k]
          << "] against its geometry's [" << mine.lower_bound[k] << ", " << mine.upper_bound[k] << "]";
    }
    for (std::size_t k : distinct) {
      EXPECT_FALSE(overlap(res.lower_bound, res.upper_bound, other.lower_bound, other.upper_bound, k))
          << name << " component " << k << " answers for the other robot's geometry";
    }
  }
}

TEST(Namespaces, AnchorFramesCarryTheFramePrefix) {
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  for (const auto& r : kRobots) {
    const std::string prefix = r.ns.substr(1) + "/";
    const Ref6 y = loadRef6(r.file);
    for (int i = 1; i <= 6; ++i) {
      const auto base = buffer.lookupTransform(prefix + "base_link", prefix + "base_anchor_" + std::to_string(i),
                                               ros::Time(0), ros::Duration(10.0));
      EXPECT_EQ(base.transform.translation.x, y.base_anchors[i - 1].x()) << prefix << i;
      EXPECT_EQ(base.transform.translation.y, y.base_anchors[i - 1].y()) << prefix << i;
      const auto platform = buffer.lookupTransform(prefix + "platform", prefix + "platform_anchor_" + std::to_string(i),
                                                   ros::Time(0), ros::Duration(10.0));
      EXPECT_EQ(platform.transform.translation.x, y.platform_anchors[i - 1].x()) << prefix << i;
    }
  }
  EXPECT_FALSE(buffer._frameExists("base_anchor_1")) << "an unprefixed anchor frame is published";
  EXPECT_FALSE(buffer._frameExists("base_link"));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "namespaces_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
