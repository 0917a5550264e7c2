// Verifier scenarios on the reference robots; prints one table row per scenario with boxes, seconds, verdict and
// peak memory. Usage: verifier_bench [time_limit_s] [all|nominal|uncertainty] [rounds]
// [default|combined|decomposed|both] [h_mm,h_mm,...]
//   time_limit_s: per scenario (default 120: the long scenarios stop there, UNDECIDED);
//   the second argument selects the scenarios: all (default), nominal (no anchor uncertainty), or uncertainty (the
//   anchor-uncertainty rows only);
//   rounds: how many times the anchor-uncertainty cases run, in turn (h = 0, 0.5, 1 mm, h = 0, ...; default 3), so
//   that the ratios are taken from each case's fastest run (this shared VM's wall times swing 2x with other load);
//   the last argument: the geometry form of the uncertain cases (SearchTuning::decompose_geometry; default: the
//   library's default; both: each uncertain case with each form, in turn, in every round);
//   the half-widths of the uncertain cases in mm, comma-separated (default: ref6.yaml's anchor_uncertainty_cases,
//   0.5 and 1 mm), e.g. 0.25,0.5,0.75,1 for the ratio as a function of h.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <sys/resource.h>

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

/// CPU time (user + system) of this process so far, all threads (s).
double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// Anchor-uncertainty row: also the CPU seconds of the run (both threads), the geometry switches / splits (strategy
/// (b)) and the time ratio to h = 0.
void urow(const std::string& scenario, const verify::VerifierResult& r, double reference_s, double cpu_s = -1.0) {
  char ratio[48] = "-";
  if (reference_s > 0.0) {
    std::snprintf(ratio, sizeof ratio, "%s%.2f", r.reason == verify::UndecidedReason::TimeBudget ? ">=" : "",
                  r.stats.seconds / reference_s);
  }
  char cpu[32] = "-";
  if (cpu_s >= 0.0) std::snprintf(cpu, sizeof cpu, "%.3f", cpu_s);
  std::printf("%-34s %-10s %-21s %10zu %9.3f %9s %8zu %8zu %7s %8.1f\n", scenario.c_str(),
              verify::toString(r.verdict).c_str(), verify::toString(r.reason).c_str(), r.stats.boxes, r.stats.seconds,
              cpu, r.stats.geometry_switches, r.stats.geometry_splits, ratio, bench::peakRssMiB());
  if (r.reason == verify::UndecidedReason::UncertaintySensitive && !r.sensitive.empty()) {
    const verify::SensitivePose& sp = r.sensitive.front();
    std::printf(
        "  uncertainty-sensitive pose: component %d, certified %.6g for some geometry (%zu pose(s)): the\n"
        "  sampled maxima of this case are more than 5%% below the true ones\n",
        sp.component, sp.failing_lower, r.sensitive_count);
  }
  std::fflush(stdout);
}

void printVec(const char* label, const DVec& v) {
  std::printf("%s", label);
  for (int k = 0; k < v.size(); ++k) std::printf("%.6g ", v[k]);
  std::printf("\n");
}

/// Anchor uncertainty: the paper workspace, every anchor coordinate known to +-h, h in anchor_uncertainty_cases.
/// Thresholds 5% above each case's own maxima over poses and geometries (sampled, bench::sampledMaximaOverGeometry),
/// 2 threads; time ratio of each uncertain case to h = 0 in the same run, `rounds` times in turn, then the ratios of
/// the fastest runs (wall and CPU time). Then max-error at h = 0.5 mm, alpha 2%.
/// A half-width h (m) in mm with one decimal, or two where the second is not 0 (0.5 -> "0.5", 0.25 -> "0.25").
std::string mm(double h) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", h * 1e3);
  std::string s = text;
  if (s.size() > 1 && s.back() == '0') s.pop_back();
  return s;
}

