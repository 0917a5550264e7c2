// Verifier scenarios on the reference robots; prints one table row per scenario with boxes, seconds, verdict and
// peak memory. Usage: verifier_bench [time_limit_s] (default 120: the long scenarios stop there, UNDECIDED).
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;

namespace {

void row(const std::string& scenario, const verify::VerifierResult& r) {
  std::printf("%-44s %-10s %-16s %12zu %10.3f %6d %9.1f\n", scenario.c_str(), verify::toString(r.verdict).c_str(),
              verify::toString(r.reason).c_str(), r.stats.boxes, r.stats.seconds, r.stats.threads, bench::peakRssMiB());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const double limit = argc > 1 ? std::atof(argv[1]) : 120.0;
  const io::RobotFile ref = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const io::RobotFile tiny = io::loadRobotFile(bench::sourceDir() + "/config/tiny_fixed_orientation.yaml");
  const model::GoughPlatform ref6(ref.geometry), tiny6(tiny.geometry);
  const domain::Workspace& paper = ref.workspaces.at("paper");
  const domain::Workspace& paper40 = ref.workspaces.at("paper_40deg");
  const domain::Workspace& fixedWs = tiny.workspaces.at("fixed_orientation");

  DVec lo, hiPaper, hiTiny;
  bench::sampledRange(ref6, paper.initialBox(), 200000, lo, hiPaper);
  bench::sampledRange(tiny6, fixedWs.initialBox(), 200000, lo, hiTiny);
  std::printf("time limit per scenario: %.0f s; thresholds = factor x maxima sampled at 2e5 points + corners\n", limit);
  std::printf("sampled maxima paper: ");
  for (int k = 0; k < 6; ++k) std::printf("%.6g ", hiPaper[k]);
  std::printf("\nsampled maxima tiny:  ");
  for (int k = 0; k < 6; ++k) std::printf("%.6g ", hiTiny[k]);
  std::printf("\n%-44s %-10s %-16s %12s %10s %6s %9s\n", "scenario", "verdict", "reason", "boxes", "seconds", "thr",
              "peakMiB");

  verify::VerifierOptions o;
  o.time_limit_s = limit;

  // paper_40deg UNSAFE (thresholds: 5% above the paper maxima).
  o.thresholds = hiPaper * 1.05;
  row("paper_40deg UNSAFE, 2 threads", verify::Verifier::run(ref6, paper40, o));

  // tiny fixed orientation at +5%: default vs paper_baseline with round-robin bisection.
  o.thresholds = hiTiny * 1.05;
  const auto tinyDefault = verify::Verifier::run(tiny6, fixedWs, o);
  row("tiny +5% default (second_order), 2 threads", tinyDefault);
  verify::VerifierOptions b = o;
  b.method = "paper_baseline";
  b.bisection = verify::Bisection::RoundRobin;
  b.time_limit_s = std::min(limit, 60.0);
  const auto tinyBaseline = verify::Verifier::run(tiny6, fixedWs, b);
  row("tiny +5% paper_baseline round-robin", tinyBaseline);
  std::printf("  ratio baseline/default seconds: %.1f%s\n", tinyBaseline.stats.seconds / tinyDefault.stats.seconds,
              tinyBaseline.verdict == verify::Verdict::Undecided ? " (baseline did not finish: lower bound)" : "");

  // The full paper workspace at +5% (the headline scenario), on 2 threads and on 1 (thread scaling).
  o.thresholds = hiPaper * 1.05;
  o.threads = 2;
  const auto two = verify::Verifier::run(ref6, paper, o);
  row("paper +5%, 2 threads", two);
  o.threads = 1;
  const auto one = verify::Verifier::run(ref6, paper, o);
  row("paper +5%, 1 thread", one);
  std::printf("  speed-up 2 threads vs 1: %.2f\n", one.stats.seconds / two.stats.seconds);
  o.threads = 0;

  // Max-error mode to 1% on the paper workspace.
  verify::VerifierOptions m = o;
  m.mode = verify::Mode::MaxError;
  m.alpha = 0.01;
  m.thresholds.resize(0);
  row("paper max-error alpha=1%, 2 threads", verify::Verifier::run(ref6, paper, m));

  // The small fixed-orientation problem: all six maxima to 0.1% (ibexopt: 2-12 s per component to 0.1%).
  m.alpha = 0.001;
  const auto tinyMax = verify::Verifier::run(tiny6, fixedWs, m);
  row("tiny max-error alpha=0.1%, all six", tinyMax);
  std::printf("  tiny maxima: ");
  for (int k = 0; k < 6; ++k) std::printf("[%.6g, %.6g] ", tinyMax.max_lower[k], tinyMax.max_upper[k]);
  std::printf("\n");

  // Anchor uncertainty (half-widths of config/ref6.yaml's anchor_uncertainty_cases), uncertainty as interval
  // coefficients: thresholds 5% above the nominal sampled maxima.
  for (const double h : ref.anchor_uncertainty_cases) {
    if (h <= 0.0) continue;
    model::GoughGeometry g = ref.geometry;
    g.setUniformAnchorUncertainty(h);
    const model::GoughPlatform uncertain(g);
    verify::VerifierOptions u = o;
    u.thresholds = hiPaper * 1.05;
    char name[80];
    std::snprintf(name, sizeof name, "paper +5%%, anchors +-%.1f mm, 2 threads", h * 1e3);
    row(name, verify::Verifier::run(uncertain, paper, u));
  }
  return 0;
}
