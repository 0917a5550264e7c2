// Per-box enclosure methods on the reference robot: overestimation of the upper bound relative to the sampled
// maximum over the box, and cost per box. Usage: enclosure_bench [robot.yaml] [workspace]
#include <chrono>
#include <cstdio>
#include <iostream>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;

int main(int argc, char** argv) {
  const std::string robotPath = argc > 1 ? argv[1] : bench::sourceDir() + "/config/ref6.yaml";
  const std::string wsName = argc > 2 ? argv[2] : "paper";
  const io::RobotFile rf = io::loadRobotFile(robotPath);
  const model::GoughPlatform robot(rf.geometry);
  const domain::Workspace& ws = rf.workspaces.at(wsName);
  const IVec whole = ws.initialBox();
  // Poses: the workspace centre and two off-centre poses (relative position in every range).
  const double rel[3][6] = {
      {0.5, 0.5, 0.5, 0.5, 0.5, 0.5}, {0.9, 0.1, 0.2, 0.8, 0.3, 0.7}, {0.2, 0.8, 0.9, 0.1, 0.9, 0.2}};
  std::printf("robot %s, workspace %s\n", robotPath.c_str(), wsName.c_str());
  std::printf("%-6s %-9s %-15s %12s %12s %12s\n", "pose", "box", "method", "upper/max", "ns/box", "(worst k)");
  for (int p = 0; p < 3; ++p) {
    DVec centre(6);
    for (int i = 0; i < 6; ++i) centre[i] = whole[i].lower() + rel[p][i] * (whole[i].upper() - whole[i].lower());
    for (const double fraction : {1.0 / 64, 1.0 / 16, 1.0 / 8, 1.0 / 4}) {
      const IVec box = bench::subBox(whole, centre, fraction);
      DVec lo, hi;
      bench::sampledRange(robot, box, 20000, lo, hi);
      for (const auto& name : enclosure::enclosureNames()) {
        const auto method = enclosure::makeEnclosure(name);
        enclosure::BoxInput in;
        ws.poseView(box, method->needsGradient(), in);
        enclosure::ErrorBounds b;
        const int reps = 2000;
        const auto t0 = std::chrono::steady_clock::now();
        for (int r = 0; r < reps; ++r) method->enclose(robot, in, b);
        const double ns =
            std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / reps;
        double worst = 0.0;
        int worstK = 0;
        for (int k = 0; k < 6; ++k) {
          const double ratio = b.upper[k] / hi[k];
          if (ratio > worst) {
            worst = ratio;
            worstK = k;
          }
        }
        std::printf("%-6d 1/%-7.0f %-15s %12.4g %12.0f %12d\n", p, 1.0 / fraction, name.c_str(), worst, ns, worstK);
      }
    }
  }
  return 0;
}
