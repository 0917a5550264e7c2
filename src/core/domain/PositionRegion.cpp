#include "pkm_accuracy/core/domain/PositionRegion.hpp"

#include <cmath>
#include <sstream>

#include "pkm_accuracy/core/Exceptions.hpp"

namespace pkm_accuracy {
namespace domain {
namespace {

void checkRange(const char* name, double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) {
    std::ostringstream os;
    os << name << ": expected finite bounds with min <= max, got [" << lo << ", " << hi << "]";
    throw InvalidArgument(os.str());
  }
}

void checkPositive(const char* name, double v) {
  if (!std::isfinite(v) || !(v > 0.0)) {
    std::ostringstream os;
    os << name << ": expected a finite value > 0, got " << v;
    throw InvalidArgument(os.str());
  }
}

}  // namespace

PositionRegion PositionRegion::box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  checkRange("x", lo.x(), hi.x());
  checkRange("y", lo.y(), hi.y());
  checkRange("z", lo.z(), hi.z());
  PositionRegion r;
  r.type_ = Type::Box;
  r.lo_ = lo;
  r.hi_ = hi;
  return r;
}

PositionRegion PositionRegion::cylinder(double cx, double cy, double radius, double zmin, double zmax) {
  if (!std::isfinite(cx) || !std::isfinite(cy)) throw InvalidArgument("cylinder centre: expected finite coordinates");
  checkPositive("cylinder radius", radius);
  checkRange("cylinder z", zmin, zmax);
  PositionRegion r;
  r.type_ = Type::Cylinder;
  r.centre_ = Eigen::Vector3d(cx, cy, 0.0);
  r.radius_ = radius;
  r.lo_ = Eigen::Vector3d(interval::rounding::subDown(cx, radius), interval::rounding::subDown(cy, radius), zmin);
  r.hi_ = Eigen::Vector3d(interval::rounding::addUp(cx, radius), interval::rounding::addUp(cy, radius), zmax);
  return r;
}

PositionRegion PositionRegion::sphere(const Eigen::Vector3d& centre, double radius) {
  if (!centre.allFinite()) throw InvalidArgument("sphere centre: expected finite coordinates");
  checkPositive("sphere radius", radius);
  PositionRegion r;
  r.type_ = Type::Sphere;
  r.centre_ = centre;
  r.radius_ = radius;
  for (int k = 0; k < 3; ++k) {
    r.lo_[k] = interval::rounding::subDown(centre[k], radius);
    r.hi_[k] = interval::rounding::addUp(centre[k], radius);
  }
  return r;
}

PositionRegion PositionRegion::polyhedron(const std::vector<Eigen::Vector3d>& normals,
                                          const std::vector<double>& offsets, const Eigen::Vector3d& bounds_lo,
                                          const Eigen::Vector3d& bounds_hi) {
  if (normals.empty()) throw InvalidArgument("polyhedron: expected at least one half-space, got none");
  if (normals.size() != offsets.size()) {
    throw InvalidArgument("polyhedron: expected as many offsets as normals, got " + std::to_string(normals.size()) +
                          " normals and " + std::to_string(offsets.size()) + " offsets");
  }
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (!normals[i].allFinite() || normals[i].norm() == 0.0 || !std::isfinite(offsets[i])) {
      throw InvalidArgument("polyhedron half-space " + std::to_string(i) +
                            ": expected a finite non-zero normal and a finite offset");
    }
  }
  PositionRegion r = box(bounds_lo, bounds_hi);
  r.type_ = Type::Polyhedron;
  r.normals_ = normals;
  r.offsets_ = offsets;
  if (r.certainlyEmpty()) {
    std::ostringstream os;
    os.precision(10);
    os << "polyhedron: empty: no point of the box [" << bounds_lo.x() << ", " << bounds_hi.x() << "] x ["
       << bounds_lo.y() << ", " << bounds_hi.y() << "] x [" << bounds_lo.z() << ", " << bounds_hi.z()
       << "] (m) satisfies every half-space";
    throw InvalidArgument(os.str());
  }
  return r;
}

bool PositionRegion::certainlyEmpty() const {
  // Breadth-first bisection of the bounding box with the certified classify(): empty once every box is Outside;
  // not empty as soon as one is Inside. A region too thin to be resolved within the budget (4096 boxes a level,
  // 65536 in all) counts as not empty, which only leaves it to the verifier.
  constexpr std::size_t kMaxBoxes = 4096, kMaxClassified = 65536;
  std::size_t classified = 0;
  std::vector<std::array<Interval, 3>> level{
      {Interval(lo_.x(), hi_.x()), Interval(lo_.y(), hi_.y()), Interval(lo_.z(), hi_.z())}};
  while (!level.empty()) {
    std::vector<std::array<Interval, 3>> next;
    for (const auto& b : level) {
      if (++classified > kMaxClassified) return false;
      const Containment c = classify(b[0], b[1], b[2]);
      if (c == Containment::Inside) return false;
      if (c == Containment::Outside) continue;
      if (next.size() + 2 > kMaxBoxes) return false;
      int k = 0;
      for (int j = 1; j < 3; ++j) {
        if (b[j].width() > b[k].width()) k = j;
      }
      if (!(b[k].width() > 0.0)) return false;  // a point neither inside nor outside: not certainly empty
      const double mid = b[k].mid();
      if (!(b[k].lower() < mid && mid < b[k].upper())) return false;
      auto lo = b, hi = b;
      lo[k] = Interval(b[k].lower(), mid);
      hi[k] = Interval(mid, b[k].upper());
      next.push_back(lo);
      next.push_back(hi);
    }
    level.swap(next);
  }
  return true;
}

std::string PositionRegion::typeName() const {
  switch (type_) {
    case Type::Box:
      return "box";
    case Type::Cylinder:
      return "cylinder";
    case Type::Sphere:
      return "sphere";
    case Type::Polyhedron:
      return "polyhedron";
  }
  return "?";
}

Containment PositionRegion::classify(const Interval& x, const Interval& y, const Interval& z) const {
  // Constraint functions g(p) <= 0; Inside if every g is certainly <= 0, Outside if some g is certainly > 0.
  bool inside = true;
  auto account = [&](const Interval& g) {
    if (g.lower() > 0.0) return false;  // certainly violated
    if (g.upper() > 0.0) inside = false;
    return true;
  };
  // Bounding-box constraints by exact comparisons (no rounding: a point on a face is inside).
  const Interval p[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    if (p[k].isEmpty() || p[k].lower() > hi_[k] || p[k].upper() < lo_[k]) return Containment::Outside;
    if (p[k].lower() < lo_[k] || p[k].upper() > hi_[k]) inside = false;
  }
  switch (type_) {
    case Type::Box:
      break;
    case Type::Cylinder:
      if (!account(sqr(x - centre_.x()) + sqr(y - centre_.y()) - sqr(Interval(radius_)))) return Containment::Outside;
      break;
    case Type::Sphere:
      if (!account(sqr(x - centre_.x()) + sqr(y - centre_.y()) + sqr(z - centre_.z()) - sqr(Interval(radius_)))) {
        return Containment::Outside;
      }
      break;
    case Type::Polyhedron:
      for (std::size_t i = 0; i < normals_.size(); ++i) {
        const Eigen::Vector3d& n = normals_[i];
        if (!account(Interval(n.x()) * x + Interval(n.y()) * y + Interval(n.z()) * z - Interval(offsets_[i]))) {
          return Containment::Outside;
        }
      }
      break;
  }
  return inside ? Containment::Inside : Containment::Partial;
}

}  // namespace domain
}  // namespace pkm_accuracy
