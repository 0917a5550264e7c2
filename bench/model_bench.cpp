// Robot models through the generic path (KinematicModel<K>, docs/models.md), figures and ratios measured in one run:
//   * the Gough platform, paper workspace, thresholds 5% above the sampled maxima: the hand-written GoughPlatform
//     (the `gough` type) against KinematicModel<GoughKinematics> (boxes and seconds, best of `rounds`);
//   * the same with +-0.5 mm on every anchor coordinate, max-error to 2% (the geometry as bisectable parameters, the
//     generic path's geometry derivatives as affine forms in the pose);
//   * every other built-in type's reference workspace (its robot file's `reference`), max-error to 1%.
// Usage: model_bench [rounds] [threads]   (defaults 3, 2)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/model/robots/GoughKinematics.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/ModelFile.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;

namespace {

struct Run {
  std::size_t boxes = 0;
  double seconds = 0.0;
  verify::VerifierResult result;
};

/// Best wall time of `rounds` runs (the box count of the last).
Run best(const model::RobotModel& m, const domain::Domain& d, const verify::VerifierOptions& o, int rounds) {
  Run out;
  out.seconds = 1e300;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    out.result = verify::Verifier::run(m, d, o);
    out.seconds = std::min(out.seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    out.boxes = out.result.stats.boxes;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 3;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  std::printf("model_bench: best of %d, %d threads, load %s\n", rounds, threads, bench::loadAverage().c_str());

  const io::RobotFile ref = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const domain::Workspace& paper = ref.workspaces.at("paper");
  const model::GoughPlatform hand(ref.geometry);
  const auto generic = model::makeGenericGough(ref.geometry);
  DVec lo, hi;
  bench::sampledRange(hand, paper.initialBox(), 200000, lo, hi);
  verify::VerifierOptions o;
  o.threads = threads;
  o.thresholds = 1.05 * hi;
  const Run h = best(hand, paper, o, rounds), g = best(*generic, paper, o, rounds);
  std::printf("\n%-44s %-10s %9s %9s\n", "gough, paper +5%", "verdict", "boxes", "seconds");
  std::printf("%-44s %-10s %9zu %9.3f\n", "hand-written (GoughPlatform)", verify::toString(h.result.verdict).c_str(),
              h.boxes, h.seconds);
  std::printf("%-44s %-10s %9zu %9.3f\n", "generic (KinematicModel<GoughKinematics>)",
              verify::toString(g.result.verdict).c_str(), g.boxes, g.seconds);
  std::printf("  ratio generic / hand-written: boxes %.3f, seconds %.2f\n",
              static_cast<double>(g.boxes) / static_cast<double>(h.boxes), g.seconds / h.seconds);

  model::GoughGeometry uncertain = ref.geometry;
  uncertain.setUniformAnchorUncertainty(5e-4);
  const model::GoughPlatform handU(uncertain);
  const auto genericU = model::makeGenericGough(uncertain);
  verify::VerifierOptions mu;
  mu.mode = verify::Mode::MaxError;
  mu.alpha = 0.02;
  mu.threads = threads;
  const Run hu = best(handU, paper, mu, rounds), gu = best(*genericU, paper, mu, rounds);
  std::printf("\n%-44s %-10s %9s %9s\n", "gough, paper +-0.5 mm anchors, max-error 2%", "converged", "boxes",
              "seconds");
  std::printf("%-44s %-10s %9zu %9.3f\n", "hand-written (GoughPlatform)", hu.result.converged ? "yes" : "no", hu.boxes,
              hu.seconds);
  std::printf("%-44s %-10s %9zu %9.3f\n", "generic (KinematicModel<GoughKinematics>)",
              gu.result.converged ? "yes" : "no", gu.boxes, gu.seconds);
  std::printf("  ratio generic / hand-written: boxes %.3f, seconds %.2f\n",
              static_cast<double>(gu.boxes) / static_cast<double>(hu.boxes), gu.seconds / hu.seconds);

  std::printf("\n%-44s %-10s %9s %9s  %s\n", "reference workspace, max-error 1%", "converged", "boxes", "seconds",
              "maxima (upper bounds)");
  for (const char* type : {"planar3rpr", "delta3", "rus6", "prs3"}) {
    const std::string path = bench::sourceDir() + "/config/" + type + ".yaml";
    io::ModelFile file;
    try {
      file = io::loadModelFile(path);
    } catch (const std::exception& e) {
      std::printf("%-44s (not available: %s)\n", type, e.what());
      continue;
    }
    verify::VerifierOptions m;
    m.mode = verify::Mode::MaxError;
    m.alpha = 0.01;
    m.threads = threads;
    const Run r = best(*file.model, *file.workspaces.at("reference"), m, rounds);
    std::printf("%-44s %-10s %9zu %9.3f ", type, r.result.converged ? "yes" : "no", r.boxes, r.seconds);
    for (int k = 0; k < r.result.max_upper.size(); ++k) std::printf(" %.4g", r.result.max_upper[k]);
    std::printf("\n");
  }
  return 0;
}
