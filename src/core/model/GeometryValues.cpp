#include <algorithm>
#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/model/KinematicModel.hpp"

namespace pkm_accuracy {
namespace model {

namespace {
namespace rnd = interval::rounding;
}  // namespace

GeometryValues::GeometryValues(const RobotDescription& description) {
  description.validate();
  const std::size_t n = description.geometry.size();
  range_.resize(n);
  centreInterval_.resize(n);
  admissible_.resize(n);
  point_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const GeometryValue& g = description.geometry[i];
    if (!g.uncertain()) {
      range_[i] = admissible_[i] = centreInterval_[i] = Interval(g.nominal);
      point_[i] = g.nominal;
      continue;
    }
    // The range covers the reals [nominal + lo, nominal + hi] (rounded outward); the admissible doubles lie inside
    // them (rounded inward; the nominal value itself always qualifies).
    range_[i] = Interval(rnd::addDown(g.nominal, g.lo), rnd::addUp(g.nominal, g.hi));
    admissible_[i] =
        Interval(std::min(g.nominal, rnd::addUp(g.nominal, g.lo)), std::max(g.nominal, rnd::addDown(g.nominal, g.hi)));
    // The point evaluations use the nominal value for a symmetric range, else the centre of the range.
    const double centre = g.lo == -g.hi ? g.nominal : range_[i].mid();
    point_[i] = centre;
    centreInterval_[i] = Interval(centre);
    params_.push_back(static_cast<int>(i));
  }
}

bool GeometryValues::uncertain() const {
  for (int v : params_)
    if (!range_[static_cast<std::size_t>(v)].isPoint()) return true;
  return false;
}

Interval GeometryValues::admissible(int p) const {
  const std::size_t v = static_cast<std::size_t>(valueOf(p));
  return Interval(std::max(range_[v].lower(), admissible_[v].lower()),
                  std::min(range_[v].upper(), admissible_[v].upper()));
}

void GeometryValues::setRange(int value, const Interval& r) {
  const std::size_t v = static_cast<std::size_t>(value);
  range_[v] = r;
  const double m = r.mid();
  point_[v] = m;
  centreInterval_[v] = Interval(m);
}

void GeometryValues::restrict(const std::vector<Interval>& ranges, const RobotDescription& description) {
  if (ranges.size() != params_.size()) {
    throw InvalidArgument("geometry ranges: expected " + std::to_string(params_.size()) + " values, got " +
                          std::to_string(ranges.size()));
  }
  for (std::size_t p = 0; p < params_.size(); ++p) {
    const Interval& current = range_[static_cast<std::size_t>(params_[p])];
    const Interval& r = ranges[p];
    if (r.isEmpty() || r.lower() < current.lower() || r.upper() > current.upper()) {
      std::ostringstream os;
      os << "geometry ranges[" << p << "] (" << description.geometry[static_cast<std::size_t>(params_[p])].name
         << "): expected a non-empty sub-interval of " << current << ", got " << r;
      throw InvalidArgument(os.str());
    }
  }
  for (std::size_t p = 0; p < params_.size(); ++p) setRange(params_[p], ranges[p]);
}

void GeometryValues::fix(const GVec& values, const RobotDescription& description) {
  if (values.size() != static_cast<int>(params_.size())) {
    throw InvalidArgument("geometry values: expected " + std::to_string(params_.size()) + " values, got " +
                          std::to_string(values.size()));
  }
  std::vector<int> kept;
  for (std::size_t p = 0; p < params_.size(); ++p) {
    const double v = values[static_cast<int>(p)];
    const std::size_t index = static_cast<std::size_t>(params_[p]);
    if (std::isnan(v)) {
      kept.push_back(params_[p]);
      continue;
    }
    if (!range_[index].contains(v)) {
      std::ostringstream os;
      os << "geometry values[" << p << "] (" << description.geometry[index].name << "): expected a point of "
         << range_[index] << ", got " << v;
      throw InvalidArgument(os.str());
    }
    setRange(params_[p], Interval(v));
  }
  params_ = kept;
}

}  // namespace model
}  // namespace pkm_accuracy
