// io::PlanarRobotFile, the reader of planar 3-RPR robot files: the reference file (config/planar3rpr.yaml) as written,
// and every error naming the file and the key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../core/TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PlanarWorkspace.hpp"
#include "pkm_accuracy/io/PlanarRobotFile.hpp"

using namespace pkm_accuracy;

namespace {

io::PlanarRobotFile planarFile() { return io::loadPlanarRobotFile(test::configPath("planar3rpr.yaml")); }

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(PlanarRobotFile, LoadsTheReferenceRobot) {
  const io::PlanarRobotFile rf = planarFile();
  const model::Planar3RPRGeometry& g = rf.geometry;
  ASSERT_EQ(g.legCount(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(g.base_anchors[i].norm(), 0.5, 1e-12) << i;
    EXPECT_NEAR(g.platform_anchors[i].norm(), 0.1, 1e-12) << i;
    EXPECT_EQ(g.sensor_error[i], 1e-5);
  }
  EXPECT_EQ(g.tool_point, Eigen::Vector2d::Zero());
  ASSERT_EQ(rf.workspaces.count("reference"), 1u);
  ASSERT_EQ(rf.workspaces.count("disc"), 1u);
  const IVec& box = rf.workspaces.at("reference").initialBox();
  EXPECT_EQ(box[0], Interval(-0.1, 0.1));
  EXPECT_EQ(box[1], Interval(-0.1, 0.1));
  EXPECT_EQ(box[2], Interval(-0.3, 0.3));
  const domain::PlanarWorkspace& disc = rf.workspaces.at("disc");
  EXPECT_TRUE(disc.isDisc());
  EXPECT_EQ(disc.discRadius(), 0.1);
  EXPECT_EQ(disc.initialBox()[2], Interval(-0.3, 0.3));
}

TEST(PlanarRobotFile, ErrorsNameTheFileAndKey) {
  const std::string anchors =
      "base_anchors: [[0, 0.5], [-0.4, -0.25], [0.4, -0.25]]\n"
      "platform_anchors: [[-0.1, 0], [0.05, -0.08], [0.05, 0.08]]\n";
  auto expectError = [](const std::string& path, const std::string& needle, bool parse) {
    try {
      io::loadPlanarRobotFile(path);
      FAIL() << "expected an exception mentioning " << needle;
    } catch (const ParseError& e) {
      EXPECT_TRUE(parse) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    } catch (const InvalidArgument& e) {
      EXPECT_FALSE(parse) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expectError(::testing::TempDir() + "/no_such_planar.yaml", "cannot open", true);
  expectError(writeTemp("planar_bad_type.yaml", "type: gough6\n" + anchors + "sensor_error: 1e-5\n"), "type", true);
  expectError(writeTemp("planar_four_legs.yaml",
                        "base_anchors: [[0, 0.5], [-0.4, -0.25], [0.4, -0.25], [0, -1]]\n"
                        "platform_anchors: [[-0.1, 0], [0.05, -0.08], [0.05, 0.08]]\nsensor_error: 1e-5\n"),
              "base_anchors", false);
  expectError(writeTemp("planar_3d_point.yaml",
                        "base_anchors: [[0, 0.5, 0], [-0.4, -0.25], [0.4, -0.25]]\n"
                        "platform_anchors: [[-0.1, 0], [0.05, -0.08], [0.05, 0.08]]\nsensor_error: 1e-5\n"),
              "base_anchors[0]", true);
  expectError(writeTemp("planar_bad_error.yaml", anchors + "sensor_error: [1e-5, -1, 1e-5]\n"), "sensor_error[1]",
              false);
  expectError(writeTemp("planar_no_theta.yaml",
                        anchors + "sensor_error: 1e-5\nworkspaces:\n  w:\n    x: [0, 1]\n    y: [0, 1]\n"),
              "workspaces.w.theta", true);
  expectError(writeTemp("planar_inverted.yaml", anchors + "sensor_error: 1e-5\nworkspaces:\n  w:\n    x: [1, 0]\n"
                                                          "    y: [0, 1]\n    theta: [0, 0]\n"),
              "workspaces.w.x", true);
  expectError(
      writeTemp("planar_disc_radius.yaml", anchors + "sensor_error: 1e-5\nworkspaces:\n  w:\n    theta: [0, 0]\n"
                                                     "    region: {type: disc, centre: [0, 0], radius: -1}\n"),
      "workspaces.w.region", true);
  expectError(writeTemp("planar_disc_and_x.yaml",
                        anchors + "sensor_error: 1e-5\nworkspaces:\n  w:\n    x: [0, 1]\n    theta: [0, 0]\n"
                                  "    region: {type: disc, centre: [0, 0], radius: 1}\n"),
              "workspaces.w.x", true);
  expectError(
      writeTemp("planar_region_type.yaml", anchors + "sensor_error: 1e-5\nworkspaces:\n  w:\n    theta: [0, 0]\n"
                                                     "    region: {type: cylinder, centre: [0, 0], radius: 1}\n"),
      "workspaces.w.region.type", true);
}
