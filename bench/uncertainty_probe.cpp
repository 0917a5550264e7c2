// Where the +-1 mm anchor-uncertainty case loses (docs/uncertainty.md, "Faces"; docs/design-notes.md). For each
// pose component k and boxes of growing size around its sampled worst pose on the `paper` workspace, relative to
// the sampled maximum over poses and geometries:
//   bound   the certified second-order bound over the box and every geometry (what the verifier uses);
//   faces   the same with BoxInput::useFaces (each component on the face of the geometry box where it is certified
//           monotone, in turn on the smaller faces these certify: what stalled search paths use), also certified;
//   vertex  the nominal enclosure over the box with the geometry fixed at the sampled worst vertex g*_k: NOT a bound
//           over every geometry, but what a bound through one geometry could reach (f_k(X, g) <= f_k(X, g*) +
//           penalty) if the penalty were 0;
//   lin     the penalty such a bound would pay with an exact first-order enclosure of d f_k / d g_p over the box
//           (finite differences at the box centre: the centre value +- (sum over pose variables of |d2 f / dg dt|
//           |dt| + sum over parameters of |d2 f / dg dg| h)), and the number of parameters whose monotonicity it
//           would certify; cert: the number of parameters the faces step certified monotone.
// Usage: uncertainty_probe [half-width in m, default 0.001]. Prints a table (double finite differences, not
// certified: a measurement of what is possible, not a result).
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "BenchCommon.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"

using namespace pkm_accuracy;
using Offsets = bench::GeometryMaxima::Offsets;

int main(int argc, char** argv) {
  const double h = argc > 1 ? std::atof(argv[1]) : 1e-3;
  if (!(h > 0.0)) {
    std::fprintf(stderr, "uncertainty_probe: the half-width must be > 0 (m), got '%s'\n", argv[1]);
    return 2;
  }
  const io::RobotFile rf = io::loadRobotFile(bench::sourceDir() + "/config/ref6.yaml");
  const domain::Workspace& ws = rf.workspaces.at("paper");
  const IVec whole = ws.initialBox();
  const auto method = enclosure::makeEnclosure("second_order");
  model::GoughGeometry uncertain = rf.geometry;
  uncertain.setUniformAnchorUncertainty(h);
  const model::GoughPlatform robot(uncertain);
  const bench::GeometryMaxima m = bench::sampledMaximaOverGeometry(rf.geometry, h, whole, 300);
  constexpr int kP = bench::GeometryMaxima::kParams;
  std::printf(
      "anchors +-%.2f mm, paper workspace; boxes: the fraction of the workspace per coordinate around the\n"
      "sampled worst pose of each component; values / sampled maximum over poses and geometries\n",
      h * 1e3);
  std::printf("%-3s %-6s %8s %8s %8s %8s %5s %5s\n", "k", "box", "bound", "faces", "vertex", "lin(%)", "mono", "cert");
  for (int k = 0; k < 6; ++k) {
    const model::GoughPlatform vertex(bench::offsetGeometry(rf.geometry, m.offsets[k]));
    for (double frac : {0.0, 1.0 / 64, 1.0 / 16, 1.0 / 8}) {
      const IVec box = bench::subBox(whole, m.pose[k], frac);
      enclosure::BoxInput in;
      ws.poseView(box, true, in);
      in.rows = 1u << k;
      in.targets = DVec::Zero(6);  // ask for every refinement (face bound included)
      enclosure::ErrorBounds b, v;
      method->enclose(robot, in, b);
      method->enclose(vertex, in, v);
      enclosure::ErrorBounds faced;
      in.useFaces = true;
      in.targets = b.upper * 0.9;  // never good enough: every face step runs
      method->enclose(robot, in, faced);
      const int certified = __builtin_popcountll(faced.faces.up[k] | faced.faces.down[k]);
      // Linearised range of d f_k / d g_p over the box (finite differences around the box centre).
      DVec c(6), dev(6);
      for (int i = 0; i < 6; ++i) {
        c[i] = box[i].mid();
        dev[i] = 0.5 * (box[i].upper() - box[i].lower());
      }
      auto f = [&](const Offsets& d, const DVec& q) { return bench::worstErrorWithOffsets(rf.geometry, d, q)[k]; };
      const double s = 1e-5;
      auto grad = [&](const DVec& q, int p) {
        Offsets a{}, b2{};
        a[p] = s;
        b2[p] = -s;
        return (f(a, q) - f(b2, q)) / (2 * s);
      };
      double penalty = 0.0;
      int monotone = 0;
      for (int p = 0; p < kP; ++p) {
        const double z0 = grad(c, p);
        double w = 0.0;
        for (int i = 0; i < 6; ++i) {
          if (!(dev[i] > 0.0)) continue;
          const double st = 1e-3 * (whole[i].upper() - whole[i].lower());
          DVec qa = c, qb = c;
          qa[i] += st;
          qb[i] -= st;
          w += std::abs((grad(qa, p) - grad(qb, p)) / (2 * st)) * dev[i];
        }
        for (int r = 0; r < kP; ++r) {
          Offsets pp{}, pm{}, mp{}, mm{};
          pp[p] += s, pp[r] += s, pm[p] += s, pm[r] -= s, mp[p] -= s, mp[r] += s, mm[p] -= s, mm[r] -= s;
          w += std::abs((f(pp, c) - f(pm, c) - f(mp, c) + f(mm, c)) / (4 * s * s)) * h;
        }
        const double lo = z0 - w, hi = z0 + w;
        monotone += lo > 0.0 || hi < 0.0;
        // g*_p at the upper end, the lower end or the centre of its range, whichever costs least.
        penalty += std::min({2 * h * std::max(0.0, -lo), 2 * h * std::max(0.0, hi), h * std::max(-lo, hi)});
      }
      char name[16];
      if (frac > 0.0) {
        std::snprintf(name, sizeof name, "1/%.0f", 1.0 / frac);
      } else {
        std::snprintf(name, sizeof name, "pose");
      }
      std::printf("%-3d %-6s %8.4f %8.4f %8.4f %8.2f %5d %5d\n", k, name, b.upper[k] / m.hi[k],
                  faced.upper[k] / m.hi[k], v.upper[k] / m.hi[k], 100.0 * penalty / m.hi[k], monotone, certified);
    }
  }
  return 0;
}
