// rostest (loader.test): loadGoughGeometry() and friends on parameters set with ros::param::set, one namespace per
// case: valid input (the reference robot loaded by the .test file, scalars, integers, options) and invalid input
// (the message must name the parameter, the expected and the actual value). Also: a node whose robot cannot be
// loaded refuses to start.
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "Ref6.hpp"
#include "pkm_accuracy/ros/AccuracyCheckerNode.hpp"
#include "pkm_accuracy/ros/RobotLoader.hpp"

namespace {

using pkm_accuracy::model::GoughGeometry;
using pkm_accuracy::ros_layer::loadGoughGeometry;
using pkm_accuracy::ros_layer::loadRobotFrames;
using pkm_accuracy::ros_layer::loadUrdfAnchorNames;
using pkm_accuracy::ros_layer::RobotFrames;
using pkm_accuracy::ros_layer::UrdfAnchorNames;

XmlRpc::XmlRpcValue list(const std::vector<double>& v) {
  XmlRpc::XmlRpcValue x;
  x.setSize(static_cast<int>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) x[static_cast<int>(i)] = v[i];
  return x;
}

XmlRpc::XmlRpcValue points(const std::vector<Eigen::Vector3d>& pts) {
  XmlRpc::XmlRpcValue x;
  x.setSize(static_cast<int>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) x[static_cast<int>(i)] = list({pts[i].x(), pts[i].y(), pts[i].z()});
  return x;
}

/// Sets the reference robot under /loader_test/<ns>/ and returns the private node handle of that namespace.
ros::NodeHandle refRobotIn(const std::string& ns) {
  const auto ref = pkm_accuracy_test::loadRef6();
  ros::NodeHandle nh("~" + ns);
  nh.setParam("base_anchors", points(ref.base_anchors));
  nh.setParam("platform_anchors", points(ref.platform_anchors));
  nh.setParam("sensor_error", list(ref.sensor_error));
  return nh;
}

/// Expects loading to fail with a message containing every one of `parts`.
void expectFailure(const ros::NodeHandle& nh, const std::vector<std::string>& parts) {
  GoughGeometry g;
  std::string error;
  EXPECT_FALSE(loadGoughGeometry(nh, g, error)) << nh.getNamespace();
  for (const auto& p : parts) {
    EXPECT_NE(error.find(p), std::string::npos) << "expected \"" << p << "\" in: " << error;
  }
  EXPECT_TRUE(g.base_anchors.empty()) << "out must be untouched on failure";
}

TEST(Loader, ReferenceRobotFromTheYamlFileLoadsExactly) {
  // loader.test loads config/ref6.yaml into ~ref6 with <rosparam file=...>: the file's format loads as is.
  const auto ref = pkm_accuracy_test::loadRef6();
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometry(ros::NodeHandle("~ref6"), g, error)) << error;
  ASSERT_EQ(g.legCount(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(g.base_anchors[i], ref.base_anchors[i]) << i;
    EXPECT_EQ(g.platform_anchors[i], ref.platform_anchors[i]) << i;
    EXPECT_EQ(g.sensor_error[i], ref.sensor_error[i]) << i;
  }
  EXPECT_EQ(g.tool_point, ref.tool_point);
  EXPECT_FALSE(g.hasUncertainty());
  RobotFrames f;
  ASSERT_TRUE(loadRobotFrames(ros::NodeHandle("~ref6"), f, error)) << error;
  EXPECT_EQ(f.base_frame, "base_link");
  EXPECT_EQ(f.platform_frame, "platform");
}

TEST(Loader, ScalarSensorErrorIntegersAndOptionalParameters) {
  ros::NodeHandle nh = refRobotIn("options");
  nh.setParam("sensor_error", 2.5e-5);
  XmlRpc::XmlRpcValue ints =
      points({{-97, 91, 0}, {97, 91, 0}, {128, 39, 0}, {31, -129, 0}, {-31, -129, 0}, {-128, 39, 0}});
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) ints[i][k] = static_cast<int>(static_cast<double>(ints[i][k]));  // as integers
  nh.setParam("base_anchors", ints);
  nh.setParam("tool_point", list({0.0, 0.0, 0.1}));
  nh.setParam("anchor_uncertainty", 0.001);
  nh.setParam("base_frame", std::string("world"));
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometry(nh, g, error)) << error;
  EXPECT_EQ(g.sensor_error, std::vector<double>(6, 2.5e-5));
  EXPECT_EQ(g.base_anchors[2], Eigen::Vector3d(128, 39, 0));
  EXPECT_EQ(g.tool_point, Eigen::Vector3d(0.0, 0.0, 0.1));
  ASSERT_EQ(g.base_anchor_halfwidth.size(), 6u);
  EXPECT_EQ(g.platform_anchor_halfwidth[4], Eigen::Vector3d::Constant(0.001));
  RobotFrames f;
  ASSERT_TRUE(loadRobotFrames(nh, f, error)) << error;
  EXPECT_EQ(f.base_frame, "world");
}

