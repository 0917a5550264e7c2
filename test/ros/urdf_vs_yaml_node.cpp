// rostest (urdf_vs_yaml.test): two nodes, one on config/ref6.yaml and one on urdf/ref6.urdf, describe the same
// anchors; plus unit tests of loadGoughGeometryFromUrdf (fixed-joint chains, numbering, error messages).
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <urdf/model.h>
#include <Eigen/Geometry>

#include "Ref6.hpp"
#include "pkm_accuracy/Describe.h"
#include "pkm_accuracy/ros/RobotLoader.hpp"

namespace {

using pkm_accuracy::Describe;
using pkm_accuracy::model::GoughGeometry;
using pkm_accuracy::ros_layer::loadGoughGeometryFromUrdf;
using pkm_accuracy::ros_layer::UrdfAnchorNames;

Describe::Response describe(const std::string& node) {
  const std::string name = "/" + node + "/describe";
  EXPECT_TRUE(ros::service::waitForService(name, ros::Duration(20.0))) << name;
  Describe srv;
  EXPECT_TRUE(ros::service::call(name, srv)) << name;
  return srv.response;
}

Eigen::Matrix3d rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::string fixedJoint(const std::string& parent, const std::string& child, const Eigen::Vector3d& xyz,
                       const Eigen::Vector3d& rpy_angles, const std::string& type = "fixed") {
  std::ostringstream os;
  os.precision(17);
  os << "<link name='" << child << "'/><joint name='" << child << "_joint' type='" << type << "'><parent link='"
     << parent << "'/><child link='" << child << "'/><origin xyz='" << xyz.x() << ' ' << xyz.y() << ' ' << xyz.z()
     << "' rpy='" << rpy_angles.x() << ' ' << rpy_angles.y() << ' ' << rpy_angles.z() << "'/>"
     << (type == "revolute" ? "<axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/>" : "")
     << "</joint>";
  return os.str();
}

/// A URDF with anchors a0..a5 under base -> plate (rotated, translated) and p0..p5 under top -> mount.
struct ChainUrdf {
  Eigen::Vector3d plate_xyz{0.1, -0.2, 0.3}, plate_rpy{0.1, -0.2, 0.3};
  Eigen::Vector3d mount_xyz{0.0, 0.01, -0.02}, mount_rpy{0.0, 0.0, M_PI / 2};
  std::vector<Eigen::Vector3d> a, p;
  ChainUrdf() {
    for (int i = 0; i < 6; ++i) {
      const double t = i * M_PI / 3;
      a.emplace_back(0.2 * std::cos(t), 0.2 * std::sin(t), 0.01 * i);
      p.emplace_back(0.1 * std::cos(t + 0.3), 0.1 * std::sin(t + 0.3), -0.005 * i);
    }
  }
  std::string xml(const std::string& a3_joint_type = "fixed", bool p5_under_base = false) const {
    std::string s = "<robot name='chain'><link name='base'/><link name='top'/>";
    s += "<joint name='float' type='floating'><parent link='base'/><child link='top'/></joint>";
    s += fixedJoint("base", "plate", plate_xyz, plate_rpy);
    s += fixedJoint("top", "mount", mount_xyz, mount_rpy);
    for (int i = 0; i < 6; ++i) {
      s += fixedJoint("plate", "a" + std::to_string(i), a[i], Eigen::Vector3d(0.3, 0.2, 0.1),
                      i == 3 ? a3_joint_type : "fixed");
      s += fixedJoint(i == 5 && p5_under_base ? "base" : "mount", "p" + std::to_string(i), p[i],
                      Eigen::Vector3d::Zero());
    }
    return s + "</robot>";
  }
  static UrdfAnchorNames names() {
    UrdfAnchorNames n;
    n.base_link = "base";
    n.platform_link = "top";
    n.base_anchor_pattern = "a%d";
    n.platform_anchor_pattern = "p%d";
    n.first_index = 0;
    return n;
  }
};

TEST(UrdfLoader, ComposesFixedJointChains) {
  ChainUrdf c;
  urdf::Model model;
  ASSERT_TRUE(model.initString(c.xml()));
  GoughGeometry g;
  g.sensor_error.assign(6, 3e-5);  // untouched by the URDF loader
  std::string error;
  ASSERT_TRUE(loadGoughGeometryFromUrdf(model, ChainUrdf::names(), g, error)) << error;
  const Eigen::Matrix3d rp = rpy(c.plate_rpy.x(), c.plate_rpy.y(), c.plate_rpy.z());
  const Eigen::Matrix3d rm = rpy(c.mount_rpy.x(), c.mount_rpy.y(), c.mount_rpy.z());
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT((g.base_anchors[i] - (c.plate_xyz + rp * c.a[i])).norm(), 1e-12) << i;
    EXPECT_LT((g.platform_anchors[i] - (c.mount_xyz + rm * c.p[i])).norm(), 1e-12) << i;
    EXPECT_EQ(g.sensor_error[i], 3e-5);
  }
}

