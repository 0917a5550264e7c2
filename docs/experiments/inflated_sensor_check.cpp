// Soundness check of enclosure::InflatedSensorBound (docs/experiments/inflated-sensor.patch applied): over random
// boxes of the paper workspace (1/12 of the ranges down to thin) at +-1 and +-0.5 mm, f_k at random poses and random
// geometries (vertices and interior points) never exceeds the bound, and every certified sign of J holds.
#include <cstdio>
#include <random>
#include "BenchCommon.hpp"
#include "pkm_accuracy/core/enclosure/InflatedSensorBound.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
using namespace pkm_accuracy;
using Offsets = bench::GeometryMaxima::Offsets;
int main() {
  const io::RobotFile rf = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  std::mt19937_64 rng(99);
  long checks = 0, bounded = 0, violations = 0; double worst = 0;
  for (double h : {1e-3, 5e-4}) {
    model::GoughGeometry unc = rf.geometry; unc.setUniformAnchorUncertainty(h);
    const model::GoughPlatform robot(unc);
    for (double frac : {1.0/12, 1.0/16, 1.0/32, 1.0/64, 0.0}) {
      for (int s = 0; s < 40; ++s) {
        IVec box(6);
        for (int i = 0; i < 6; ++i) { const double w = (whole[i].upper() - whole[i].lower()) * frac; std::uniform_real_distribution<double> u(whole[i].lower(), whole[i].upper() - w); const double lo = u(rng); box[i] = Interval(lo, lo + w); }
        enclosure::BoxInput in; ws.poseView(box, true, in);
        double up[6]; DMat hints; enclosure::SignPattern sg;
        if (!enclosure::InflatedSensorBound::bound(robot, in, 0x3f, up, hints, sg)) continue;
        for (int t = 0; t < 60; ++t) {
          DVec q = bench::randomPoint(box, rng); if (t < 8) for (int i = 0; i < 6; ++i) q[i] = ((t + i) & 1) ? box[i].upper() : box[i].lower();
          Offsets d{}; std::uniform_int_distribution<int> coin(0, 2);
          for (int p = 0; p < 36; ++p) { const int c = coin(rng); d[p] = c == 0 ? -h : (c == 1 ? h : std::uniform_real_distribution<double>(-h, h)(rng)); }
          const DVec f = bench::worstErrorWithOffsets(rf.geometry, d, q);
          for (int k = 0; k < 6; ++k) {
            ++checks; if (!std::isfinite(up[k])) continue; ++bounded;
            if (f[k] > up[k]) { ++violations; worst = std::max(worst, f[k] / up[k]); }
            // also check certified signs
          }
          const DMat J = model::GoughPlatform(bench::offsetGeometry(rf.geometry, d)).jacobian(q);
          for (int k = 0; k < 6; ++k) for (int j = 0; j < 6; ++j) { const int bit = k * 6 + j; if (sg.known(bit) && sg.sign(bit) * J(k, j) < 0) { ++violations; std::printf("sign violation\n"); } }
        }
      }
    }
  }
  std::printf("checks %ld (bounded %ld): violations %ld (worst ratio %.6f)\n", checks, bounded, violations, worst);
}