TEST(Loader, PerCoordinateAndToolPointHalfWidths) {
  ros::NodeHandle nh = refRobotIn("per_coordinate");
  nh.setParam("anchor_uncertainty", 0.001);  // replaced for the base anchors by the list below
  nh.setParam("base_anchor_uncertainty", points({{0.001, 0.002, 0.0},
                                                 {0.001, 0.002, 0.0},
                                                 {0.001, 0.002, 0.0},
                                                 {0.001, 0.002, 0.0},
                                                 {0.001, 0.002, 0.0},
                                                 {0.0, 0.0, 0.0}}));
  nh.setParam("tool_point_uncertainty", list({0.0, 0.0, 0.0005}));
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometry(nh, g, error)) << error;
  ASSERT_EQ(g.base_anchor_halfwidth.size(), 6u);
  EXPECT_EQ(g.base_anchor_halfwidth[0], Eigen::Vector3d(0.001, 0.002, 0.0));
  EXPECT_EQ(g.base_anchor_halfwidth[5], Eigen::Vector3d::Zero());
  ASSERT_EQ(g.platform_anchor_halfwidth.size(), 6u);
  EXPECT_EQ(g.platform_anchor_halfwidth[3], Eigen::Vector3d::Constant(0.001));
  EXPECT_EQ(g.tool_point_halfwidth, Eigen::Vector3d(0.0, 0.0, 0.0005));
  // One number for every coordinate of one kind of anchor, without anchor_uncertainty.
  ros::NodeHandle nh2 = refRobotIn("platform_only");
  nh2.setParam("platform_anchor_uncertainty", 0.0002);
  ASSERT_TRUE(loadGoughGeometry(nh2, g, error)) << error;
  EXPECT_TRUE(g.base_anchor_halfwidth.empty());
  ASSERT_EQ(g.platform_anchor_halfwidth.size(), 6u);
  EXPECT_EQ(g.platform_anchor_halfwidth[1], Eigen::Vector3d::Constant(0.0002));
  EXPECT_EQ(g.tool_point_halfwidth, Eigen::Vector3d::Zero());
}

// Offsets [lo, hi] (a general box per coordinate) move the coordinate to the centre of its range.
TEST(Loader, OffsetsMoveTheCoordinateToTheCentreOfItsRange) {
  ros::NodeHandle nh = refRobotIn("offsets");
  const auto ref = pkm_accuracy_test::loadRef6();
  XmlRpc::XmlRpcValue v = points(std::vector<Eigen::Vector3d>(6, Eigen::Vector3d::Zero()));
  v[1][0] = list({-0.002, 0.0});
  v[1][2] = 0.0005;
  nh.setParam("platform_anchor_uncertainty", v);
  XmlRpc::XmlRpcValue t = list({0.0, 0.0, 0.0});
  t[2] = list({0.0, 0.01});
  nh.setParam("tool_point_uncertainty", t);
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometry(nh, g, error)) << error;
  EXPECT_NEAR(g.platform_anchors[1].x(), ref.platform_anchors[1].x() - 0.001, 1e-15);
  EXPECT_EQ(g.platform_anchors[1].y(), ref.platform_anchors[1].y());
  EXPECT_EQ(g.platform_anchors[1].z(), ref.platform_anchors[1].z());
  EXPECT_EQ(g.platform_anchors[2], ref.platform_anchors[2]);
  EXPECT_NEAR(g.platform_anchor_halfwidth[1].x(), 0.001, 1e-15);
  // (In long double, where these sums of doubles of similar size are exact.)
  using LD = long double;
  EXPECT_LE(LD(g.platform_anchors[1].x()) - g.platform_anchor_halfwidth[1].x(),
            LD(ref.platform_anchors[1].x()) - 0.002);
  EXPECT_GE(LD(g.platform_anchors[1].x()) + g.platform_anchor_halfwidth[1].x(), LD(ref.platform_anchors[1].x()));
  EXPECT_EQ(g.platform_anchor_halfwidth[1].z(), 0.0005);
  EXPECT_NEAR(g.tool_point.z(), 0.005, 1e-15);
  EXPECT_NEAR(g.tool_point_halfwidth.z(), 0.005, 1e-15);
  EXPECT_LE(g.tool_point.z() - g.tool_point_halfwidth.z(), 0.0);
  EXPECT_GE(g.tool_point.z() + g.tool_point_halfwidth.z(), 0.01);
}

