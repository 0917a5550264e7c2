#include "SelfCheck.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <memory>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

namespace pkm_accuracy {
namespace verify {
namespace {

/// splitmix64's finaliser: a well-mixed 64-bit hash step.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

std::uint64_t bitsOf(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// Uniform in [lo, hi] (lo itself for a degenerate range).
double uniformIn(double lo, double hi, std::mt19937_64& rng) {
  if (!(hi > lo)) return lo;
  const double v = std::uniform_real_distribution<double>(lo, hi)(rng);
  return std::min(std::max(v, lo), hi);
}

double vertexOf(double lo, double hi, std::mt19937_64& rng) { return (rng() & 1u) ? hi : lo; }

}  // namespace

int SelfCheck::check(const model::RobotModel& model, const std::vector<Interval>& ranges, const IVec& box,
                     unsigned rows, const enclosure::ErrorBounds& bounds) const {
  const int n = model.dof();
  if (bounds.upper.size() != n) return 0;
  std::mt19937_64 rng(seedOf(box, ranges));
  int evaluated = 0;
  for (int i = 0; i < kPoints; ++i) {
    const DVec t = boxPoint(box, i, rng);
    const IVec poseBox = domain_.poseAt(t);
    DVec pose(poseBox.size());
    for (int j = 0; j < poseBox.size(); ++j) pose[j] = poseBox[j].mid();
    std::vector<double> g;
    std::unique_ptr<model::RobotModel> fixed;
    if (!ranges.empty()) {
      g = geometryPoint(ranges, i, rng);
      std::vector<Interval> point(g.size());
      for (std::size_t p = 0; p < g.size(); ++p) point[p] = Interval(g[p]);
      fixed = model.restrictGeometry(point);
    }
    const model::RobotModel& at = fixed ? *fixed : model;
    DVec f;
    double condition = 0.0;
    if (!errorAt(at, pose, f, condition)) continue;
    ++evaluated;
    const double margin = kRelative + kPerCondition * condition;
    for (int k = 0; k < n; ++k) {
      if (!((rows >> k) & 1u)) continue;
      const double upper = bounds.upper[k];
      if (std::isfinite(upper) && f[k] - upper > margin * std::max(f[k], upper)) {
        fail(model, box, ranges, k, "upper", upper, f[k], condition, t, pose, g);
      }
      const double lower = bounds.lower.size() == n ? bounds.lower[k] : 0.0;
      if (lower > 0.0 && lower - f[k] > margin * lower) {
        fail(model, box, ranges, k, "lower", lower, f[k], condition, t, pose, g);
      }
    }
  }
  return evaluated;
}

std::uint64_t SelfCheck::seedOf(const IVec& box, const std::vector<Interval>& ranges) {
  std::uint64_t h = 0x5e1fc4ecull;
  for (int i = 0; i < box.size(); ++i) h = mix(mix(h ^ bitsOf(box[i].lower())) ^ bitsOf(box[i].upper()));
  for (const Interval& r : ranges) h = mix(mix(h ^ bitsOf(r.lower())) ^ bitsOf(r.upper()));
  return h;
}

DVec SelfCheck::boxPoint(const IVec& box, int i, std::mt19937_64& rng) {
  DVec t(box.size());
  for (int v = 0; v < box.size(); ++v) {
    const double lo = box[v].lower(), hi = box[v].upper();
    t[v] =
        i == 0 ? std::min(std::max(box[v].mid(), lo), hi) : (i == 1 ? vertexOf(lo, hi, rng) : uniformIn(lo, hi, rng));
  }
  return t;
}

std::vector<double> SelfCheck::geometryPoint(const std::vector<Interval>& ranges, int i, std::mt19937_64& rng) {
  std::vector<double> g(ranges.size());
  for (std::size_t p = 0; p < ranges.size(); ++p) {
    const double lo = ranges[p].lower(), hi = ranges[p].upper();
    g[p] = i == 2 ? uniformIn(lo, hi, rng) : vertexOf(lo, hi, rng);
  }
  return g;
}

bool SelfCheck::errorAt(const model::RobotModel& model, const DVec& pose, DVec& f, double& condition) {
  const DMat a = model.inverseJacobian(pose);
  DMat inverse;
  if (!enclosure::approximateInverse(a, inverse)) return false;
  const std::vector<double>& e = model.sensorError();
  f = DVec::Zero(model.dof());
  for (int k = 0; k < model.dof(); ++k)
    for (int j = 0; j < model.dof(); ++j) f[k] += std::abs(inverse(k, j)) * e[static_cast<std::size_t>(j)];
  condition = a.cwiseAbs().rowwise().sum().maxCoeff() * inverse.cwiseAbs().rowwise().sum().maxCoeff();
  return f.allFinite();
}

void SelfCheck::fail(const model::RobotModel& model, const IVec& box, const std::vector<Interval>& ranges, int k,
                     const char* which, double bound, double value, double condition, const DVec& t, const DVec& pose,
                     const std::vector<double>& g) const {
  std::ostringstream os;
  os << std::setprecision(17);
  os << "self-check: the enclosure method '" << method_ << "' certified the " << which << " bound " << bound
     << " of the error component " << model.componentName(k) << " on the box";
  for (int i = 0; i < box.size(); ++i) {
    os << (i == 0 ? " " : ", ") << domain_.variableName(i) << " in [" << box[i].lower() << ", " << box[i].upper()
       << "]";
  }
  if (!ranges.empty()) {
    os << " with the geometry ranges";
    for (std::size_t p = 0; p < ranges.size(); ++p) {
      os << (p == 0 ? " " : ", ") << model.geometryParameterName(static_cast<int>(p)) << " in [" << ranges[p].lower()
         << ", " << ranges[p].upper() << "]";
    }
  }
  os << ", but at its point";
  for (int i = 0; i < t.size(); ++i) os << (i == 0 ? " " : ", ") << domain_.variableName(i) << " = " << t[i];
  os << " (pose";
  for (int i = 0; i < pose.size(); ++i) os << (i == 0 ? " " : ", ") << pose[i];
  os << ")";
  if (!g.empty()) {
    os << " and geometry";
    for (std::size_t p = 0; p < g.size(); ++p) {
      os << (p == 0 ? " " : ", ") << model.geometryParameterName(static_cast<int>(p)) << " = " << g[p];
    }
  }
  os << " the worst error evaluated in double is " << value << " (J^-1 condition number " << std::setprecision(3)
     << condition << ")";
  throw InternalError(os.str());
}

}  // namespace verify
}  // namespace pkm_accuracy
