#include "pkm_accuracy/core/verify/Verifier.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "BranchAndBound.hpp"
#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace verify {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidArgument(message);
}

}  // namespace

void Verifier::validate(const model::RobotModel& model, const domain::Domain& domain, const VerifierOptions& o) {
  const int n = model.dof();
  const int m = domain.variables();
  require(m >= 1 && m <= kMaxDof, "domain: expected 1 to 6 variables, got " + std::to_string(m));
  if (o.mode == Mode::Verify || o.thresholds.size() > 0) {
    require(o.thresholds.size() == n, "thresholds: expected " + std::to_string(n) +
                                          " values (one per component), got " + std::to_string(o.thresholds.size()));
    for (int k = 0; k < n; ++k) {
      std::ostringstream os;
      os << "thresholds[" << k << "] (" << model.componentName(k) << "): expected a finite value > 0, got "
         << o.thresholds[k];
      require(o.thresholds[k] > 0.0 && std::isfinite(o.thresholds[k]), os.str());
    }
  }
  if (o.mode == Mode::MaxError) {
    std::ostringstream os;
    os << "alpha: expected a finite value > 0, got " << o.alpha;
    require(o.alpha > 0.0 && std::isfinite(o.alpha), os.str());
  }
  if (o.min_width.size() > 0) {
    require(o.min_width.size() == m, "min_width: expected " + std::to_string(m) + " values (one per variable), got " +
                                         std::to_string(o.min_width.size()));
    for (int i = 0; i < m; ++i) {
      std::ostringstream os;
      os << "min_width[" << i << "]: expected a finite value >= 0, got " << o.min_width[i];
      require(o.min_width[i] >= 0.0 && std::isfinite(o.min_width[i]), os.str());
    }
  }
  {
    std::ostringstream os;
    os << "time_limit: expected a finite value >= 0 s, got " << o.time_limit_s;
    require(o.time_limit_s >= 0.0 && std::isfinite(o.time_limit_s), os.str());
  }
  require(o.threads >= 0, "threads: expected >= 0 (0 = all cores), got " + std::to_string(o.threads));
  require(o.tuning.stall_levels >= 0,
          "stall_levels: expected >= 0 (0 = half the number of box variables, at least 2), got " +
              std::to_string(o.tuning.stall_levels));
  require(o.presample_points >= 0 && o.presample_points <= 50,
          "presample_points: expected 0 to 50, got " + std::to_string(o.presample_points));
  enclosure::makeEnclosure(o.method);  // throws on an unknown name
  const IVec& box = domain.initialBox();
  for (int i = 0; i < m; ++i) {
    std::ostringstream os;
    os << domain.variableName(i) << ": expected a finite non-empty range, got " << box[i];
    require(!box[i].isEmpty() && box[i].isBounded(), os.str());
  }
}

VerifierResult Verifier::run(const model::RobotModel& model, const domain::Domain& domain,
                             const VerifierOptions& options) {
  validate(model, domain, options);
  BranchAndBound search(model, domain, options);
  return search.run();
}

}  // namespace verify
}  // namespace pkm_accuracy
