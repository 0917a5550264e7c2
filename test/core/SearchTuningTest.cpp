// verify::SearchTuning, the search's internal knobs (no user interface exposes them; benches and tests set them): they
// change how the search goes, not what it certifies. Here the geometry form, on the reference robot with every anchor
// coordinate known to +-0.5 mm over a 2 cm box, where dx reaches ~1.1328e-4 m. (The other knobs are tested with the
// verifier: skip_hopeless in VerifierTest, faces, stall_levels and both forms' answers in UncertaintyVerifierTest,
// every bisection rule in the soundness suite; that the reports write them as run in test/io/ResultWriterTest.)
#include <gtest/gtest.h>

#include "TestRobots.hpp"
#include "pkm_accuracy/core/domain/Workspace.hpp"
#include "pkm_accuracy/core/verify/Verifier.hpp"

using namespace pkm_accuracy;
using verify::Verdict;

namespace {

struct UncertainTinyBox {
  model::GoughGeometry geometry = [] {
    model::GoughGeometry g = test::ref6File().geometry;
    g.setUniformAnchorUncertainty(5e-4);
    return g;
  }();
  model::GoughPlatform robot{geometry};
  domain::Workspace ws =
      domain::Workspace::fromRanges({Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(0.47, 0.48),
                                     Interval(-0.01, 0.01), Interval(-0.01, 0.01), Interval(-0.01, 0.01)});

  /// dx at `dx` m, the other components far from their maxima; one thread (deterministic box counts).
  static verify::VerifierOptions options(double dx) {
    verify::VerifierOptions o;
    o.thresholds = (DVec(6) << dx, 1.3e-4, 1e-3, 1e-2, 1e-2, 1e-2).finished();
    o.threads = 1;
    o.max_boxes = 20000;  // a safety net
    return o;
  }
};

// dx 0.09% above its maximum: the decomposed and the combined geometry forms both certify it, with different searches
// (measured: 1 and 11 boxes).
TEST(SearchTuning, BothGeometryFormsCertifyTheMarginWithDifferentSearches) {
  const UncertainTinyBox s;
  verify::VerifierOptions o = UncertainTinyBox::options(1.1338e-4);
  o.tuning.decompose_geometry = true;
  const verify::VerifierResult decomposed = verify::Verifier::run(s.robot, s.ws, o);
  o.tuning.decompose_geometry = false;
  const verify::VerifierResult combined = verify::Verifier::run(s.robot, s.ws, o);
  EXPECT_EQ(decomposed.verdict, Verdict::Safe) << decomposed.message;
  EXPECT_EQ(combined.verdict, Verdict::Safe) << combined.message;
  EXPECT_NE(decomposed.stats.boxes, combined.stats.boxes);
}

}  // namespace
