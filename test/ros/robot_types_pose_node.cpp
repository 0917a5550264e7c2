// rostest (robot_types_delta3.test, robot_types_prs3.test, robot_types_planar3rpr.test): the node started on a robot
// whose pose is not the rigid-body pose (x, y, z, roll, pitch, yaw) -- a delta3 (pose x, y, z), a prs3 (pose z, tilt_x,
// tilt_y) or a planar3rpr (pose x, y, theta, with a disc workspace too) -- with its
// robot file (private parameter ~robot_file of this test) loaded as the node's parameters. The oracle is the core
// reading the same file (io::loadModelFile, independent of the parameter server) and run directly:
// - ~describe gives the file's type, dof, pose and error components, joints, sensor errors and workspaces;
// - max_error over every named workspace: the node's bracket overlaps the core's;
// - max_error over the named workspace `reference`: the node's bracket and the core's are certified brackets of the
//   same maxima (they overlap, each within alpha); the 6-number vectors hold the n components, then zeros;
// - verify with thresholds 1.05 x the node's upper bounds: SAFE, and 0.95 x its lower bounds: UNSAFE, as the core
//   says on the same thresholds;
// - the same workspace given as pose_min / pose_max gives the same bracket as the named one (one thread: the same
//   search);
// - refusals name the field: a threshold beyond the robot's n components, pose_min / pose_max of the wrong length,
//   region fields, another frame_id; trajectories and varieties name the type and the service.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/VerifyTrajectory.h"
#include "pkm_accuracy/VerifyVariety.h"
#include "pkm_accuracy/VerifyWorkspace.h"
#include "pkm_accuracy/core/domain/Domain.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"

namespace {

using pkm_accuracy::Describe;
using pkm_accuracy::VerifyTrajectory;
using pkm_accuracy::VerifyVariety;
using pkm_accuracy::VerifyWorkspace;
namespace verify = pkm_accuracy::verify;

constexpr double kAlpha = 0.01;

std::string robotFile() {
  std::string path;
  ros::NodeHandle("~").getParam("robot_file", path);
  return path;
}

const pkm_accuracy::io::ModelFile& file() {
  static const pkm_accuracy::io::ModelFile f = pkm_accuracy::io::loadModelFile(robotFile());
  return f;
}

std::size_t dof() { return static_cast<std::size_t>(file().model->dof()); }

const pkm_accuracy::domain::Domain& reference() { return *file().workspaces.at("reference"); }

VerifyWorkspace::Response call(const VerifyWorkspace::Request& req) {
  EXPECT_TRUE(ros::service::waitForService("/verify_workspace", ros::Duration(20.0)));
  VerifyWorkspace srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::call("/verify_workspace", srv));  // (transport success even for refused requests)
  return srv.response;
}

VerifyWorkspace::Request maxErrorRequest() {
  VerifyWorkspace::Request r;
  r.workspace = "reference";
  r.mode = "max_error";
  r.alpha = kAlpha;
  r.threads = 1;
  r.time_budget = 60.0;
  return r;
}

/// The core's verdict on the reference workspace for thresholds (n numbers).
verify::Verdict coreVerdict(const std::vector<double>& thresholds) {
  verify::VerifierOptions o;
  o.thresholds = pkm_accuracy::DVec(static_cast<int>(thresholds.size()));
  for (std::size_t k = 0; k < thresholds.size(); ++k) o.thresholds[static_cast<int>(k)] = thresholds[k];
  o.threads = 1;
  return verify::Verifier::run(*file().model, reference(), o).verdict;
}

void expectRefused(const VerifyWorkspace::Response& r, const std::string& field) {
  EXPECT_FALSE(r.success) << field;
  EXPECT_EQ(r.job_id, 0u) << field;
  EXPECT_NE(r.message.find(field), std::string::npos) << "expected the message to name " << field << ": " << r.message;
}

TEST(RobotTypesPose, DescribeGivesTheRobotsOwnCoordinates) {
  ASSERT_TRUE(ros::service::waitForService("/pkm_accuracy/describe", ros::Duration(20.0)));
  Describe srv;
  ASSERT_TRUE(ros::service::call("/pkm_accuracy/describe", srv));
  const auto& r = srv.response;
  ASSERT_TRUE(r.success) << r.message;
  const auto& d = file().description;
  EXPECT_EQ(r.robot_type, file().type);
  EXPECT_EQ(r.dof, dof());
  EXPECT_FALSE(r.rigid_body_pose);
  ASSERT_EQ(r.pose_components.size(), dof());
  ASSERT_EQ(r.error_components.size(), dof());
  ASSERT_EQ(r.joints.size(), dof());
  ASSERT_EQ(r.sensor_error.size(), dof());
  for (std::size_t k = 0; k < dof(); ++k) {
    EXPECT_EQ(r.pose_components[k], d.pose[k].name + " [" + d.pose[k].unit + "]");
    EXPECT_EQ(r.error_components[k], d.pose[k].errorName() + " [" + d.pose[k].unit + "]");
    EXPECT_EQ(r.joints[k], d.joints[k].name + " [" + d.joints[k].unit + "]");
    EXPECT_EQ(r.sensor_error[k], d.sensor_error[k]);
  }
  EXPECT_TRUE(r.base_anchors.empty());
  std::vector<std::string> names;
  for (const auto& w : file().workspaces) names.push_back(w.first);  // (a std::map: sorted)
  EXPECT_EQ(r.workspaces, names);
}