TEST(Loader, BadHalfWidthsAreRejectedNamingTheParameter) {
  {
    ros::NodeHandle nh = refRobotIn("five_halfwidths");
    nh.setParam("base_anchor_uncertainty", points({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}));
    expectFailure(nh, {"/loader_test/five_halfwidths/base_anchor_uncertainty", "6 triples", "got a list of 5 items"});
  }
  {
    ros::NodeHandle nh = refRobotIn("negative_halfwidth");
    XmlRpc::XmlRpcValue v = points(std::vector<Eigen::Vector3d>(6, Eigen::Vector3d::Zero()));
    v[2][1] = -0.001;
    nh.setParam("platform_anchor_uncertainty", v);
    expectFailure(nh, {"platform_anchor_uncertainty[2][1]", ">= 0", "-0.001"});
  }
  {
    ros::NodeHandle nh = refRobotIn("negative_scalar_halfwidth");
    nh.setParam("base_anchor_uncertainty", -0.001);
    expectFailure(nh, {"base_anchor_uncertainty", ">= 0", "-0.001"});
  }
  {
    ros::NodeHandle nh = refRobotIn("short_tool_halfwidth");
    nh.setParam("tool_point_uncertainty", list({0.001, 0.001}));
    expectFailure(nh, {"tool_point_uncertainty", "[bx, by, bz]", "got a list of 2 items"});
  }
  {
    ros::NodeHandle nh = refRobotIn("reversed_offsets");
    XmlRpc::XmlRpcValue v = points(std::vector<Eigen::Vector3d>(6, Eigen::Vector3d::Zero()));
    v[4][2] = list({0.001, -0.001});
    nh.setParam("base_anchor_uncertainty", v);
    expectFailure(nh, {"base_anchor_uncertainty[4][2]", "lo <= hi", "[0.001, -0.001]"});
  }
  {
    ros::NodeHandle nh = refRobotIn("three_offsets");
    XmlRpc::XmlRpcValue v = list({0.0, 0.0, 0.0});
    v[1] = list({-0.001, 0.0, 0.001});
    nh.setParam("tool_point_uncertainty", v);
    expectFailure(nh, {"tool_point_uncertainty[1]", "offsets [lo, hi]", "a list of 3 items"});
  }
  {
    ros::NodeHandle nh = refRobotIn("string_tool_halfwidth");
    nh.setParam("tool_point_uncertainty", std::string("small"));
    expectFailure(nh, {"tool_point_uncertainty", "the string \"small\""});
  }
}

TEST(Loader, FiveBaseAnchorsAreRejectedNamingTheParameter) {
  ros::NodeHandle nh = refRobotIn("five_anchors");
  auto five = pkm_accuracy_test::loadRef6().base_anchors;
  five.pop_back();
  nh.setParam("base_anchors", points(five));
  expectFailure(nh, {"/loader_test/five_anchors/base_anchors", "expected a list of 6", "got a list of 5 items"});
}

