// Peak memory of long verifier runs. Usage: memory_bench [h_mm] [margin] [seconds,seconds,...]
//   h_mm: half-width of every anchor coordinate (default 2);
//   margin: thresholds = margin x the case's maxima over poses and geometries, sampled in double (default 1.01:
//   close enough to the maxima that the run ends by its time budget, UNDECIDED, which is the case to bound);
//   the time budgets of the runs, each in a fresh process (default 60,300).
// The paper workspace of config/ref6.yaml, 2 threads. Each run prints its verdict, boxes, seconds and the peak
// resident set size of its process (getrusage; the process holds nothing else but the robot and the sampled maxima).
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;

namespace {

std::vector<double> parseList(const char* text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::atof(item.c_str()));
  return out;
}

/// One run in this (child) process: prints its row and exits.
void runOnce(const model::GoughPlatform& robot, const domain::Workspace& paper, const DVec& thresholds,
             double seconds) {
  verify::VerifierOptions o;
  o.time_limit_s = seconds;
  o.threads = 2;
  o.thresholds = thresholds;
  const verify::VerifierResult r = verify::Verifier::run(robot, paper, o);
  std::printf("%8.0f  %-10s %-14s %10zu %9.1f %9.1f\n", seconds, verify::toString(r.verdict).c_str(),
              verify::toString(r.reason).c_str(), r.stats.boxes, r.stats.seconds, bench::peakRssMiB());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const double h = (argc > 1 ? std::atof(argv[1]) : 2.0) * 1e-3;
  const double margin = argc > 2 ? std::atof(argv[2]) : 1.01;
  const std::vector<double> budgets = argc > 3 ? parseList(argv[3]) : std::vector<double>{60.0, 300.0};
  const io::RobotFile ref = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const domain::Workspace& paper = ref.workspaces.at("paper");
  model::GoughGeometry g = ref.geometry;
  g.setUniformAnchorUncertainty(h);
  const model::GoughPlatform robot(g);
  const bench::GeometryMaxima m = bench::sampledMaximaOverGeometry(ref.geometry, h, paper.initialBox(), 10000);
  std::printf("memory_bench: paper workspace, anchors +-%g mm, thresholds %g x the sampled maxima, 2 threads\n",
              h * 1e3, margin);
  std::printf("%8s  %-10s %-14s %10s %9s %9s\n", "budget_s", "verdict", "reason", "boxes", "seconds", "peakMiB");
  std::fflush(stdout);
  for (const double seconds : budgets) {
    const pid_t child = fork();
    if (child < 0) {
      std::perror("memory_bench: fork");
      return 1;
    }
    if (child == 0) {
      runOnce(robot, paper, m.hi * margin, seconds);
      std::_Exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "memory_bench: the run with a budget of %g s failed\n", seconds);
      return 1;
    }
  }
  return 0;
}