TEST(RobotTypesPose, EveryNamedWorkspaceIsTheFilesOne) {
  // max_error over each named workspace of the file (planar3rpr: also its disc): the node's and the core's brackets
  // of the same maxima overlap.
  for (const auto& [name, domain] : file().workspaces) {
    verify::VerifierOptions o;
    o.mode = verify::Mode::MaxError;
    o.alpha = kAlpha;
    o.threads = 1;
    const verify::VerifierResult core = verify::Verifier::run(*file().model, *domain, o);
    VerifyWorkspace::Request req = maxErrorRequest();
    req.workspace = name;
    const VerifyWorkspace::Response r = call(req);
    ASSERT_TRUE(r.success) << name << ": " << r.message;
    EXPECT_EQ(r.converged, core.converged) << name;
    for (std::size_t k = 0; k < dof(); ++k) {
      EXPECT_LE(r.lower_bound[k], core.max_upper[static_cast<int>(k)]) << name << ", " << k;
      EXPECT_LE(core.max_lower[static_cast<int>(k)], r.upper_bound[k]) << name << ", " << k;
    }
  }
}

TEST(RobotTypesPose, MaxErrorAndVerdictsAgreeWithTheCore) {
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = kAlpha;
  o.threads = 1;
  const verify::VerifierResult core = verify::Verifier::run(*file().model, reference(), o);
  ASSERT_TRUE(core.converged);

  const VerifyWorkspace::Response r = call(maxErrorRequest());
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.converged) << r.message;
  const pkm_accuracy::IVec& box = reference().initialBox();
  for (std::size_t k = 0; k < 6; ++k) {
    if (k >= dof()) {
      // Beyond the robot's components: zeros.
      EXPECT_EQ(r.lower_bound[k], 0.0) << k;
      EXPECT_EQ(r.upper_bound[k], 0.0) << k;
      continue;
    }
    const int i = static_cast<int>(k);
    // Both are certified brackets of the same maximum: they overlap, and each is within alpha.
    EXPECT_LE(r.lower_bound[k], core.max_upper[i]) << k;
    EXPECT_LE(core.max_lower[i], r.upper_bound[k]) << k;
    EXPECT_GT(r.lower_bound[k], 0.0) << k;
    EXPECT_LE(r.upper_bound[k], (1.0 + kAlpha) * r.lower_bound[k] * (1.0 + 1e-12)) << k;
  }
  // Row k of lower_bound_poses: a pose of the workspace (its n coordinates, then zeros).
  ASSERT_EQ(r.lower_bound_poses.size(), 36u);
  for (std::size_t k = 0; k < dof(); ++k) {
    for (std::size_t i = 0; i < 6; ++i) {
      const double v = r.lower_bound_poses[6 * k + i];
      if (i >= dof()) {
        EXPECT_EQ(v, 0.0) << k << ", " << i;
      } else {
        EXPECT_GE(v, box[static_cast<int>(i)].lower()) << k << ", " << i;
        EXPECT_LE(v, box[static_cast<int>(i)].upper()) << k << ", " << i;
      }
    }
  }
  EXPECT_TRUE(r.argmax_poses.empty());  // (rigid-body poses only)

  // Thresholds 5% above the node's upper bounds: SAFE; 5% below its lower bounds: UNSAFE; the core agrees.
  VerifyWorkspace::Request v;
  v.workspace = "reference";
  v.threads = 1;
  v.time_budget = 60.0;
  std::vector<double> above, below;
  for (std::size_t k = 0; k < dof(); ++k) {
    above.push_back(1.05 * r.upper_bound[k]);
    below.push_back(0.95 * r.lower_bound[k]);
  }
  for (std::size_t k = 0; k < dof(); ++k) v.thresholds[k] = above[k];
  const VerifyWorkspace::Response safe = call(v);
  ASSERT_TRUE(safe.success) << safe.message;
  EXPECT_EQ(safe.verdict, "SAFE") << safe.message;
  EXPECT_EQ(coreVerdict(above), verify::Verdict::Safe);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(safe.upper_bound[k], k < dof() ? above[k] : 0.0) << k;

  for (std::size_t k = 0; k < dof(); ++k) v.thresholds[k] = below[k];
  const VerifyWorkspace::Response unsafe = call(v);
  ASSERT_TRUE(unsafe.success) << unsafe.message;
  EXPECT_EQ(unsafe.verdict, "UNSAFE") << unsafe.message;
  EXPECT_EQ(coreVerdict(below), verify::Verdict::Unsafe);
  ASSERT_TRUE(unsafe.has_witness);
  ASSERT_GE(unsafe.witness_component, 0);
  const auto c = static_cast<std::size_t>(unsafe.witness_component);
  ASSERT_LT(c, dof());
  EXPECT_GT(unsafe.witness_error[c], below[c]);
  for (std::size_t i = 0; i < 6; ++i) {
    if (i >= dof()) {
      EXPECT_EQ(unsafe.witness_pose[i], 0.0) << i;
      EXPECT_EQ(unsafe.witness_error[i], 0.0) << i;
    } else {
      EXPECT_GE(unsafe.witness_pose[i], box[static_cast<int>(i)].lower()) << i;
      EXPECT_LE(unsafe.witness_pose[i], box[static_cast<int>(i)].upper()) << i;
    }
  }
  EXPECT_EQ(unsafe.witness.orientation.w, 1.0);  // identity: not a rigid-body pose
}

