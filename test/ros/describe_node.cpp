// rostest (describe.test): the node started on config/ref6.yaml describes exactly the reference robot, publishes
// its anchor frames on /tf_static, advertises /verify_workspace (answered by the verifier) and survives bad
// requests.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "Ref6.hpp"
#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/Version.hpp"

namespace {

using pkm_accuracy::Describe;
using pkm_accuracy::VerifyWorkspace;

const char* const kDescribe = "/pkm_accuracy/describe";
const double kNaN = std::numeric_limits<double>::quiet_NaN();

Describe::Response describe() {
  EXPECT_TRUE(ros::service::waitForService(kDescribe, ros::Duration(20.0)));
  Describe srv;
  EXPECT_TRUE(ros::service::call(kDescribe, srv));
  return srv.response;
}

/// A valid request: the `paper` workspace of config/ref6.yaml with thresholds.
VerifyWorkspace::Request paperRequest() {
  VerifyWorkspace::Request r;
  r.region_type = "box";
  r.box_min = {-0.15, -0.15, 0.45};
  r.box_max = {0.15, 0.15, 0.50};
  const double a = 15.0 * M_PI / 180.0;
  r.roll_min = r.pitch_min = r.yaw_min = -a;
  r.roll_max = r.pitch_max = r.yaw_max = a;
  r.thresholds = {1e-4, 1e-4, 1e-4, 1e-3, 1e-3, 1e-3};
  r.mode = "verify";
  return r;
}

VerifyWorkspace::Response verify(const VerifyWorkspace::Request& req) {
  EXPECT_TRUE(ros::service::waitForService("/verify_workspace", ros::Duration(20.0)));
  VerifyWorkspace srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call("/verify_workspace", srv));  // transport success even for bad requests
  return srv.response;
}

TEST(Describe, ReturnsExactlyTheReferenceRobot) {
  const auto ref = pkm_accuracy_test::loadRef6();
  const Describe::Response r = describe();
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.robot_source, "yaml");
  EXPECT_EQ(r.version, pkm_accuracy::version());
  EXPECT_FALSE(r.version.empty());
  EXPECT_EQ(r.base_frame, "base_link");
  EXPECT_EQ(r.platform_frame, "platform");
  ASSERT_EQ(r.base_anchors.size(), 6u);
  ASSERT_EQ(r.platform_anchors.size(), 6u);
  ASSERT_EQ(r.sensor_error.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(r.base_anchors[i].x, ref.base_anchors[i].x()) << "leg " << i;
    EXPECT_EQ(r.base_anchors[i].y, ref.base_anchors[i].y()) << "leg " << i;
    EXPECT_EQ(r.base_anchors[i].z, ref.base_anchors[i].z()) << "leg " << i;
    EXPECT_EQ(r.platform_anchors[i].x, ref.platform_anchors[i].x()) << "leg " << i;
    EXPECT_EQ(r.platform_anchors[i].y, ref.platform_anchors[i].y()) << "leg " << i;
    EXPECT_EQ(r.platform_anchors[i].z, ref.platform_anchors[i].z()) << "leg " << i;
    EXPECT_EQ(r.sensor_error[i], ref.sensor_error[i]) << "leg " << i;
  }
  // Guard against the oracle and the node agreeing on a wrong reading: two literal values of config/ref6.yaml.
  EXPECT_EQ(r.base_anchors[2].x, 0.1276);
  EXPECT_EQ(r.platform_anchors[5].y, -0.01052);
  EXPECT_EQ(r.tool_point.x, ref.tool_point.x());
  EXPECT_EQ(r.tool_point.y, ref.tool_point.y());
  EXPECT_EQ(r.tool_point.z, ref.tool_point.z());
  EXPECT_TRUE(r.base_anchor_halfwidth.empty());
  EXPECT_TRUE(r.platform_anchor_halfwidth.empty());
  EXPECT_EQ(r.tool_point_halfwidth.x, 0.0);
  EXPECT_EQ(r.tool_point_halfwidth.y, 0.0);
  EXPECT_EQ(r.tool_point_halfwidth.z, 0.0);
  EXPECT_TRUE(r.geometry_parameters.empty());  // no anchor uncertainty (uncertainty.test has some)
}

