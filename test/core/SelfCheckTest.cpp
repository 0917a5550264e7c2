// The verifier's self-check (VerifierOptions::self_check): it passes on the reference problems (every enclosure
// method, workspaces, a trajectory, the planar robot, geometric uncertainty), and it stops a run whose enclosure
// certifies wrong bounds (test doubles of enclosure::ErrorEnclosure injected through VerifierOptions::enclosure) with
// an InternalError naming the method, the box and a point of the box.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/robots/Planar3RPRKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/PlanarRobotFile.hpp"
#include "pkm_accuracy/io/TrajectoryFile.hpp"

using namespace pkm_accuracy;

namespace {

/// A wrong enclosure: the registry's second_order bounds with their upper bounds scaled by `upperScale` and their
/// lower bounds by `lowerScale`.
class ScaledEnclosure : public enclosure::ErrorEnclosure {
 public:
  ScaledEnclosure(std::string name, double upperScale, double lowerScale)
      : name_(std::move(name)), upper_(upperScale), lower_(lowerScale) {}
  std::string name() const override { return name_; }
  bool needsGradient() const override { return inner_->needsGradient(); }
  void enclose(const model::RobotModel& model, const enclosure::BoxInput& in,
               enclosure::ErrorBounds& out) const override {
    inner_->enclose(model, in, out);
    out.upper *= upper_;
    out.lower *= lower_;
  }

 private:
  const std::string name_;
  const double upper_, lower_;
  const std::unique_ptr<enclosure::ErrorEnclosure> inner_ = enclosure::makeEnclosure("second_order");
};

/// A wrong enclosure under geometric uncertainty: second_order's bounds for the geometry at the centre of the ranges
/// only. Only points of the geometry box other than its centre can show it.
class CentreGeometryEnclosure : public enclosure::ErrorEnclosure {
 public:
  std::string name() const override { return "centre_geometry_only"; }
  bool needsGradient() const override { return inner_->needsGradient(); }
  void enclose(const model::RobotModel& model, const enclosure::BoxInput& in,
               enclosure::ErrorBounds& out) const override {
    std::vector<Interval> centre(static_cast<std::size_t>(model.geometryParameterCount()));
    for (int p = 0; p < model.geometryParameterCount(); ++p) centre[p] = Interval(model.geometryParameterCentre(p));
    inner_->enclose(*model.restrictGeometry(centre), in, out);
  }

 private:
  const std::unique_ptr<enclosure::ErrorEnclosure> inner_ = enclosure::makeEnclosure("second_order");
};

model::GoughGeometry ref6WithUncertainty(double h) {
  model::GoughGeometry g = test::ref6File().geometry;
  g.setUniformAnchorUncertainty(h);
  return g;
}

/// The sub-box of `paper` with `fraction` of every width at its (+x, +y, +z, +angles) vertex.
domain::Workspace paperCorner(double fraction) {
  const IVec paper = test::ref6File().workspaces.at("paper").initialBox();
  IVec box(6);
  for (int i = 0; i < 6; ++i) {
    const double w = (paper[i].upper() - paper[i].lower()) * fraction;
    box[i] = Interval(paper[i].upper() - w, paper[i].upper());
  }
  return domain::Workspace::fromRanges(test::toRanges(box));
}

verify::VerifierOptions maxError(double alpha, std::size_t maxBoxes) {
  verify::VerifierOptions o;
  o.mode = verify::Mode::MaxError;
  o.alpha = alpha;
  o.max_boxes = maxBoxes;
  o.self_check = true;
  return o;
}

/// Runs with the self-check on: it must pass and have evaluated points.
void expectPasses(const model::RobotModel& robot, const domain::Domain& domain, const verify::VerifierOptions& o,
                  const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_TRUE(o.self_check);
  verify::VerifierResult r;
  try {
    r = verify::Verifier::run(robot, domain, o);
  } catch (const InternalError& e) {
    FAIL() << e.what();
  }
  EXPECT_GT(r.stats.boxes, 0u);
  EXPECT_GT(r.stats.self_check_points, 0u);
}

/// The "name in [lo, hi]" items of a message part, in order.
std::vector<std::pair<std::string, Interval>> namedRanges(const std::string& text) {
  static const std::regex item(R"(([A-Za-z_\[\]0-9.]+(?: \[(?:m|rad)\])?) in \[([^,\]]+), ([^\]]+)\])");
  std::vector<std::pair<std::string, Interval>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), item); it != std::sregex_iterator(); ++it) {
    out.push_back({(*it)[1].str(), Interval(std::stod((*it)[2].str()), std::stod((*it)[3].str()))});
  }
  return out;
}

