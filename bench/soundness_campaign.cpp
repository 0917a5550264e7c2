// Randomized soundness campaign (docs/soundness.md, "The randomized soundness suite"): runs random verification
// problems and checks every answer of the verifier against an independent plain oracle (test/support/PlainOracle.hpp,
// SoundnessCases.hpp).
//
//   soundness_campaign SEED COUNT [FIRST] [--profile general|uncertain] [--slice] [--boxes N] [--time S]
//                      [--samples N] [--verbose]
//
// runs the cases FIRST .. FIRST + COUNT - 1 (default FIRST = 0) of the campaign SEED; every case has its own
// generator, so `soundness_campaign SEED 1 I --verbose` re-runs case I alone. --profile uncertain draws only box
// workspaces with anchor uncertainty and the default options; --slice uses the budgets of the CI slice
// (SoundnessSuiteTest: seed 1, profile general) instead of the campaign's larger ones. Prints every failure with the
// case's full description and the counts; exits 1 if any case failed (2 on bad arguments). Reads config/ref6.yaml
// from $PKM_SOURCE_DIR (default: the current directory).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "../test/support/SoundnessCases.hpp"
#include "BenchCommon.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;
namespace sn = pkm_accuracy::test::soundness;

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: soundness_campaign SEED COUNT [FIRST] [--profile general|uncertain] [--slice] [--boxes N]\n"
               "                          [--time S] [--samples N] [--verbose]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  sn::RunSettings settings = sn::campaignSettings();
  sn::Profile profile = sn::Profile::General;
  bool verbose = false;
  std::string options;  // (the budget options given, for the reproduce lines)
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--verbose") {
        verbose = true;
      } else if (a == "--slice") {
        settings = sn::sliceSettings();
        options += " --slice";
      } else if (a == "--profile" && i + 1 < argc) {
        const std::string v = argv[++i];
        if (v != "general" && v != "uncertain") return usage();
        profile = v == "general" ? sn::Profile::General : sn::Profile::Uncertain;
        options += " --profile " + v;
      } else if ((a == "--boxes" || a == "--time" || a == "--samples") && i + 1 < argc) {
        options += " " + a + " " + argv[i + 1];
        const std::string v = argv[++i];
        if (a == "--boxes") settings.maxBoxes = std::stoul(v);
        if (a == "--time") settings.timeLimit = std::stod(v);
        if (a == "--samples") settings.search.samples = std::stoi(v);
      } else if (!a.empty() && a[0] == '-') {
        return usage();
      } else {
        positional.push_back(a);
      }
    }
    if (positional.size() < 2 || positional.size() > 3) return usage();
    const std::uint64_t seed = std::stoull(positional[0]);
    const int count = std::stoi(positional[1]);
    const int first = positional.size() > 2 ? std::stoi(positional[2]) : 0;
    const model::GoughGeometry ref6 = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml").geometry;

    std::printf(
        "soundness_campaign: seed %llu, profile %s, cases %d..%d, %zu boxes and %.1f s per verifier run, %d "
        "oracle samples; load %s\n",
        static_cast<unsigned long long>(seed), sn::profileName(profile).c_str(), first, first + count - 1,
        settings.maxBoxes, settings.timeLimit, settings.search.samples, bench::loadAverage().c_str());
    std::fflush(stdout);
    const auto start = std::chrono::steady_clock::now();
    sn::Counts total;
    for (int index = first; index < first + count; ++index) {
      const auto caseStart = std::chrono::steady_clock::now();
      sn::Counts counts;
      std::vector<std::string> failures;
      std::string description;
      try {
        const sn::Case c = sn::makeCase(seed, index, ref6, profile);
        description = c.description();
        failures = sn::runCase(c, settings, counts);
      } catch (const std::exception& e) {
        failures.push_back(std::string("exception: ") + e.what());
        ++counts.failedCases;
      }
      total.add(counts);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - caseStart).count();
      if (verbose || !failures.empty()) {
        std::printf("%s %s (%.2f s)\n", failures.empty() ? "ok  " : "FAIL", description.c_str(), seconds);
        std::printf("  counts: %s\n", counts.summary().c_str());
      }
      for (const std::string& f : failures) std::printf("  failure: %s\n", f.c_str());
      if (!failures.empty()) {
        std::printf("  reproduce: soundness_campaign %llu 1 %d%s --verbose\n", static_cast<unsigned long long>(seed),
                    index, options.c_str());
      }
      if (!verbose && (index - first + 1) % 50 == 0) {
        std::printf("[%d/%d] %s\n", index - first + 1, count, total.summary().c_str());
      }
      std::fflush(stdout);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("total: %s; %.1f s\n", total.summary().c_str(), seconds);
    return total.failedCases > 0 ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soundness_campaign: %s\n", e.what());
    return 2;
  }
}