TEST(Describe, AnchorFramesAreOnTfStatic) {
  const auto ref = pkm_accuracy_test::loadRef6();
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  for (int i = 1; i <= 6; ++i) {
    const std::string a = "base_anchor_" + std::to_string(i);
    const std::string b = "platform_anchor_" + std::to_string(i);
    const auto ta = buffer.lookupTransform("base_link", a, ros::Time(0), ros::Duration(10.0));
    EXPECT_EQ(ta.transform.translation.x, ref.base_anchors[i - 1].x()) << a;
    EXPECT_EQ(ta.transform.translation.y, ref.base_anchors[i - 1].y()) << a;
    EXPECT_EQ(ta.transform.translation.z, ref.base_anchors[i - 1].z()) << a;
    EXPECT_EQ(ta.transform.rotation.w, 1.0) << a;
    const auto tb = buffer.lookupTransform("platform", b, ros::Time(0), ros::Duration(10.0));
    EXPECT_EQ(tb.transform.translation.x, ref.platform_anchors[i - 1].x()) << b;
    EXPECT_EQ(tb.transform.translation.y, ref.platform_anchors[i - 1].y()) << b;
    EXPECT_EQ(tb.transform.translation.z, ref.platform_anchors[i - 1].z()) << b;
  }
}

TEST(VerifyWorkspace, IsAdvertisedWithAGlobalNameAndAnswersAValidRequest) {
  // The paper workspace with the paper's thresholds: the verifier finds a violating pose at once (verify_node.cpp
  // checks the results in detail).
  const auto r = verify(paperRequest());
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.verdict, "UNSAFE") << r.message;
  EXPECT_TRUE(r.has_witness);
  EXPECT_GT(r.job_id, 0u);
}

struct BadCase {
  const char* field;
  void (*mutate)(VerifyWorkspace::Request&);
};

TEST(VerifyWorkspace, BadRequestsAreRefusedNamingTheFieldAndTheNodeSurvives) {
  const BadCase cases[] = {
      {"region_type", [](VerifyWorkspace::Request& r) { r.region_type = "cube"; }},
      {"box_min[2]", [](VerifyWorkspace::Request& r) { r.box_min[2] = 0.6; }},
      {"box_max[0]", [](VerifyWorkspace::Request& r) { r.box_max[0] = kNaN; }},
      {"radius",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "sphere";
         r.radius = -1.0;
       }},
      {"z_min",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "cylinder";
         r.radius = 0.1;
         r.z_min = 1.0;
       }},
      {"halfspace_offsets",
       [](VerifyWorkspace::Request& r) {
         r.region_type = "polyhedron";
         r.halfspace_normals.resize(2);
         r.halfspace_normals[0].x = r.halfspace_normals[1].z = 1.0;
         r.halfspace_offsets = {0.1};
       }},
      {"halfspace_normals", [](VerifyWorkspace::Request& r) { r.halfspace_normals.resize(1); }},
      {"pitch_min", [](VerifyWorkspace::Request& r) { r.pitch_min = 1.0; }},
      {"thresholds[3]", [](VerifyWorkspace::Request& r) { r.thresholds[3] = -1.0; }},
      {"thresholds[0]", [](VerifyWorkspace::Request& r) { r.thresholds[0] = kNaN; }},
      {"mode", [](VerifyWorkspace::Request& r) { r.mode = "fast"; }},
      {"alpha", [](VerifyWorkspace::Request& r) { r.alpha = -0.5; }},
      {"time_budget", [](VerifyWorkspace::Request& r) { r.time_budget = -2.0; }},
      {"min_width", [](VerifyWorkspace::Request& r) { r.min_width = kNaN; }},
      {"frame_id", [](VerifyWorkspace::Request& r) { r.frame_id = "world"; }},
      {"geometry_splitting", [](VerifyWorkspace::Request& r) { r.geometry_splitting = "sometimes"; }},
  };
  for (const auto& c : cases) {
    VerifyWorkspace::Request req = paperRequest();
    c.mutate(req);
    const auto r = verify(req);
    EXPECT_FALSE(r.success) << c.field;
    EXPECT_NE(r.message.find(c.field), std::string::npos)
        << "expected the message to name " << c.field << ": " << r.message;
    EXPECT_EQ(r.verdict, "") << c.field;
  }
  // max_error mode without thresholds is valid (here on a small sub-box of the paper workspace, decided at once);
  // the node is still alive and still describes the robot.
  VerifyWorkspace::Request req = paperRequest();
  req.box_min = {-0.01, -0.01, 0.47};
  req.box_max = {0.01, 0.01, 0.48};
  req.roll_min = req.pitch_min = req.yaw_min = -0.01;
  req.roll_max = req.pitch_max = req.yaw_max = 0.01;
  req.mode = "max_error";
  req.alpha = 0.5;
  req.thresholds = {0, 0, 0, 0, 0, 0};
  const auto r = verify(req);
  EXPECT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.message.find("invalid request"), std::string::npos) << r.message;
  EXPECT_TRUE(describe().success);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "describe_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
