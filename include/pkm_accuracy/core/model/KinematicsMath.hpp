// The elementary functions a robot model's templated kinematics calls (KinematicModel.hpp), for every scalar type the
// core instantiates it with: double (point evaluation, not certified), Interval (enclosures over boxes) and
// Dual<T, N> nested to any depth and Jet2<T, N> (enclosures of first and second derivatives), the first-order affine
// forms AffineForm / SegmentAffineForm (affine forms of the second derivatives over a box) and DependencyMask.
//
// Models call them qualified, `kin::sqrt(x)`, never `std::sqrt` or an unqualified `sqrt`: these versions are
// domain-checked. Where the argument of sqrt may be negative somewhere in a box (a pose the mechanism cannot reach,
// e.g. the discriminant of a crank's inverse kinematics), kin::sqrt returns Interval::entire() instead of the square
// root of the argument's non-negative part, so that every enclosure computed from it is unbounded and nothing can be
// certified over that box (the verifier bisects it and reports it undecided). In double the same argument gives NaN.
#pragma once

#include <array>
#include <cmath>

#include "pkm_accuracy/core/interval/AffineForm.hpp"
#include "pkm_accuracy/core/interval/Dual.hpp"
#include "pkm_accuracy/core/interval/Functions.hpp"
#include "pkm_accuracy/core/interval/Interval.hpp"
#include "pkm_accuracy/core/interval/InverseTrig.hpp"
#include "pkm_accuracy/core/interval/Jet2.hpp"
#include "pkm_accuracy/core/interval/SegmentAffineForm.hpp"
#include "pkm_accuracy/core/model/DependencyMask.hpp"

