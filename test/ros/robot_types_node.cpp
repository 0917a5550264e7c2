// rostest (robot_types.test): the node started on config/rus6.yaml (type rus6, a 6-RUS hexapod with rotary
// actuators) describes that robot and bounds its errors over the file's `reference` workspace exactly as the core
// does when it reads the same file (io::loadModelFile, independent of the parameter server).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"

namespace {

using pkm_accuracy::Describe;
using pkm_accuracy::VerifyWorkspace;

const std::string kFile = std::string(PKM_SOURCE_DIR) + "/config/rus6.yaml";

TEST(RobotTypes, DescribeNamesTheTypeItsJointsAndSensorErrors) {
  ASSERT_TRUE(ros::service::waitForService("/pkm_accuracy/describe", ros::Duration(20.0)));
  Describe srv;
  ASSERT_TRUE(ros::service::call("/pkm_accuracy/describe", srv));
  const auto& r = srv.response;
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.robot_type, "rus6");
  EXPECT_EQ(r.dof, 6u);
  EXPECT_TRUE(r.rigid_body_pose);
  EXPECT_EQ(r.pose_components,
            (std::vector<std::string>{"x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]"}));
  EXPECT_EQ(r.error_components,
            (std::vector<std::string>{"dx [m]", "dy [m]", "dz [m]", "drx [rad]", "dry [rad]", "drz [rad]"}));
  ASSERT_EQ(r.joints.size(), 6u);
  EXPECT_EQ(r.joints[2], "crank_2 [rad]");
  const pkm_accuracy::io::ModelFile file = pkm_accuracy::io::loadModelFile(kFile);
  ASSERT_EQ(r.sensor_error.size(), 6u);
  for (int j = 0; j < 6; ++j) EXPECT_EQ(r.sensor_error[j], file.description.sensor_error[j]);
  EXPECT_TRUE(r.base_anchors.empty());  // (Gough anchors only)
  EXPECT_EQ(r.workspaces, std::vector<std::string>{"reference"});
}

TEST(RobotTypes, MaxErrorOverTheNamedWorkspaceMatchesTheCore) {
  const pkm_accuracy::io::ModelFile file = pkm_accuracy::io::loadModelFile(kFile);
  pkm_accuracy::verify::VerifierOptions o;
  o.mode = pkm_accuracy::verify::Mode::MaxError;
  o.alpha = 0.01;
  o.threads = 1;
  const auto core = pkm_accuracy::verify::Verifier::run(*file.model, *file.workspaces.at("reference"), o);
  ASSERT_TRUE(core.converged);

  ASSERT_TRUE(ros::service::waitForService("/verify_workspace", ros::Duration(20.0)));
  VerifyWorkspace srv;
  srv.request.workspace = "reference";
  srv.request.mode = "max_error";
  srv.request.alpha = 0.01;
  ASSERT_TRUE(ros::service::call("/verify_workspace", srv));
  const auto& r = srv.response;
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.upper_bound.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    // Both are certified brackets of the same maximum: they overlap, each within 1%.
    EXPECT_LE(r.lower_bound[k], core.max_upper[k]) << k;
    EXPECT_LE(core.max_lower[k], r.upper_bound[k]) << k;
    EXPECT_LE(r.upper_bound[k], 1.0101 * r.lower_bound[k]) << k;
  }
  // Thresholds 5% above the maxima: SAFE; 5% below the certified lower bounds: UNSAFE.
  VerifyWorkspace v;
  v.request.workspace = "reference";
  for (int k = 0; k < 6; ++k) v.request.thresholds[k] = 1.05 * core.max_upper[k];
  ASSERT_TRUE(ros::service::call("/verify_workspace", v));
  EXPECT_EQ(v.response.verdict, "SAFE") << v.response.message;
  for (int k = 0; k < 6; ++k) v.request.thresholds[k] = 0.95 * core.max_lower[k];
  ASSERT_TRUE(ros::service::call("/verify_workspace", v));
  EXPECT_EQ(v.response.verdict, "UNSAFE") << v.response.message;
}

TEST(RobotTypes, APoseBoxIsTheBoxRegionWithItsAngleRanges) {
  // pose_min / pose_max (x, y, z, roll, pitch, yaw) of the reference workspace: the same search as the named one
  // (one thread), whose box region and angle ranges they are.
  const pkm_accuracy::io::ModelFile file = pkm_accuracy::io::loadModelFile(kFile);
  const pkm_accuracy::IVec& box = file.workspaces.at("reference")->initialBox();
  ASSERT_TRUE(ros::service::waitForService("/verify_workspace", ros::Duration(20.0)));
  VerifyWorkspace named;
  named.request.workspace = "reference";
  named.request.mode = "max_error";
  named.request.alpha = 0.05;
  named.request.threads = 1;
  VerifyWorkspace byBox;
  byBox.request = named.request;
  byBox.request.workspace.clear();
  for (int i = 0; i < 6; ++i) {
    byBox.request.pose_min.push_back(box[i].lower());
    byBox.request.pose_max.push_back(box[i].upper());
  }
  ASSERT_TRUE(ros::service::call("/verify_workspace", named));
  ASSERT_TRUE(ros::service::call("/verify_workspace", byBox));
  ASSERT_TRUE(named.response.success) << named.response.message;
  ASSERT_TRUE(byBox.response.success) << byBox.response.message;
  EXPECT_EQ(byBox.response.boxes, named.response.boxes);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(byBox.response.lower_bound[k], named.response.lower_bound[k]) << k;
    EXPECT_EQ(byBox.response.upper_bound[k], named.response.upper_bound[k]) << k;
  }
  EXPECT_EQ(byBox.response.argmax_poses.size(), 6u);  // (a rigid-body pose)
  // A wrong length is refused naming the field.
  byBox.request.pose_max.pop_back();
  ASSERT_TRUE(ros::service::call("/verify_workspace", byBox));
  EXPECT_FALSE(byBox.response.success);
  EXPECT_NE(byBox.response.message.find("pose_max"), std::string::npos) << byBox.response.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "robot_types_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