TEST(Loader, MissingOrMalformedParameters) {
  {
    ros::NodeHandle nh = refRobotIn("missing");
    nh.deleteParam("platform_anchors");
    expectFailure(nh, {"platform_anchors", "not set"});
  }
  {
    ros::NodeHandle nh = refRobotIn("short_point");
    XmlRpc::XmlRpcValue v = points(pkm_accuracy_test::loadRef6().base_anchors);
    v[3] = list({0.1, 0.2});
    nh.setParam("base_anchors", v);
    expectFailure(nh, {"base_anchors[3]", "[x, y, z]", "got a list of 2 items"});
  }
  {
    ros::NodeHandle nh = refRobotIn("string_coordinate");
    XmlRpc::XmlRpcValue v = points(pkm_accuracy_test::loadRef6().platform_anchors);
    v[1][2] = std::string("zero");
    nh.setParam("platform_anchors", v);
    expectFailure(nh, {"platform_anchors[1][2]", "expected a number", "the string \"zero\""});
  }
  {
    ros::NodeHandle nh = refRobotIn("not_a_list");
    nh.setParam("base_anchors", 3.0);
    expectFailure(nh, {"base_anchors", "got the number 3"});
  }
  {
    ros::NodeHandle nh = refRobotIn("tool_point");
    nh.setParam("tool_point", list({1.0, 2.0}));
    expectFailure(nh, {"tool_point", "got a list of 2 items"});
  }
}

TEST(Loader, BadSensorErrors) {
  {
    ros::NodeHandle nh = refRobotIn("negative_sensor_error");
    nh.setParam("sensor_error", list({1e-5, 1e-5, -1e-5, 1e-5, 1e-5, 1e-5}));
    expectFailure(nh, {"sensor_error[2]", "> 0", "-1e-05"});
  }
  {
    ros::NodeHandle nh = refRobotIn("zero_sensor_error");
    nh.setParam("sensor_error", 0.0);
    expectFailure(nh, {"sensor_error", "> 0", "got 0"});
  }
  {
    ros::NodeHandle nh = refRobotIn("four_sensor_errors");
    nh.setParam("sensor_error", list({1e-5, 1e-5, 1e-5, 1e-5}));
    expectFailure(nh, {"sensor_error", "expected 6 numbers", "got a list of 4 items"});
  }
  {
    ros::NodeHandle nh = refRobotIn("missing_sensor_error");
    nh.deleteParam("sensor_error");
    expectFailure(nh, {"sensor_error", "not set"});
  }
}

TEST(Loader, GeometryErrorsFromTheCoreNameTheParameter) {
  {
    ros::NodeHandle nh = refRobotIn("coincident");
    auto a = pkm_accuracy_test::loadRef6().base_anchors;
    a[4] = a[1];
    nh.setParam("base_anchors", points(a));
    expectFailure(nh, {"/loader_test/coincident/base_anchors[4]", "coincides with base_anchors[1]"});
  }
  {
    ros::NodeHandle nh = refRobotIn("negative_uncertainty");
    nh.setParam("anchor_uncertainty", -0.001);
    expectFailure(nh, {"anchor_uncertainty", ">= 0", "-0.001"});
  }
}

// `sensor_error:=2e-5` on a roslaunch line and `2e-5` in a YAML 1.1 file reach the parameter server as strings.
TEST(Loader, NumbersWrittenAsStringsAreReadAsNumbers) {
  ros::NodeHandle nh = refRobotIn("strings");
  nh.setParam("sensor_error", std::string("2e-5"));
  XmlRpc::XmlRpcValue tool = list({0.0, 0.0, 0.0});
  tool[2] = std::string("1.5E-2");
  nh.setParam("tool_point", tool);
  nh.setParam("anchor_uncertainty", std::string("+1e-4"));
  XmlRpc::XmlRpcValue base = points(pkm_accuracy_test::loadRef6().base_anchors);
  base[3][0] = std::string("0.031");
  nh.setParam("base_anchors", base);
  GoughGeometry g;
  std::string error;
  ASSERT_TRUE(loadGoughGeometry(nh, g, error)) << error;
  EXPECT_EQ(g.sensor_error, std::vector<double>(6, 2e-5));
  EXPECT_EQ(g.tool_point, Eigen::Vector3d(0.0, 0.0, 1.5e-2));
  EXPECT_EQ(g.platform_anchor_halfwidth[2], Eigen::Vector3d::Constant(1e-4));
  EXPECT_EQ(g.base_anchors[3], pkm_accuracy_test::loadRef6().base_anchors[3]);
  // A list of strings, as <rosparam> gives for [2e-5, 2e-5, ...].
  nh.setParam("sensor_error", [] {
    XmlRpc::XmlRpcValue v;
    v.setSize(6);
    for (int i = 0; i < 6; ++i) v[i] = std::string(i == 4 ? "3e-5" : "2e-5");
    return v;
  }());
  ASSERT_TRUE(loadGoughGeometry(nh, g, error)) << error;
  EXPECT_EQ(g.sensor_error[4], 3e-5);
  EXPECT_EQ(g.sensor_error[0], 2e-5);
  // anchor_first_index as the string "0" (URDF anchors numbered from 0).
  ros::NodeHandle names("~strings_names");
  names.setParam("anchor_first_index", std::string("0"));
  UrdfAnchorNames n;
  ASSERT_TRUE(loadUrdfAnchorNames(names, n, error)) << error;
  EXPECT_EQ(n.first_index, 0);
}