TEST(RobotTypesPose, APoseBoxRequestIsTheNamedWorkspace) {
  const pkm_accuracy::IVec& box = reference().initialBox();
  VerifyWorkspace::Request byBox = maxErrorRequest();
  byBox.workspace.clear();
  for (int i = 0; i < box.size(); ++i) {
    byBox.pose_min.push_back(box[i].lower());
    byBox.pose_max.push_back(box[i].upper());
  }
  const VerifyWorkspace::Response a = call(byBox);
  const VerifyWorkspace::Response b = call(maxErrorRequest());
  ASSERT_TRUE(a.success) << a.message;
  ASSERT_TRUE(b.success) << b.message;
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(a.lower_bound[k], b.lower_bound[k]) << k;
    EXPECT_EQ(a.upper_bound[k], b.upper_bound[k]) << k;
  }
  EXPECT_EQ(a.boxes, b.boxes);
}

TEST(RobotTypesPose, RefusalsNameTheField) {
  const std::size_t n = dof();
  VerifyWorkspace::Request ok;
  ok.workspace = "reference";
  for (std::size_t k = 0; k < n; ++k) ok.thresholds[k] = 1.0;

  VerifyWorkspace::Request r = ok;
  r.thresholds[n] = 1e-3;  // beyond the robot's components
  expectRefused(call(r), "thresholds[" + std::to_string(n) + "]");
  r = ok;
  r.mode = "max_error";
  r.thresholds[n] = 1e-3;  // (max_error: not "all 0" either)
  expectRefused(call(r), "thresholds[" + std::to_string(n) + "]");
  r = ok;
  r.thresholds[0] = 0.0;
  expectRefused(call(r), "thresholds[0]");

  const pkm_accuracy::IVec& box = reference().initialBox();
  VerifyWorkspace::Request byBox = ok;
  byBox.workspace.clear();
  for (int i = 0; i < box.size(); ++i) {
    byBox.pose_min.push_back(box[i].lower());
    byBox.pose_max.push_back(box[i].upper());
  }
  r = byBox;
  r.pose_min.pop_back();
  expectRefused(call(r), "pose_min");
  r = byBox;
  r.pose_max.push_back(0.0);
  expectRefused(call(r), "pose_max");
  r = byBox;
  std::swap(r.pose_min[0], r.pose_max[0]);
  expectRefused(call(r), "pose_min[0]");
  r = byBox;
  r.frame_id = "world";  // (the robot's own coordinates: no other frame)
  expectRefused(call(r), "frame_id");
  r = ok;
  r.pose_min = byBox.pose_min;  // both a name and a box
  r.pose_max = byBox.pose_max;
  expectRefused(call(r), "pose_min");
  r = byBox;
  r.region_type = "box";  // the rigid-body region fields
  expectRefused(call(r), "region_type");
  r = ok;
  r.workspace.clear();  // no workspace at all
  expectRefused(call(r), "pose_min");

  // Still serving.
  const VerifyWorkspace::Response fine = call(byBox);
  EXPECT_TRUE(fine.success) << fine.message;
}

TEST(RobotTypesPose, TrajectoriesAndVarietiesAreRefusedNamingTheTypeAndTheService) {
  ASSERT_TRUE(ros::service::waitForService("/verify_trajectory", ros::Duration(20.0)));
  VerifyTrajectory t;
  t.request.times = {0.0, 1.0};
  t.request.x = t.request.y = t.request.z = t.request.roll = t.request.pitch = t.request.yaw = {0.0, 0.0};
  t.request.thresholds = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  ASSERT_TRUE(ros::service::call("/verify_trajectory", t));
  EXPECT_FALSE(t.response.success);
  EXPECT_NE(t.response.message.find(file().type), std::string::npos) << t.response.message;
  EXPECT_NE(t.response.message.find("verify_trajectory"), std::string::npos) << t.response.message;

  ASSERT_TRUE(ros::service::waitForService("/verify_variety", ros::Duration(20.0)));
  VerifyVariety v;
  v.request.parameters = 1;
  ASSERT_TRUE(ros::service::call("/verify_variety", v));
  EXPECT_FALSE(v.response.success);
  EXPECT_NE(v.response.message.find(file().type), std::string::npos) << v.response.message;
  EXPECT_NE(v.response.message.find("verify_variety"), std::string::npos) << v.response.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "robot_types_pose_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