TEST(UrdfLoader, ErrorsNameTheLinkOrJoint) {
  ChainUrdf c;
  std::string error;
  GoughGeometry g;
  urdf::Model ok;
  ASSERT_TRUE(ok.initString(c.xml()));

  UrdfAnchorNames one_based = ChainUrdf::names();
  one_based.first_index = 1;  // the URDF numbers 0..5: a6 does not exist
  EXPECT_FALSE(loadGoughGeometryFromUrdf(ok, one_based, g, error));
  EXPECT_NE(error.find("'a6'"), std::string::npos) << error;
  EXPECT_NE(error.find("not found"), std::string::npos) << error;

  UrdfAnchorNames bad_pattern = ChainUrdf::names();
  bad_pattern.platform_anchor_pattern = "p%s";
  EXPECT_FALSE(loadGoughGeometryFromUrdf(ok, bad_pattern, g, error));
  EXPECT_NE(error.find("p%s"), std::string::npos) << error;

  UrdfAnchorNames bad_base = ChainUrdf::names();
  bad_base.base_link = "ground";
  EXPECT_FALSE(loadGoughGeometryFromUrdf(ok, bad_base, g, error));
  EXPECT_NE(error.find("'ground'"), std::string::npos) << error;

  urdf::Model movable;
  ASSERT_TRUE(movable.initString(c.xml("revolute")));
  EXPECT_FALSE(loadGoughGeometryFromUrdf(movable, ChainUrdf::names(), g, error));
  EXPECT_NE(error.find("'a3_joint'"), std::string::npos) << error;
  EXPECT_NE(error.find("fixed"), std::string::npos) << error;

  urdf::Model wrong_parent;
  ASSERT_TRUE(wrong_parent.initString(c.xml("fixed", true)));
  EXPECT_FALSE(loadGoughGeometryFromUrdf(wrong_parent, ChainUrdf::names(), g, error));
  EXPECT_NE(error.find("'p5'"), std::string::npos) << error;
  EXPECT_NE(error.find("descendant of link 'top'"), std::string::npos) << error;
  EXPECT_TRUE(g.base_anchors.empty()) << "out must be untouched on failure";
}

TEST(UrdfLoader, Ref6UrdfFileHasExactlyTheYamlAnchors) {
  const auto ref = pkm_accuracy_test::loadRef6();
  urdf::Model model;
  ASSERT_TRUE(model.initFile(pkm_accuracy_test::sourcePath("urdf/ref6.urdf")));
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometryFromUrdf(model, UrdfAnchorNames(), g, error)) << error;
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(g.base_anchors[i], ref.base_anchors[i]) << i;
    EXPECT_EQ(g.platform_anchors[i], ref.platform_anchors[i]) << i;
  }
}

TEST(UrdfVsYaml, BothNodesDescribeTheSameRobot) {
  const auto ref = pkm_accuracy_test::loadRef6();
  const Describe::Response y = describe("pkm_yaml");
  const Describe::Response u = describe("pkm_urdf");
  ASSERT_TRUE(y.success) << y.message;
  ASSERT_TRUE(u.success) << u.message;
  EXPECT_EQ(y.robot_source, "yaml");
  EXPECT_EQ(u.robot_source, "urdf");
  EXPECT_EQ(u.base_frame, y.base_frame);
  EXPECT_EQ(u.platform_frame, y.platform_frame);
  ASSERT_EQ(u.base_anchors.size(), 6u);
  ASSERT_EQ(u.platform_anchors.size(), 6u);
  ASSERT_EQ(y.base_anchors.size(), 6u);
  ASSERT_EQ(y.platform_anchors.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(u.base_anchors[i], y.base_anchors[i]) << i;
    EXPECT_EQ(u.platform_anchors[i], y.platform_anchors[i]) << i;
    EXPECT_EQ(u.base_anchors[i].x, ref.base_anchors[i].x()) << i;
    EXPECT_EQ(u.base_anchors[i].y, ref.base_anchors[i].y()) << i;
    EXPECT_EQ(u.platform_anchors[i].x, ref.platform_anchors[i].x()) << i;
    EXPECT_EQ(u.platform_anchors[i].y, ref.platform_anchors[i].y()) << i;
  }
  EXPECT_EQ(u.sensor_error, y.sensor_error);  // the URDF node has one scalar ~sensor_error for all legs
  EXPECT_EQ(u.tool_point, y.tool_point);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "urdf_vs_yaml_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