TEST(Loader, StringsThatAreNotWholeFiniteNumbersAreRefusedNamingTheParameter) {
  const std::vector<std::string> bad = {"2e-5 m", " 2e-5", "2e-5 ", "", "1e999", "inf", "nan", "-inf", "two", "2,5e-5"};
  for (const auto& text : bad) {
    ros::NodeHandle nh = refRobotIn("bad_string_" + std::to_string(&text - bad.data()));
    nh.setParam("sensor_error", text);
    expectFailure(nh, {nh.resolveName("sensor_error"), "the string \"" + text + "\""});
  }
  {
    ros::NodeHandle nh = refRobotIn("bad_string_uncertainty");
    nh.setParam("anchor_uncertainty", std::string("1e-4m"));
    expectFailure(nh, {"/loader_test/bad_string_uncertainty/anchor_uncertainty", "the string \"1e-4m\""});
  }
  {
    ros::NodeHandle nh = refRobotIn("negative_string");
    nh.setParam("sensor_error", std::string("-2e-5"));
    expectFailure(nh, {"sensor_error", "> 0", "-2e-05"});
  }
  std::string error;
  for (const char* text : {"0.5", "1e0x", "2 "}) {
    ros::NodeHandle nh("~bad_index_string");
    nh.setParam("anchor_first_index", std::string(text));
    UrdfAnchorNames n;
    EXPECT_FALSE(loadUrdfAnchorNames(nh, n, error)) << text;
    EXPECT_NE(error.find("anchor_first_index"), std::string::npos) << error;
  }
}

TEST(Loader, NumericStringHelpers) {
  using pkm_accuracy::ros_layer::numberFromString;
  double x = 0.0;
  EXPECT_TRUE(numberFromString("2e-5", x));
  EXPECT_EQ(x, 2e-5);
  EXPECT_TRUE(numberFromString("-3", x));
  EXPECT_EQ(x, -3.0);
  EXPECT_TRUE(numberFromString(".5", x));
  EXPECT_EQ(x, 0.5);
  x = 7.0;
  EXPECT_FALSE(numberFromString("0x", x));
  EXPECT_EQ(x, 7.0) << "unchanged on failure";
  // Node options: an optional number given as a string.
  ros::NodeHandle nh("~options_strings");
  nh.setParam("some_budget", std::string("2.5"));
  nh.setParam("some_count", std::string("3"));
  nh.setParam("bad_count", std::string("3.5"));
  double budget = 1.0;
  int count = 1;
  std::string error;
  ASSERT_TRUE(pkm_accuracy::ros_layer::readOptionalNumber(nh, "some_budget", budget, error)) << error;
  EXPECT_EQ(budget, 2.5);
  ASSERT_TRUE(pkm_accuracy::ros_layer::readOptionalInteger(nh, "some_count", count, error)) << error;
  EXPECT_EQ(count, 3);
  EXPECT_FALSE(pkm_accuracy::ros_layer::readOptionalInteger(nh, "bad_count", count, error));
  EXPECT_NE(error.find("/loader_test/options_strings/bad_count"), std::string::npos) << error;
  EXPECT_EQ(count, 3);
  ASSERT_TRUE(pkm_accuracy::ros_layer::readOptionalNumber(nh, "unset", budget, error));
  EXPECT_EQ(budget, 2.5);
}

