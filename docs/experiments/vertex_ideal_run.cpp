// UNSOUND experiment driver (docs/experiments/README.md): the paper workspace at anchor half-width h with every
// component bounded through its sampled worst geometry vertex (needs vertex-ideal.patch applied to the core).
// Usage: vertex_ideal_run h time_limit_s ideal(0|1). Prints verdict, boxes and seconds.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

namespace pkm_accuracy {
namespace enclosure {
extern const model::RobotModel* g_vertex[kMaxDof];
}
}  // namespace pkm_accuracy
using namespace pkm_accuracy;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: vertex_ideal_run h time_limit_s ideal(0|1)\n");
    return 2;
  }
  const double h = std::atof(argv[1]);
  const double limit = std::atof(argv[2]);
  const bool ideal = std::atoi(argv[3]) != 0;
  const io::RobotFile rf = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const bench::GeometryMaxima m = bench::sampledMaximaOverGeometry(rf.geometry, h, ws.initialBox(), 2000);
  std::vector<std::unique_ptr<model::GoughPlatform>> vertices;
  for (int k = 0; k < 6; ++k) {
    vertices.push_back(std::make_unique<model::GoughPlatform>(bench::offsetGeometry(rf.geometry, m.offsets[k])));
    if (ideal) enclosure::g_vertex[k] = vertices.back().get();
  }
  model::GoughGeometry g = rf.geometry;
  g.setUniformAnchorUncertainty(h);
  const model::GoughPlatform robot(g);
  verify::VerifierOptions o;
  o.time_limit_s = limit;
  o.threads = 2;
  o.thresholds = m.hi * 1.05;
  const verify::VerifierResult r = verify::Verifier::run(robot, ws, o);
  std::printf("h=%g ideal=%d: %s %zu boxes %.1f s\n", h, ideal, verify::toString(r.verdict).c_str(), r.stats.boxes,
              r.stats.seconds);
  return 0;
}