namespace pkm_accuracy {
namespace model {
namespace kin {

using interval::Dual;
using interval::Interval;

// ---- double ----------------------------------------------------------------------------------------------------
inline double sqr(double x) { return x * x; }
inline double sqrt(double x) { return std::sqrt(x); }  // NaN for x < 0
inline double sin(double x) { return std::sin(x); }
inline double cos(double x) { return std::cos(x); }
inline double atan2(double y, double x) { return std::atan2(y, x); }

// ---- Interval ---------------------------------------------------------------------------------------------------
inline Interval sqr(const Interval& x) { return interval::sqr(x); }
/// The enclosure of sqrt over x when x >= 0 everywhere; Interval::entire() when x may be negative (or is empty).
inline Interval sqrt(const Interval& x) {
  if (x.isEmpty() || !(x.lower() >= 0.0)) return Interval::entire();
  return interval::sqrt(x);
}
inline Interval sin(const Interval& x) { return interval::sin(x); }
inline Interval cos(const Interval& x) { return interval::cos(x); }
/// atan2 over the box y x x (principal value; [-pi, pi] where the box meets the branch cut or the origin).
inline Interval atan2(const Interval& y, const Interval& x) { return interval::atan2(y, x); }

// ---- first-order affine forms over a box (AffineForm.hpp, SegmentAffineForm.hpp) ---------------------------------
// A result that cannot be bounded (sqrt of a range reaching 0 or below, a division by a range containing 0) is not
// finite: the caller checks finite() and falls back to intervals.
template <int M>
interval::AffineForm<M> sqr(const interval::AffineForm<M>& x) {
  return x * x;
}
template <int M>
interval::AffineForm<M> sqrt(const interval::AffineForm<M>& x) {
  if (!x.finite() || !(x.toInterval().lower() > 0.0)) return interval::AffineForm<M>(std::nan(""));
  return interval::sqrt(x);
}
template <int M>
interval::AffineForm<M> sin(const interval::AffineForm<M>& x) {
  return x.finite() ? interval::sin(x) : interval::AffineForm<M>(std::nan(""));
}
template <int M>
interval::AffineForm<M> cos(const interval::AffineForm<M>& x) {
  return x.finite() ? interval::cos(x) : interval::AffineForm<M>(std::nan(""));
}
template <int M>
interval::SegmentAffineForm<M> sqr(const interval::SegmentAffineForm<M>& x) {
  return x * x;
}
template <int M>
interval::SegmentAffineForm<M> sqrt(const interval::SegmentAffineForm<M>& x) {
  if (!x.finite() || !(x.toInterval().lower() > 0.0)) return interval::SegmentAffineForm<M>(std::nan(""));
  return interval::sqrt(x);
}
template <int M>
interval::SegmentAffineForm<M> sin(const interval::SegmentAffineForm<M>& x) {
  return x.finite() ? interval::sin(x) : interval::SegmentAffineForm<M>(std::nan(""));
}
template <int M>
interval::SegmentAffineForm<M> cos(const interval::SegmentAffineForm<M>& x) {
  return x.finite() ? interval::cos(x) : interval::SegmentAffineForm<M>(std::nan(""));
}

// ---- Jet2<T, N> (first and second derivatives; Jet2.hpp) ------------------------------------------------------
using interval::Jet2;

template <typename T, int N>
Jet2<T, N> sqr(const Jet2<T, N>& x) {
  return x * x;
}
/// s = sqrt(x) from s^2 = x: s' = x' / (2 s), s''_ab = (x''_ab - 2 s'_a s'_b) / (2 s); unbounded where x may be
/// <= 0 (kin::sqrt of T).
template <typename T, int N>
Jet2<T, N> sqrt(const Jet2<T, N>& x) {
  const T s = kin::sqrt(x.value());
  if (x.order() == 0) return Jet2<T, N>(s);
  const T inv = T(1.0) / (s * 2.0);
  std::array<T, N> g;
  for (int i = 0; i < N; ++i) g[i] = x.d(i) * inv;
  return Jet2<T, N>(s).withDerivatives(g, [&](int a, int b) { return (x.d2(a, b) - (g[a] * g[b]) * 2.0) * inv; });
}
template <typename T, int N>
Jet2<T, N> sin(const Jet2<T, N>& x) {
  const T s = kin::sin(x.value());
  return Jet2<T, N>::chain(x, s, kin::cos(x.value()), -s);
}
template <typename T, int N>
Jet2<T, N> cos(const Jet2<T, N>& x) {
  const T c = kin::cos(x.value());
  return Jet2<T, N>::chain(x, c, -kin::sin(x.value()), -c);
}
/// theta = atan2(y, x): d theta = (x dy - y dx) / r^2 with r^2 = x^2 + y^2, and
/// d2 theta_ab = (x_a y_b + x y_ab - y_a x_b - y x_ab) / r^2 - d theta_b (2 (x x_a + y y_a)) / r^2.
template <typename T, int N>
Jet2<T, N> atan2(const Jet2<T, N>& y, const Jet2<T, N>& x) {
  const T& xv = x.value();
  const T& yv = y.value();
  if (x.order() == 0 && y.order() == 0) return Jet2<T, N>(kin::atan2(yv, xv));
  const T r2 = kin::sqr(xv) + kin::sqr(yv);
  std::array<T, N> g;
  for (int i = 0; i < N; ++i) g[i] = (xv * y.d(i) - yv * x.d(i)) / r2;
  return Jet2<T, N>(kin::atan2(yv, xv)).withDerivatives(g, [&](int a, int b) {
    return (x.d(a) * y.d(b) + xv * y.d2(a, b) - y.d(a) * x.d(b) - yv * x.d2(a, b)) / r2 -
           g[b] * ((xv * x.d(a) + yv * y.d(a)) * 2.0) / r2;
  });
}

// ---- Dual<T, N> (forward-mode derivatives; T may itself be a Dual) ----------------------------------------------
template <typename T, int N>
Dual<T, N> sqr(const Dual<T, N>& a);
template <typename T, int N>
Dual<T, N> sqrt(const Dual<T, N>& a);
template <typename T, int N>
Dual<T, N> sin(const Dual<T, N>& a);
template <typename T, int N>
Dual<T, N> cos(const Dual<T, N>& a);
template <typename T, int N>
Dual<T, N> atan2(const Dual<T, N>& y, const Dual<T, N>& x);

template <typename T, int N>
Dual<T, N> sqr(const Dual<T, N>& a) {
  Dual<T, N> r(kin::sqr(a.value()));
  const T twoV = a.value() * 2.0;
  for (int i = 0; i < N; ++i) r.d(i) = twoV * a.d(i);
  return r;
}
template <typename T, int N>
Dual<T, N> sqrt(const Dual<T, N>& a) {
  const T s = kin::sqrt(a.value());
  Dual<T, N> r(s);
  const T twoS = s * 2.0;
  for (int i = 0; i < N; ++i) r.d(i) = a.d(i) / twoS;
  return r;
}
template <typename T, int N>
Dual<T, N> sin(const Dual<T, N>& a) {
  Dual<T, N> r(kin::sin(a.value()));
  const T c = kin::cos(a.value());
  for (int i = 0; i < N; ++i) r.d(i) = c * a.d(i);
  return r;
}
template <typename T, int N>
Dual<T, N> cos(const Dual<T, N>& a) {
  Dual<T, N> r(kin::cos(a.value()));
  const T ms = -kin::sin(a.value());
  for (int i = 0; i < N; ++i) r.d(i) = ms * a.d(i);
  return r;
}
/// d atan2(y, x) = (x dy - y dx) / (x^2 + y^2), valid on both sides of the branch cut.
template <typename T, int N>
Dual<T, N> atan2(const Dual<T, N>& y, const Dual<T, N>& x) {
  Dual<T, N> r(kin::atan2(y.value(), x.value()));
  const T den = kin::sqr(x.value()) + kin::sqr(y.value());
  for (int i = 0; i < N; ++i) r.d(i) = (x.value() * y.d(i) - y.value() * x.d(i)) / den;
  return r;
}

// ---- small vector helpers for 3-vectors of any scalar -------------------------------------------------------------
template <typename T>
using Vec3 = std::array<T, 3>;

template <typename T>
T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
/// R = Rz(yaw) Ry(pitch) Rx(roll) (row-major r[i][j]), the pose convention of every 6-dof model.
template <typename T>
std::array<Vec3<T>, 3> rotationRpy(const T& roll, const T& pitch, const T& yaw) {
  const T cr = kin::cos(roll), sr = kin::sin(roll);
  const T cp = kin::cos(pitch), sp = kin::sin(pitch);
  const T cy = kin::cos(yaw), sy = kin::sin(yaw);
  return {Vec3<T>{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
          Vec3<T>{sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr}, Vec3<T>{-sp, cp * sr, cp * cr}};
}
/// R v.
template <typename T>
Vec3<T> rotate(const std::array<Vec3<T>, 3>& r, const Vec3<T>& v) {
  return {dot(r[0], v), dot(r[1], v), dot(r[2], v)};
}

}  // namespace kin
}  // namespace model
}  // namespace pkm_accuracy
