// A scalar type that records which geometry values a quantity depends on: instantiating a model's templated
// kinematics with it gives, for each entry of J^-1, the set of geometry values that appear in its formula. Exact and
// structural (it does not depend on the pose), unlike a test of computed derivatives for zero, which rounding or a
// particular pose could hide. KinematicModel uses it to list which rows of J^-1 each uncertain geometry parameter
// moves (GeometryDerivatives).
#pragma once

#include <bitset>

namespace pkm_accuracy {
namespace model {

/// Largest number of geometry values (certain or not) a model description may have.
constexpr int kMaxGeometryValues = 256;

struct DependencyMask {
  std::bitset<kMaxGeometryValues> bits;

  DependencyMask() = default;
  DependencyMask(double) {}  // NOLINT(runtime/explicit): constants depend on nothing
  static DependencyMask on(int value) {
    DependencyMask m;
    m.bits.set(static_cast<std::size_t>(value));
    return m;
  }

  friend DependencyMask operator+(const DependencyMask& a, const DependencyMask& b) { return join(a, b); }
  friend DependencyMask operator-(const DependencyMask& a, const DependencyMask& b) { return join(a, b); }
  friend DependencyMask operator*(const DependencyMask& a, const DependencyMask& b) { return join(a, b); }
  friend DependencyMask operator/(const DependencyMask& a, const DependencyMask& b) { return join(a, b); }
  friend DependencyMask operator-(const DependencyMask& a) { return a; }
  friend DependencyMask operator+(const DependencyMask& a) { return a; }
  DependencyMask& operator+=(const DependencyMask& o) { return *this = join(*this, o); }
  DependencyMask& operator-=(const DependencyMask& o) { return *this = join(*this, o); }
  DependencyMask& operator*=(const DependencyMask& o) { return *this = join(*this, o); }
  DependencyMask& operator/=(const DependencyMask& o) { return *this = join(*this, o); }

 private:
  static DependencyMask join(const DependencyMask& a, const DependencyMask& b) {
    DependencyMask r;
    r.bits = a.bits | b.bits;
    return r;
  }
};

namespace kin {
inline DependencyMask sqr(const DependencyMask& a) { return a; }
inline DependencyMask sqrt(const DependencyMask& a) { return a; }
inline DependencyMask sin(const DependencyMask& a) { return a; }
inline DependencyMask cos(const DependencyMask& a) { return a; }
inline DependencyMask atan2(const DependencyMask& y, const DependencyMask& x) { return y * x; }
}  // namespace kin

}  // namespace model
}  // namespace pkm_accuracy
