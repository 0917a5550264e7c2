#include <gtest/gtest.h>

#include <random>

#include "pkm_accuracy/core/Exceptions.hpp"
#include "pkm_accuracy/core/domain/PositionRegion.hpp"

using namespace pkm_accuracy;
using domain::Containment;
using domain::PositionRegion;

namespace {

bool insideCylinder(double x, double y, double z) { return x * x + y * y <= 0.04 && z >= 0.4 && z <= 0.5; }

}  // namespace

TEST(PositionRegion, ClassificationAgreesWithPointMembership) {
  const PositionRegion cyl = PositionRegion::cylinder(0.0, 0.0, 0.2, 0.4, 0.5);
  const PositionRegion ball = PositionRegion::sphere(Eigen::Vector3d(0, 0, 0.45), 0.1);
  // Polyhedron: the cube [-0.1, 0.1]^3 cut by x + y <= 0.1.
  const PositionRegion poly = PositionRegion::polyhedron(
      {Eigen::Vector3d(1, 1, 0)}, {0.1}, Eigen::Vector3d(-0.1, -0.1, -0.1), Eigen::Vector3d(0.1, 0.1, 0.1));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.3, 0.3), uz(0.2, 0.7), w(0.0, 0.05);
  int inside = 0, outside = 0, partial = 0;
  for (int t = 0; t < 20000; ++t) {
    const double cx = u(rng), cy = u(rng), cz = uz(rng), h = w(rng);
    const Interval x(cx - h, cx + h), y(cy - h, cy + h), z(cz - h, cz + h);
    const Containment c = cyl.classify(x, y, z);
    inside += c == Containment::Inside;
    outside += c == Containment::Outside;
    partial += c == Containment::Partial;
    for (int s = 0; s < 8; ++s) {
      const double px = (s & 1) ? x.upper() : x.lower(), py = (s & 2) ? y.upper() : y.lower();
      const double pz = (s & 4) ? z.upper() : z.lower();
      if (c == Containment::Inside) {
        EXPECT_TRUE(insideCylinder(px, py, pz));
      }
      if (c == Containment::Outside) {
        EXPECT_FALSE(insideCylinder(px, py, pz));
      }
      const double r2 = px * px + py * py + (pz - 0.45) * (pz - 0.45);
      const Containment cb = ball.classify(x, y, z);
      if (cb == Containment::Inside) {
        EXPECT_LE(r2, 0.01);
      }
      if (cb == Containment::Outside) {
        EXPECT_GT(r2, 0.01);
      }
      const double qx = px * 0.4, qy = py * 0.4, qz = pz - 0.45;
      const Containment cp = poly.classify(x * Interval(0.4), y * Interval(0.4), z - Interval(0.45));
      const bool inPoly = std::abs(qx) <= 0.1 && std::abs(qy) <= 0.1 && std::abs(qz) <= 0.1 && qx + qy <= 0.1;
      if (cp == Containment::Inside) {
        EXPECT_TRUE(inPoly);
      }
      if (cp == Containment::Outside) {
        EXPECT_FALSE(inPoly);
      }
    }
  }
  // All three answers occur (the test is not vacuous).
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
  EXPECT_GT(partial, 100);
}

TEST(PositionRegion, RejectsInvalidParameters) {
  EXPECT_THROW(PositionRegion::cylinder(0, 0, -1, 0, 1), InvalidArgument);
  EXPECT_THROW(PositionRegion::cylinder(0, 0, 1, 1, 0), InvalidArgument);
  EXPECT_THROW(PositionRegion::sphere(Eigen::Vector3d(0, 0, std::nan("")), 1), InvalidArgument);
  EXPECT_THROW(PositionRegion::polyhedron({}, {}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), InvalidArgument);
  EXPECT_THROW(
      PositionRegion::polyhedron({Eigen::Vector3d::Zero()}, {1.0}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
      InvalidArgument);
  EXPECT_THROW(PositionRegion::box(Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 0, 1)), InvalidArgument);
}

// A polyhedron proven empty is refused (a verification over it would be vacuous: SAFE after 0 boxes); a region
// of zero volume that is not empty (a face of the box) is not.
TEST(PositionRegion, EmptyPolyhedronIsRefused) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Ones();
  try {
    PositionRegion::polyhedron({Eigen::Vector3d(1, 0, 0)}, {-0.5}, lo, hi);  // x <= -0.5 misses the box
    ADD_FAILURE() << "accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("polyhedron: empty"), std::string::npos) << e.what();
  }
  // Empty only between two cuts: x + y <= 0.9 and x + y >= 1.0 (proven after bisection).
  EXPECT_THROW(PositionRegion::polyhedron({Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(-1, -1, 0)}, {0.9, -1.0}, lo, hi),
               InvalidArgument);
  // Not empty: the same band with room in it, a single corner, and the face x = 0.
  EXPECT_NO_THROW(
      PositionRegion::polyhedron({Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(-1, -1, 0)}, {1.0, -0.9}, lo, hi));
  EXPECT_NO_THROW(PositionRegion::polyhedron({Eigen::Vector3d(1, 1, 1)}, {0.0}, lo, hi));
  EXPECT_NO_THROW(PositionRegion::polyhedron({Eigen::Vector3d(1, 0, 0)}, {0.0}, lo, hi));
  EXPECT_FALSE(PositionRegion::box(lo, hi).certainlyEmpty());
}