void uncertaintyScenarios(const io::RobotFile& ref, const domain::Workspace& paper, double limit, int rounds,
                          const std::vector<int>& forms, std::vector<double> cases) {
  constexpr int kRandomPoses = 10000;
  std::printf(
      "\n-- anchor uncertainty: paper workspace, thresholds = 1.05 x that case's maxima over poses\n"
      "   and geometries, sampled in double (not certified): 64 corners + %d random poses; per pose and\n"
      "   component the anchor vertex given by the signs of central differences (step h) of f_k w.r.t. the 36\n"
      "   anchor coordinates + 8 random vertices; the best 8 per component refined by single-coordinate flips\n",
      kRandomPoses);
  std::printf("   load average before: %s (2 cores)\n", bench::loadAverage().c_str());
  if (cases.empty()) cases = ref.anchor_uncertainty_cases;
  if (cases.empty() || cases.front() != 0.0) cases.insert(cases.begin(), 0.0);
  std::vector<DVec> maxima;
  DVec nominalMax;
  for (const double h : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    const bench::GeometryMaxima m = bench::sampledMaximaOverGeometry(ref.geometry, h, paper.initialBox(), kRandomPoses);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (h == 0.0) nominalMax = m.hi;
    char label[96];
    std::snprintf(label, sizeof label, "   maxima h=%s mm (%ld evaluations, %.1f s): ", mm(h).c_str(), m.evaluations,
                  s);
    printVec(label, m.hi);
    if (h > 0.0 && nominalMax.size() == 6) {
      std::printf("     ratio to h=0: ");
      for (int k = 0; k < 6; ++k) std::printf("%.3f ", m.hi[k] / nominalMax[k]);
      int atCorner = 0;
      for (int k = 0; k < 6; ++k) {
        bool corner = true;
        for (int i = 0; i < 6; ++i) {
          const Interval& r = paper.initialBox()[i];
          corner = corner && (m.pose[k][i] == r.lower() || m.pose[k][i] == r.upper());
        }
        atCorner += corner ? 1 : 0;
      }
      std::printf(" (%d of 6 at a workspace corner)\n", atCorner);
    }
    maxima.push_back(m.hi);
  }
  std::printf("%-34s %-10s %-21s %10s %9s %9s %8s %8s %7s %8s\n", "scenario (2 threads)", "verdict", "reason", "boxes",
              "seconds", "cpu_s", "switches", "gsplits", "xh=0", "peakMiB");
  // Runs: h = 0 once, then each uncertain case with each form (-1: the library's default, 0 combined, 1 decomposed).
  struct Run {
    std::size_t c;
    int form;
  };
  std::vector<Run> runs;
  for (std::size_t c = 0; c < cases.size(); ++c)
    for (std::size_t f = 0; f < (cases[c] == 0.0 ? 1 : forms.size()); ++f) runs.push_back({c, forms[f]});
  std::vector<double> bestWall(runs.size(), 0.0), bestCpu(runs.size(), 0.0);
  std::vector<bool> finished(runs.size(), true);
  const auto runName = [&](const Run& run) {
    char name[80];
    const char* form = run.form < 0 || cases[run.c] == 0.0 ? "" : (run.form == 0 ? ", comb." : ", decomp.");
    std::snprintf(name, sizeof name, "paper +5%%, anchors +-%s mm%s", mm(cases[run.c]).c_str(), form);
    return std::string(name);
  };
  for (int round = 0; round < rounds; ++round) {
    if (rounds > 1) std::printf("  round %d of %d\n", round + 1, rounds);
    double reference = 0.0;
    for (std::size_t x = 0; x < runs.size(); ++x) {
      const std::size_t c = runs[x].c;
      const double h = cases[c];
      model::GoughGeometry g = ref.geometry;
      g.setUniformAnchorUncertainty(h);
      const model::GoughPlatform robot(g);
      verify::VerifierOptions o;
      o.time_limit_s = limit;
      o.threads = 2;
      o.thresholds = maxima[c] * 1.05;
      if (runs[x].form >= 0) o.tuning.decompose_geometry = runs[x].form == 1;
      const double cpu0 = cpuSeconds();
      const verify::VerifierResult r = verify::Verifier::run(robot, paper, o);
      const double cpu = cpuSeconds() - cpu0;
      urow(runName(runs[x]).c_str(), r, h == 0.0 ? 0.0 : reference, cpu);
      std::printf("  (load average after it: %s)\n", bench::loadAverage().c_str());
      if (h == 0.0) reference = r.verdict == verify::Verdict::Safe ? r.stats.seconds : 0.0;
      finished[x] = finished[x] && r.verdict == verify::Verdict::Safe;
      if (round == 0 || r.stats.seconds < bestWall[x]) bestWall[x] = r.stats.seconds;
      if (round == 0 || cpu < bestCpu[x]) bestCpu[x] = cpu;
    }
  }
  std::printf(
      "  xh=0: seconds / seconds of the h=0 row of the same round (\">=\": that case did not finish); goal <= 3;\n"
      "  seed paper 10 / 23 / 42 min, i.e. 2.3 and 4.2\n");
  if (rounds > 1 && finished[0]) {
    std::printf("  fastest of %d rounds (ratios to h=0; \">=\": a round did not finish):\n", rounds);
    for (std::size_t x = 0; x < runs.size(); ++x) {
      const char* atLeast = finished[x] ? "" : ">=";
      std::printf("    %s: wall %.3f s (%s%.2fx), cpu %.3f s (%s%.2fx)\n", runName(runs[x]).c_str() + 11, bestWall[x],
                  atLeast, bestWall[x] / bestWall[0], bestCpu[x], atLeast, bestCpu[x] / bestCpu[0]);
    }
  }

  // Max-error with uncertainty: certified bracket [lower, upper] of the maxima over poses and geometries.
  const double hMax = 0.0005;
  model::GoughGeometry g = ref.geometry;
  g.setUniformAnchorUncertainty(hMax);
  const model::GoughPlatform robot(g);
  verify::VerifierOptions m;
  m.mode = verify::Mode::MaxError;
  m.alpha = 0.02;
  m.time_limit_s = limit;
  m.threads = 2;
  if (forms.size() == 1 && forms[0] >= 0) m.tuning.decompose_geometry = forms[0] == 1;
  const verify::VerifierResult r = verify::Verifier::run(robot, paper, m);
  urow("paper max-error 2%, +-0.5 mm", r, 0.0);
  std::printf("  (load average after it: %s)\n", bench::loadAverage().c_str());
  std::printf("  bracket (%s): ", r.converged ? "converged to 2%" : "NOT converged");
  for (int k = 0; k < 6; ++k) std::printf("[%.6g, %.6g] ", r.max_lower[k], r.max_upper[k]);
  std::printf("\n");
  for (std::size_t c = 0; c < cases.size(); ++c) {
    if (cases[c] != hMax) continue;
    std::printf("  sampled maxima (h=0.5 mm) / certified lower: ");
    bool inside = true;
    for (int k = 0; k < 6; ++k) {
      std::printf("%.4f ", maxima[c][k] / r.max_lower[k]);
      inside = inside && maxima[c][k] <= r.max_upper[k];
    }
    std::printf("(sampled <= certified upper: %s)\n", inside ? "yes" : "NO");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const double limit = argc > 1 ? std::atof(argv[1]) : 120.0;
  const std::string group = argc > 2 ? argv[2] : "all";
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 3;
  const std::string form = argc > 4 ? argv[4] : "default";
  std::vector<int> forms;
  if (form == "default") forms = {-1};
  if (form == "combined") forms = {0};
  if (form == "decomposed") forms = {1};
  if (form == "both") forms = {0, 1};
  std::vector<double> cases;  // (m; empty: ref6.yaml's)
  bool casesOk = true;
  if (argc > 5) {
    std::string list = argv[5];
    for (std::size_t start = 0; start <= list.size();) {
      const std::size_t end = std::min(list.find(',', start), list.size());
      char* stop = nullptr;
      const std::string item = list.substr(start, end - start);
      const double mm = std::strtod(item.c_str(), &stop);
      casesOk = casesOk && !item.empty() && stop == item.c_str() + item.size() && mm > 0.0 && mm < 100.0;
      cases.push_back(mm * 1e-3);
      start = end + 1;
    }
  }
  if ((group != "all" && group != "nominal" && group != "uncertainty") || rounds < 1 || forms.empty() || !casesOk) {
    std::fprintf(stderr,
                 "usage: verifier_bench [time_limit_s] [all|nominal|uncertainty] [rounds >= 1] "
                 "[default|combined|decomposed|both] [h_mm,h_mm,... (each > 0)]\n");
    return 2;
  }
  const io::RobotFile ref = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const io::RobotFile tiny = io::loadRobotFile(bench::sourceDir() + "/config/tiny_fixed_orientation.yaml");
  const model::GoughPlatform ref6(ref.geometry), tiny6(tiny.geometry);
  const domain::Workspace& paper = ref.workspaces.at("paper");
  const domain::Workspace& paper40 = ref.workspaces.at("paper_40deg");
  const domain::Workspace& fixedWs = tiny.workspaces.at("fixed_orientation");
  if (group == "uncertainty") {
    std::printf("time limit per scenario: %.0f s\n", limit);
    uncertaintyScenarios(ref, paper, limit, rounds, forms, cases);
    return 0;
  }

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
  b.tuning.bisection = verify::Bisection::RoundRobin;
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

  if (group == "all") uncertaintyScenarios(ref, paper, limit, rounds, forms, cases);
  return 0;
}