/// The "name = value" items of a message part, in order.
std::vector<std::pair<std::string, double>> namedValues(const std::string& text) {
  static const std::regex item(R"(([A-Za-z_\[\]0-9.]+(?: \[(?:m|rad)\])?) = ([-+0-9.eE]+))");
  std::vector<std::pair<std::string, double>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), item); it != std::sregex_iterator(); ++it) {
    out.push_back({(*it)[1].str(), std::stod((*it)[2].str())});
  }
  return out;
}

/// Runs expecting the self-check to stop the run; checks that the message names the method, the bound, a box of the
/// workspace by its variables and a point of that box. Returns the message.
std::string expectStopped(const model::RobotModel& robot, const domain::Workspace& ws, const verify::VerifierOptions& o,
                          const std::string& method, const std::string& which) {
  try {
    verify::Verifier::run(robot, ws, o);
  } catch (const InternalError& e) {
    const std::string m = e.what();
    std::cout << "[ info     ] " << m.substr(0, 420) << (m.size() > 420 ? " ..." : "") << "\n";
    EXPECT_EQ(m.rfind("self-check: the enclosure method '" + method + "' certified the " + which + " bound ", 0), 0u)
        << m;
    const std::size_t boxAt = m.find(" on the box "), pointAt = m.find(", but at its point ");
    const std::size_t poseAt = m.find(" (pose ");
    EXPECT_NE(m.find("the worst error evaluated in double is "), std::string::npos) << m;
    if (boxAt == std::string::npos || pointAt == std::string::npos || poseAt == std::string::npos) {
      ADD_FAILURE() << m;
      return m;
    }
    const std::size_t boxEnd = std::min(m.find(" with the geometry ranges"), pointAt);
    const auto box = namedRanges(m.substr(boxAt, boxEnd - boxAt));
    const auto point = namedValues(m.substr(pointAt, poseAt - pointAt));
    EXPECT_EQ(box.size(), 6u) << m;
    EXPECT_EQ(point.size(), 6u) << m;
    for (std::size_t i = 0; i < box.size() && i < point.size() && i < 6; ++i) {
      EXPECT_EQ(box[i].first, ws.variableName(static_cast<int>(i))) << m;
      EXPECT_EQ(point[i].first, ws.variableName(static_cast<int>(i))) << m;
      EXPECT_TRUE(box[i].second.contains(point[i].second)) << m;
      EXPECT_TRUE(ws.initialBox()[static_cast<int>(i)].contains(box[i].second.lower())) << m;
      EXPECT_TRUE(ws.initialBox()[static_cast<int>(i)].contains(box[i].second.upper())) << m;
    }
    return m;
  }
  ADD_FAILURE() << "the self-check did not stop the run of " << method;
  return "";
}

}  // namespace

TEST(SelfCheck, PassesOnTheReferenceProblems) {
  const io::RobotFile rf = test::ref6File();
  const model::GoughPlatform nominal(rf.geometry);
  for (const double h : rf.anchor_uncertainty_cases) {
    const model::GoughPlatform robot(ref6WithUncertainty(h));
    expectPasses(robot, rf.workspaces.at("paper"), maxError(0.5, 600), "paper, h = " + std::to_string(h));
  }
  verify::VerifierOptions v;
  v.thresholds = DVec::Constant(6, 1e-4);
  v.presample_points = 0;  // (the grid would find a witness before any box)
  v.self_check = true;
  expectPasses(nominal, rf.workspaces.at("paper_40deg"), v, "paper_40deg (singular poses)");
  const io::RobotFile tiny = test::tinyFile();
  expectPasses(model::GoughPlatform(tiny.geometry), tiny.workspaces.begin()->second, maxError(0.01, 0), "tiny");

  const io::PlanarRobotFile planar = io::loadPlanarRobotFile(test::configPath("planar3rpr.yaml"));
  const auto planarRobotPtr = model::makePlanar3RPR(planar.geometry);
  const auto& planarRobot = *planarRobotPtr;
  for (const auto& ws : planar.workspaces) expectPasses(planarRobot, ws.second, maxError(0.02, 2000), ws.first);

  const io::TrajectoryFile trajectory = io::loadTrajectoryFile(test::configPath("trajectory_example.yaml"));
  expectPasses(nominal, *trajectory.domain, maxError(0.02, 0), "trajectory_example");

  // Every enclosure method, with the derivative step too; the geometry box bisected (strategy (b)) at +-1 mm.
  const domain::Workspace corner = paperCorner(1.0 / 16.0);
  const model::GoughPlatform uncertain(ref6WithUncertainty(0.0005));
  for (const std::string& method : enclosure::enclosureNames()) {
    verify::VerifierOptions o = maxError(0.05, 300);
    o.method = method;
    o.monotonicity = true;
    expectPasses(nominal, corner, o, method + ", exact geometry");
    expectPasses(uncertain, corner, o, method + ", h = 0.5 mm");
  }
  verify::VerifierOptions always = maxError(0.02, 500);
  always.geometry_splitting = verify::GeometrySplitting::Always;
  expectPasses(model::GoughPlatform(ref6WithUncertainty(0.001)), paperCorner(1.0 / 128.0), always,
               "geometry splitting always, h = 1 mm");
}

