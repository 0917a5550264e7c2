#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"

#include <Eigen/LU>
#include <cmath>
#include <utility>

namespace pkm_accuracy {
namespace enclosure {

IMat multiply(const DMat& c, const IMat& a) {
  IMat r(c.rows(), a.cols());
  for (int i = 0; i < c.rows(); ++i) {
    for (int j = 0; j < a.cols(); ++j) {
      Interval s(0.0);
      for (int k = 0; k < c.cols(); ++k) s += Interval(c(i, k)) * a(k, j);
      r(i, j) = s;
    }
  }
  return r;
}

IMat multiply(const IMat& a, const DMat& c) {
  IMat r(a.rows(), c.cols());
  for (int i = 0; i < a.rows(); ++i) {
    for (int j = 0; j < c.cols(); ++j) {
      Interval s(0.0);
      for (int k = 0; k < a.cols(); ++k) s += a(i, k) * Interval(c(k, j));
      r(i, j) = s;
    }
  }
  return r;
}

namespace {

// Midpoint m and a radius r with [m - r, m + r] containing the interval (r rounded up, also covering a midpoint
// that is not exactly central).
void midRad(const IMat& a, DMat& m, DMat& r) {
  m.resize(a.rows(), a.cols());
  r.resize(a.rows(), a.cols());
  for (int i = 0; i < a.rows(); ++i) {
    for (int j = 0; j < a.cols(); ++j) {
      const double mid = a(i, j).mid();
      m(i, j) = mid;
      r(i, j) = interval::radiusAbout(a(i, j), mid);
    }
  }
}

// From s = fl(X Y), p = fl(|X| |Y_mid|) and q = fl(|X| rad) (inner dimension n), the enclosure of the exact product
// set. In any rounding mode each operation has relative error below u = 2^-52 (plus an absolute 2^-1074 on
// underflow), so |s - exact mid product| <= gamma_n p_exact and p_exact <= (1 + gamma_n) p, q_exact <= (1 +
// gamma_n) q, gamma_n = n u / (1 - n u). The radius bound below over-covers these terms with explicit margins.
IMat assemble(const DMat& s, const DMat& p, const DMat& q, int n) {
  const double u = 0x1p-52;
  const double gamma = (n + 2) * u / (1.0 - (n + 2) * u);
  const double tiny = 1e-300;  // >> 2n * 2^-1074, the underflow terms
  IMat out(s.rows(), s.cols());
  for (int i = 0; i < s.rows(); ++i) {
    for (int j = 0; j < s.cols(); ++j) {
      // r >= (1 + gamma) q + gamma (1 + gamma) p, evaluated with an extra relative margin for its own roundings.
      const double r = interval::rounding::nextUp((q(i, j) + gamma * 2.0 * p(i, j)) * (1.0 + 4.0 * gamma) + tiny);
      out(i, j) =
          Interval::fromBoundsUnchecked(interval::rounding::subDown(s(i, j), r), interval::rounding::addUp(s(i, j), r));
      if (!std::isfinite(r) || !std::isfinite(s(i, j))) out(i, j) = Interval::entire();
    }
  }
  return out;
}

}  // namespace

IMat multiplyMidRad(const DMat& c, const IMat& a) {
  DMat m, r;
  midRad(a, m, r);
  const DMat ac = c.cwiseAbs();
  // Coefficient-based products (lazyProduct): 6 x 6 is far too small for Eigen's blocked GEMM.
  return assemble(c.lazyProduct(m), ac.lazyProduct(m.cwiseAbs()), ac.lazyProduct(r), static_cast<int>(c.cols()));
}

IMat multiplyMidRad(const IMat& a, const DMat& c) {
  DMat m, r;
  midRad(a, m, r);
  const DMat ac = c.cwiseAbs();
  return assemble(m.lazyProduct(c), m.cwiseAbs().lazyProduct(ac), r.lazyProduct(ac), static_cast<int>(c.rows()));
}

IMat multiply(const IMat& a, const IMat& b) {
  IMat r(a.rows(), b.cols());
  for (int i = 0; i < a.rows(); ++i) {
    for (int j = 0; j < b.cols(); ++j) {
      Interval s(0.0);
      for (int k = 0; k < a.cols(); ++k) s += a(i, k) * b(k, j);
      r(i, j) = s;
    }
  }
  return r;
}

namespace {

/// Partial pivoting: the row (from k on) whose entry in column k has the largest mignitude (k on ties).
int pivotRow(const IMat& a, int k) {
  int p = k;
  double best = a(k, k).mig();
  for (int i = k + 1; i < a.rows(); ++i) {
    if (a(i, k).mig() > best) {
      best = a(i, k).mig();
      p = i;
    }
  }
  return p;
}

}  // namespace

bool gaussSolve(IMat a, IMat b, IMat& x, bool pivoting) {
  const int n = static_cast<int>(a.rows());
  const int m = static_cast<int>(b.cols());
  for (int k = 0; k < n; ++k) {
    if (pivoting) {
      const int p = pivotRow(a, k);
      if (p != k) {
        a.row(k).swap(a.row(p));
        b.row(k).swap(b.row(p));
      }
    }
    const Interval piv = a(k, k);
    if (piv.isEmpty() || piv.containsZero()) return false;
    for (int i = k + 1; i < n; ++i) {
      if (a(i, k) == Interval(0.0)) continue;
      const Interval f = a(i, k) / piv;
      for (int j = k + 1; j < n; ++j) a(i, j) -= f * a(k, j);
      for (int j = 0; j < m; ++j) b(i, j) -= f * b(k, j);
    }
  }
  x.resize(n, m);
  for (int i = n - 1; i >= 0; --i) {
    for (int j = 0; j < m; ++j) {
      Interval s = b(i, j);
      for (int l = i + 1; l < n; ++l) s -= a(i, l) * x(l, j);
      x(i, j) = s / a(i, i);
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (!x(i, j).isBounded()) return false;
  return true;
}

bool gaussInverse(const IMat& a, IMat& inverse, bool pivoting) {
  const int n = static_cast<int>(a.rows());
  IMat id(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) id(i, j) = Interval(i == j ? 1.0 : 0.0);
  return gaussSolve(a, id, inverse, pivoting);
}

namespace {

/// determinantSign() without the preconditioning.
int eliminationSign(IMat a) {
  const int n = static_cast<int>(a.rows());
  if (n == 0 || a.cols() != n) return 0;
  int sign = 1;
  for (int k = 0; k < n; ++k) {
    const int p = pivotRow(a, k);
    if (p != k) {
      a.row(k).swap(a.row(p));
      sign = -sign;
    }
    const Interval piv = a(k, k);
    if (piv.isEmpty() || !piv.isBounded() || piv.containsZero()) return 0;
    if (piv.upper() < 0.0) sign = -sign;
    for (int i = k + 1; i < n; ++i) {
      if (a(i, k) == Interval(0.0)) continue;
      const Interval f = a(i, k) / piv;
      for (int j = k + 1; j < n; ++j) a(i, j) -= f * a(k, j);
    }
  }
  return sign;
}

}  // namespace

int determinantSign(const IMat& a) {
  const int direct = eliminationSign(a);
  if (direct != 0) return direct;
  DMat c;
  if (!approximateInverse(midpoint(a), c)) return 0;
  const int preconditioned = eliminationSign(multiply(c, a));
  if (preconditioned == 0) return 0;
  IMat ci(c.rows(), c.cols());
  for (int i = 0; i < c.rows(); ++i)
    for (int j = 0; j < c.cols(); ++j) ci(i, j) = Interval(c(i, j));
  return preconditioned * eliminationSign(ci);
}

bool approximateInverse(const DMat& a, DMat& inverse) {
  if (!a.allFinite()) return false;
  Eigen::PartialPivLU<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>> lu(a);
  inverse = lu.inverse();
  if (!inverse.allFinite()) return false;
  // Reject numerically singular matrices: the preconditioner would be useless and may overflow.
  const double cond = a.cwiseAbs().rowwise().sum().maxCoeff() * inverse.cwiseAbs().rowwise().sum().maxCoeff();
  return cond < 1e14;
}

DMat midpoint(const IMat& a) {
  DMat m(a.rows(), a.cols());
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) m(i, j) = a(i, j).mid();
  return m;
}

}  // namespace enclosure
}  // namespace pkm_accuracy