TEST(Loader, FrameAndPatternParameters) {
  std::string error;
  {
    ros::NodeHandle nh("~frames_bad");
    nh.setParam("base_frame", 3);
    RobotFrames f;
    EXPECT_FALSE(loadRobotFrames(nh, f, error));
    EXPECT_NE(error.find("base_frame"), std::string::npos) << error;
  }
  {
    ros::NodeHandle nh("~patterns");
    nh.setParam("base_anchor_pattern", std::string("A%d_link"));
    nh.setParam("anchor_first_index", 0);
    UrdfAnchorNames n;
    ASSERT_TRUE(loadUrdfAnchorNames(nh, n, error)) << error;
    EXPECT_EQ(n.base_anchor_pattern, "A%d_link");
    EXPECT_EQ(n.platform_anchor_pattern, "platform_anchor_%d");
    EXPECT_EQ(n.first_index, 0);
    EXPECT_EQ(pkm_accuracy::ros_layer::formatAnchorName(n.base_anchor_pattern, 4), "A4_link");
  }
  {
    ros::NodeHandle nh("~patterns_bad");
    nh.setParam("platform_anchor_pattern", std::string("p%s%d"));
    UrdfAnchorNames n;
    EXPECT_FALSE(loadUrdfAnchorNames(nh, n, error));
    EXPECT_NE(error.find("platform_anchor_pattern"), std::string::npos) << error;
  }
  {
    ros::NodeHandle nh("~index_bad");
    nh.setParam("anchor_first_index", 2);
    UrdfAnchorNames n;
    EXPECT_FALSE(loadUrdfAnchorNames(nh, n, error));
    EXPECT_NE(error.find("anchor_first_index"), std::string::npos) << error;
  }
}

TEST(Node, RefusesToStartWithoutARobot) {
  {
    ros::NodeHandle pnh = refRobotIn("node_five_anchors");
    auto five = pkm_accuracy_test::loadRef6().base_anchors;
    five.pop_back();
    pnh.setParam("base_anchors", points(five));
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle(), pnh);
    std::string error;
    EXPECT_FALSE(node.start(error));
    EXPECT_NE(error.find("base_anchors"), std::string::npos) << error;
  }
  {
    ros::NodeHandle pnh = refRobotIn("node_bad_source");
    pnh.setParam("robot_source", std::string("sdf"));
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle(), pnh);
    std::string error;
    EXPECT_FALSE(node.start(error));
    EXPECT_NE(error.find("robot_source"), std::string::npos) << error;
  }
  {
    ros::NodeHandle pnh = refRobotIn("node_no_urdf");
    pnh.setParam("robot_source", std::string("urdf"));
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle(), pnh);
    std::string error;
    EXPECT_FALSE(node.start(error));
    EXPECT_NE(error.find("robot_description"), std::string::npos) << error;
  }
  // A URDF without the links the parameters name: the message names the parameters (not only robot_description).
  std::string urdf;
  {
    std::ifstream f(pkm_accuracy_test::sourcePath("urdf/ref6.urdf"));
    urdf.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  ASSERT_FALSE(urdf.empty());
  {
    ros::NodeHandle pnh = refRobotIn("node_urdf_base_frame");
    pnh.setParam("robot_source", std::string("urdf"));
    pnh.setParam("robot_description", urdf);
    pnh.setParam("base_frame", std::string("base_plate"));
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle(), pnh);
    std::string error;
    EXPECT_FALSE(node.start(error));
    EXPECT_NE(error.find("/loader_test/node_urdf_base_frame/base_frame = \"base_plate\""), std::string::npos) << error;
    EXPECT_NE(error.find("robot_description"), std::string::npos) << error;
  }
  {
    ros::NodeHandle pnh = refRobotIn("node_urdf_first_index");
    pnh.setParam("robot_source", std::string("urdf"));
    pnh.setParam("robot_description", urdf);
    pnh.setParam("anchor_first_index", 0);  // the URDF numbers its anchors 1..6
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle(), pnh);
    std::string error;
    EXPECT_FALSE(node.start(error));
    EXPECT_NE(error.find("/loader_test/node_urdf_first_index/anchor_first_index = 0"), std::string::npos) << error;
    EXPECT_NE(error.find("base_anchor_0"), std::string::npos) << error;
  }
  {
    ros::NodeHandle pnh = refRobotIn("node_urdf_ok");
    pnh.setParam("robot_source", std::string("urdf"));
    pnh.setParam("robot_description", urdf);
    pkm_accuracy::ros_layer::AccuracyCheckerNode node(ros::NodeHandle("node_urdf_ok_ns"), pnh);
    std::string error;
    EXPECT_TRUE(node.start(error)) << error;
  }
  EXPECT_FALSE(ros::service::exists("/verify_workspace", false)) << "nothing may be advertised without a robot";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "loader_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