TEST(SelfCheck, StopsARunWhoseEnclosureHalvesItsUpperBounds) {
  const model::GoughPlatform robot(test::ref6File().geometry);
  const domain::Workspace ws = paperCorner(1.0 / 16.0);
  verify::VerifierOptions o = maxError(0.01, 0);
  o.enclosure = std::make_shared<ScaledEnclosure>("halved_second_order", 0.5, 1.0);
  // Without the self-check the run completes: nothing else notices.
  o.self_check = false;
  const verify::VerifierResult unchecked = verify::Verifier::run(robot, ws, o);
  EXPECT_GT(unchecked.stats.boxes, 0u);
  EXPECT_EQ(unchecked.stats.self_check_points, 0u);
  o.self_check = true;
  for (const int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    o.threads = threads;
    expectStopped(robot, ws, o, "halved_second_order", "upper");
  }
}

TEST(SelfCheck, StopsARunWhoseEnclosureDoublesItsLowerBounds) {
  // Lower bounds over a box come with geometric uncertainty (second_order's geometry form).
  const model::GoughPlatform robot(ref6WithUncertainty(0.0005));
  const domain::Workspace ws = paperCorner(1.0 / 64.0);
  verify::VerifierOptions o = maxError(0.05, 0);
  o.enclosure = std::make_shared<ScaledEnclosure>("doubled_lower", 1.0, 2.0);
  const std::string m = expectStopped(robot, ws, o, "doubled_lower", "lower");
  EXPECT_NE(m.find(" with the geometry ranges base_anchors[0].x in ["), std::string::npos) << m;
}

TEST(SelfCheck, GeometryPointsCatchABoundForTheCentreGeometryOnly) {
  const model::GoughPlatform robot(ref6WithUncertainty(0.001));
  const domain::Workspace ws = paperCorner(1.0 / 64.0);
  verify::VerifierOptions o = maxError(0.01, 0);
  o.enclosure = std::make_shared<CentreGeometryEnclosure>();
  const std::string m = expectStopped(robot, ws, o, "centre_geometry_only", "upper");
  // The geometry of the point is named, each value in the admissible ranges named before it.
  const std::size_t rangesAt = m.find(" with the geometry ranges "), geometryAt = m.find(") and geometry ");
  ASSERT_NE(rangesAt, std::string::npos) << m;
  ASSERT_NE(geometryAt, std::string::npos) << m;
  const auto ranges = namedRanges(m.substr(rangesAt, m.find(", but at its point ") - rangesAt));
  const auto values = namedValues(m.substr(geometryAt));
  ASSERT_EQ(ranges.size(), static_cast<std::size_t>(robot.geometryParameterCount())) << m;
  ASSERT_EQ(values.size(), ranges.size()) << m;
  bool offCentre = false;
  for (std::size_t p = 0; p < ranges.size(); ++p) {
    EXPECT_EQ(values[p].first, robot.geometryParameterName(static_cast<int>(p)));
    EXPECT_TRUE(ranges[p].second.contains(values[p].second)) << values[p].first;
    offCentre = offCentre || values[p].second != robot.geometryParameterCentre(static_cast<int>(p));
  }
  EXPECT_TRUE(offCentre) << m;
}
