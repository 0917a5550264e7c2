// MPFR (200 bits) reference computations for the Gough platform tests: an RAII number type, J^-1 by the conventions
// (docs/conventions.md), Gauss-Jordan inversion and the worst error per component. Independent of the code under
// test (only the geometry struct and the pose are shared).
#pragma once

#include <mpfr.h>

#include <utility>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/model/GoughGeometry.hpp"

namespace pkm_accuracy {
namespace test {

// ---- MPFR (200 bits) ------------------------------------------------------------------------------------------------
struct Mp {
  mpfr_t v;
  Mp() { mpfr_init2(v, 200); }
  explicit Mp(double d) {
    mpfr_init2(v, 200);
    mpfr_set_d(v, d, MPFR_RNDN);
  }
  Mp(const Mp& o) {
    mpfr_init2(v, 200);
    mpfr_set(v, o.v, MPFR_RNDN);
  }
  Mp& operator=(const Mp& o) {
    mpfr_set(v, o.v, MPFR_RNDN);
    return *this;
  }
  ~Mp() { mpfr_clear(v); }
};
inline Mp operator+(const Mp& a, const Mp& b) {
  Mp r;
  mpfr_add(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
inline Mp operator-(const Mp& a, const Mp& b) {
  Mp r;
  mpfr_sub(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
inline Mp operator*(const Mp& a, const Mp& b) {
  Mp r;
  mpfr_mul(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
inline Mp operator/(const Mp& a, const Mp& b) {
  Mp r;
  mpfr_div(r.v, a.v, b.v, MPFR_RNDN);
  return r;
}
inline Mp mpSqrt(const Mp& a) {
  Mp r;
  mpfr_sqrt(r.v, a.v, MPFR_RNDN);
  return r;
}
inline Mp mpSin(const Mp& a) {
  Mp r;
  mpfr_sin(r.v, a.v, MPFR_RNDN);
  return r;
}
inline Mp mpCos(const Mp& a) {
  Mp r;
  mpfr_cos(r.v, a.v, MPFR_RNDN);
  return r;
}
inline Mp mpAbs(const Mp& a) {
  Mp r;
  mpfr_abs(r.v, a.v, MPFR_RNDN);
  return r;
}
inline double toDouble(const Mp& a) { return mpfr_get_d(a.v, MPFR_RNDN); }
inline bool mpLessEqual(const Mp& a, double b) { return mpfr_cmp_d(a.v, b) <= 0; }
inline bool mpGreaterEqual(const Mp& a, double b) { return mpfr_cmp_d(a.v, b) >= 0; }

using MpMat = std::vector<std::vector<Mp>>;

/// J^-1 at pose q of a concrete geometry, by the conventions (docs/conventions.md), in MPFR.
inline MpMat mpInverseJacobian(const model::GoughGeometry& g, const DVec& q) {
  const Mp sr = mpSin(Mp(q[3])), cr = mpCos(Mp(q[3])), sp = mpSin(Mp(q[4])), cp = mpCos(Mp(q[4]));
  const Mp sy = mpSin(Mp(q[5])), cy = mpCos(Mp(q[5]));
  const Mp r[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                      {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                      {Mp(0.0) - sp, cp * sr, cp * cr}};
  MpMat a(6, std::vector<Mp>(6, Mp(0.0)));
  for (int i = 0; i < 6; ++i) {
    Mp d[3], u[3];
    for (int k = 0; k < 3; ++k) {
      Mp rb(0.0), ru(0.0);
      for (int l = 0; l < 3; ++l) {
        rb = rb + r[k][l] * Mp(g.platform_anchors[i][l]);
        ru = ru + r[k][l] * (Mp(g.platform_anchors[i][l]) - Mp(g.tool_point[l]));
      }
      d[k] = Mp(q[k]) + rb - Mp(g.base_anchors[i][k]);
      u[k] = ru;
    }
    const Mp len = mpSqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const Mp n[3] = {d[0] / len, d[1] / len, d[2] / len};
    a[i][0] = n[0];
    a[i][1] = n[1];
    a[i][2] = n[2];
    a[i][3] = u[1] * n[2] - u[2] * n[1];
    a[i][4] = u[2] * n[0] - u[0] * n[2];
    a[i][5] = u[0] * n[1] - u[1] * n[0];
  }
  return a;
}

/// X = A^-1 B (A: n x n, B: n x m) by Gauss-Jordan elimination with partial pivoting, in MPFR.
inline MpMat mpSolve(MpMat a, MpMat b) {
  const int n = static_cast<int>(a.size());
  const int m = static_cast<int>(b[0].size());
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (mpfr_cmpabs(a[i][k].v, a[p][k].v) > 0) p = i;
    std::swap(a[k], a[p]);
    std::swap(b[k], b[p]);
    const Mp piv = a[k][k];
    for (int j = 0; j < n; ++j) a[k][j] = a[k][j] / piv;
    for (int j = 0; j < m; ++j) b[k][j] = b[k][j] / piv;
    for (int i = 0; i < n; ++i) {
      if (i == k) continue;
      const Mp f = a[i][k];
      for (int j = 0; j < n; ++j) a[i][j] = a[i][j] - f * a[k][j];
      for (int j = 0; j < m; ++j) b[i][j] = b[i][j] - f * b[k][j];
    }
  }
  return b;
}

/// Sign of det A (+1, -1; 0 if a pivot vanishes at 200 bits) by Gauss elimination with partial pivoting, in MPFR.
inline int mpDeterminantSign(MpMat a) {
  const int n = static_cast<int>(a.size());
  int sign = 1;
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (mpfr_cmpabs(a[i][k].v, a[p][k].v) > 0) p = i;
    if (p != k) {
      std::swap(a[k], a[p]);
      sign = -sign;
    }
    const int s = mpfr_sgn(a[k][k].v);
    if (s == 0) return 0;
    if (s < 0) sign = -sign;
    for (int i = k + 1; i < n; ++i) {
      const Mp f = a[i][k] / a[k][k];
      for (int j = k; j < n; ++j) a[i][j] = a[i][j] - f * a[k][j];
    }
  }
  return sign;
}

/// The same for a double matrix (its entries exact).
inline int mpDeterminantSign(const DMat& a) {
  MpMat m(a.rows(), std::vector<Mp>(a.cols(), Mp(0.0)));
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) m[i][j] = Mp(a(i, j));
  return mpDeterminantSign(std::move(m));
}

inline MpMat mpIdentity(int n) {
  MpMat id(n, std::vector<Mp>(n, Mp(0.0)));
  for (int i = 0; i < n; ++i) id[i][i] = Mp(1.0);
  return id;
}

/// Worst error of every component at pose q for a concrete geometry: sum_j |J_kj| e_j, J = (J^-1)^-1, in MPFR.
inline std::vector<Mp> mpfrWorstError(const model::GoughGeometry& g, const DVec& q) {
  const MpMat j = mpSolve(mpInverseJacobian(g, q), mpIdentity(6));
  std::vector<Mp> f(6, Mp(0.0));
  for (int k = 0; k < 6; ++k)
    for (int l = 0; l < 6; ++l) f[k] = f[k] + mpAbs(j[k][l]) * Mp(g.sensor_error[l]);
  return f;
}

}  // namespace test
}  // namespace pkm_accuracy
