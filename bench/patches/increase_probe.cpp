// Session 35 (bench/RESULTS.md *Session 35*; bench/patches/README.md): for the boxes a `PKM_DUMP` run of pkm_verify
// (session35_oracles.patch) enclosed at depths [d0, d1] with a component still above its threshold (every
// `every`-th), the second_order enclosure with the geometry +-h (decomposed form; NOT=1: no targets, i.e. full
// increase bounds) and without, against sampled maxima over the box (bench::sampledMaximaOverGeometry, 30 random
// poses + corners). Prints "G depth k bound_h/thr bound_0/thr sampled_h/thr sampled_0/thr dumped/thr" on stderr.
// Build against the core library (not built by CMake), from the repository root, on one line:
//   g++ -O2 -std=c++17 -I bench -I bench/patches -I include -I /usr/include/eigen3 -I $PKM_WS/devel/include
//   bench/patches/increase_probe.cpp -L $PKM_WS/devel/lib -lpkm_accuracy_io -lpkm_accuracy_core
//   -Wl,-rpath,$PKM_WS/devel/lib -ltbb -lyaml-cpp
// Usage: increase_probe DUMP h d0 d1 every thr_1 .. thr_6
#include <cstdio>
#include <fstream>
#include <sstream>
#include "BenchCommon.hpp"
#include "DumpedBoxes.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
using namespace pkm_accuracy;
int main(int argc, char** argv) {
  const double h = std::atof(argv[2]);
  const int d0 = std::atoi(argv[3]), d1 = std::atoi(argv[4]), every = std::atoi(argv[5]);
  const io::RobotFile rf = io::loadRobotFile("config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const auto method = enclosure::makeEnclosure("second_order");
  model::GoughGeometry unc = rf.geometry;
  unc.setUniformAnchorUncertainty(h);
  const model::GoughPlatform robotH(unc), robot0(rf.geometry);
  double thr[6];
  for (int k = 0; k < 6; ++k) thr[k] = std::atof(argv[6 + k]);
  int cnt = 0;
  for (const bench::DumpedBox& dumped : bench::readDumpedBoxes(argv[1], d0, d1)) {
    const unsigned a = dumped.active;
    const IVec& box = dumped.box;
    const double* r = dumped.ratio;
    const int d = dumped.depth;
    unsigned fails = 0;
    for (int k = 0; k < 6; ++k)
      if (((a >> k) & 1) && r[k] > 1 && r[k] < 50) fails |= 1u << k;
    if (!fails || (cnt++ % every)) continue;
    enclosure::BoxInput bi;
    ws.poseView(box, true, bi);
    bi.rows = fails;
    bi.decomposeGeometry = !std::getenv("COMB");
    if (!std::getenv("NOT")) bi.targets.resize(6);
    if (!std::getenv("NOT"))
      for (int k = 0; k < 6; ++k) bi.targets[k] = thr[k];
    enclosure::ErrorBounds bh, b0;
    method->enclose(robotH, bi, bh);
    method->enclose(robot0, bi, b0);
    bench::GeometryMaxima th = bench::sampledMaximaOverGeometry(rf.geometry, h, box, 30);
    bench::GeometryMaxima t0 = bench::sampledMaximaOverGeometry(rf.geometry, 0.0, box, 30);
    for (int k = 0; k < 6; ++k) {
      if (!((fails >> k) & 1)) continue;
      std::fprintf(stderr, "G %d %d %.4f %.4f %.4f %.4f %.4f\n", d, k, bh.upper[k] / thr[k], b0.upper[k] / thr[k],
                   th.hi[k] / thr[k], t0.hi[k] / thr[k], r[k]);
    }
  }
}
