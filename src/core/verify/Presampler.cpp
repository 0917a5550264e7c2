#include "Presampler.hpp"

#include <algorithm>
#include <cmath>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {

void Presampler::presample() const {
  const VerifierOptions& o = c_.options;
  const int g = o.presample_points;
  if (g <= 0) return;
  std::vector<int> vars;
  for (int i = 0; i < c_.m; ++i)
    if (c_.initWidth[i] > 0.0) vars.push_back(i);
  std::size_t total = 1;
  for (std::size_t v = 0; v < vars.size() && total < 100000; ++v) total *= static_cast<std::size_t>(g);
  if (total >= 100000) return;
  // Double-precision screening, then certification of the promising points only.
  std::vector<double> best(c_.n, -1.0);
  std::vector<DVec> bestPoint(c_.n);
  if (!screen(total, vars, g, best, bestPoint)) return;
  // Uncertain geometry, verify mode: the screening above sees the centre geometry only, whose errors are below the
  // maxima over the geometries (by 5-8% at +-0.5 mm on the reference robot), so the grid's worst point of each
  // component is certified over every geometry as well (an uncertainty-sensitive pose there rules SAFE out at once).
  if (o.mode == Mode::Verify && c_.params > 0 && !certifyBest(best, bestPoint)) return;
  if (o.mode == Mode::MaxError) {
    for (int k = 0; k < c_.n; ++k) {
      if (best[k] < 0.0) continue;
      points_.evaluatePoint(bestPoint[k], c_.thinBox(bestPoint[k]), c_.thinBox(bestPoint[k]));
    }
  }
  // An uncertainty-sensitive pose rules SAFE out; it ends the search (when asked to stop at the first evidence)
  // only now, so that every sampled point could first show a witness for every geometry.
  if (o.mode == Mode::Verify && o.stop_at_first_witness && state_.sensitiveCount() > 0) {
    state_.requestStop(Stop::Sensitive);
  }
}

DVec Presampler::gridPoint(std::size_t index, const std::vector<int>& vars, int g) const {
  const IVec& initial = c_.initial;
  DVec t = domain::centreOf(initial);
  std::size_t rest = index;
  for (int v : vars) {
    const int j = static_cast<int>(rest % g);
    rest /= g;
    t[v] = g == 1 ? initial[v].mid() : initial[v].lower() + (initial[v].upper() - initial[v].lower()) * j / (g - 1);
    t[v] = std::min(std::max(t[v], initial[v].lower()), initial[v].upper());
  }
  return t;
}

bool Presampler::screen(std::size_t total, const std::vector<int>& vars, int g, std::vector<double>& best,
                        std::vector<DVec>& bestPoint) const {
  const VerifierOptions& o = c_.options;
  for (std::size_t idx = 0; idx < total; ++idx) {
    const DVec t = gridPoint(idx, vars, g);
    const IVec thin = c_.thinBox(t);
    if (c_.domain.classify(thin) != domain::Containment::Inside) continue;
    const IVec pose = c_.domain.poseAt(t);
    DVec p(pose.size());
    for (int i = 0; i < pose.size(); ++i) p[i] = pose[i].mid();
    const DVec f = enclosure::errorAtPoseDouble(c_.model, p);
    bool evaluated = false;
    if (o.mode == Mode::Verify) {
      for (int k = 0; k < c_.n; ++k) {
        if (f[k] > o.thresholds[k]) {
          points_.evaluatePoint(t, thin, thin, false);
          if (state_.haveWitness() && o.stop_at_first_witness) return false;
          evaluated = true;
          break;
        }
      }
    }
    for (int k = 0; k < c_.n && !evaluated; ++k) {
      if (std::isfinite(f[k]) && f[k] > best[k]) {
        best[k] = f[k];
        bestPoint[k] = t;
      }
    }
  }
  return true;
}

bool Presampler::certifyBest(const std::vector<double>& best, const std::vector<DVec>& bestPoint) const {
  for (int k = 0; k < c_.n; ++k) {
    bool seen = best[k] < 0.0;  // (no point, or the same point as an earlier component's)
    for (int j = 0; j < k && !seen; ++j) seen = best[j] >= 0.0 && bestPoint[j] == bestPoint[k];
    if (seen) continue;
    points_.evaluatePoint(bestPoint[k], c_.thinBox(bestPoint[k]), c_.thinBox(bestPoint[k]), false);
    if (state_.haveWitness() && c_.options.stop_at_first_witness) return false;
  }
  return true;
}

}  // namespace verify
}  // namespace pkm_accuracy
