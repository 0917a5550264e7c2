// The position part of a workspace: a box, a vertical cylinder, a sphere or a convex polyhedron (half-spaces),
// in the base frame (m). classify() answers Inside / Outside / Partial for a box of positions, rigorously.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/domain/Domain.hpp"

namespace pkm_accuracy {
namespace domain {

class PositionRegion {
 public:
  enum class Type { Box, Cylinder, Sphere, Polyhedron };

  /// The axis-aligned box [lo, hi] (per coordinate). @throws InvalidArgument on empty/inverted/non-finite bounds.
  static PositionRegion box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  /// Vertical cylinder: axis through (cx, cy), radius r > 0, z in [zmin, zmax].
  static PositionRegion cylinder(double cx, double cy, double radius, double zmin, double zmax);
  /// Ball of centre c and radius r > 0.
  static PositionRegion sphere(const Eigen::Vector3d& centre, double radius);
  /// Convex polyhedron { p : normals[i] . p <= offsets[i] for all i }, which must be bounded: `bounds_lo`/`bounds_hi`
  /// give a box that contains it (used as the initial search box).
  /// @throws InvalidArgument if the polyhedron is certainly empty (no point of the box satisfies every half-space,
  ///         proven by certainlyEmpty()): a verification over it would be vacuous.
  static PositionRegion polyhedron(const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& offsets,
                                   const Eigen::Vector3d& bounds_lo, const Eigen::Vector3d& bounds_hi);

  Type type() const { return type_; }
  std::string typeName() const;
  /// Axis-aligned bounding box of the region.
  const Eigen::Vector3d& boundsLo() const { return lo_; }
  const Eigen::Vector3d& boundsHi() const { return hi_; }

  /// Certified classification of a box of positions.
  Containment classify(const Interval& x, const Interval& y, const Interval& z) const;
  /// True only if the region is proven empty: a bisection of the bounding box (at most 4096 boxes) classifies
  /// every box Outside. False if some box is Inside, or if the budget ends first (a very thin region).
  bool certainlyEmpty() const;

 private:
  PositionRegion() = default;
  Type type_ = Type::Box;
  Eigen::Vector3d lo_, hi_;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double radius_ = 0.0;
  std::vector<Eigen::Vector3d> normals_;
  std::vector<double> offsets_;
};

}  // namespace domain
}  // namespace pkm_accuracy
