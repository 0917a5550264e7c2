// Dot products of affine forms, many at once, with the quadratic part bounded after the sum.
//
// For `count` vectors of n affine forms x_e = (x_{0,e}, ..., x_{n-1,e}) and one vector y = (y_0, ..., y_{n-1}), all
// in the same N noise symbols tau in [-1, 1]^N, out_e encloses x_e . y = sum_l x_{l,e} y_l. With x_{l,e} = c_l +
// a_l . tau + rho_l (|rho_l| <= r_l) and y_l = wc_l + wa_l . tau + sigma_l (|sigma_l| <= wr_l):
//   x_e . y = sum_l (c_l wc_l + c_l wa_l . tau + wc_l a_l . tau) + tau^T Q tau + sum_l (rho_l y_l + (a_l . tau)
//             sigma_l + c_l sigma_l),   Q = sum_l a_l wa_l^T,
// and the quadratic part tau^T Q tau = sum_m Q_mm tau_m^2 + sum_{m < m'} (Q_mm' + Q_m'm) tau_m tau_m' lies in
// sum_m Q_mm / 2 (to the centre) +- (sum_m |Q_mm| / 2 + sum_{m < m'} |Q_mm' + Q_m'm|). Q is formed before any
// magnitude is taken, so the terms of different components l cancel where they do (x_e and y are often nearly
// orthogonal in that part: the geometry derivatives and the nominal expansion's columns, GeometryIncrement); the
// product-by-product bound sum_l (dev(a_l) dev(wa_l) - sum_m |a_lm wa_lm| / 2), what interval::AffineForm's
// operator* gives each term, is kept where it is smaller. The other terms: radius sum_l (|c_l| wr_l + |wc_l| r_l +
// r_l dev(y_l) + slope_l wr_l), slope_l >= sum_m |a_lm| (given).
//
// Layout (struct of arrays, entries innermost, for vectorisable loops): xc[l][e], xa[l][m][e], xr[l][e] (>= 0),
// xslope[l][e] (>= sum_m |xa[l][m][e]|), for l < n, m < N, e < count <= Capacity.
//
// Rounding: each centre, coefficient and Q entry is accumulated through fewer than n (N + 4) + 4 roundings (per l a
// product, a sum over m of at most N products, two additions), so in any IEEE rounding mode its error is below that
// many times 2^-52 (< 2.3e-16) times the sum of the magnitudes of its terms; those magnitudes are summed in err
// (each at least once) and (n (N + 4) + 4) 2.3e-16 err goes to the radius; the radius terms are sums of non-negative
// products, covered by a relative 1e-12. Tested against MPFR in every rounding mode (test/core/AffineDotsMpfrTest.cpp),
// with cases where the bound is attained.
#pragma once

#include <algorithm>
#include <cmath>

#include "pkm_accuracy/core/interval/AffineForm.hpp"

namespace pkm_accuracy {
namespace interval {

template <int N, int Capacity>
void affineDots(int n, int count, const double (*xc)[Capacity], const double (*xa)[N][Capacity],
                const double (*xr)[Capacity], const double (*xslope)[Capacity], const AffineForm<N>* y,
                AffineForm<N>* out) {
  const auto up = [](double x) { return x * (1.0 + 1e-12) + 1e-300; };
  const double errFactor = (n * (N + 4) + 4) * 2.3e-16;
  double c[Capacity], a[N][Capacity], r[Capacity], err[Capacity], plainQ[Capacity];
  double q[N][N][Capacity];  // Q_mm on the diagonal, Q_mm' + Q_m'm above it (the part below is not used)
  for (int e = 0; e < count; ++e) c[e] = r[e] = err[e] = plainQ[e] = 0.0;
  for (int m = 0; m < N; ++m)
    for (int e = 0; e < count; ++e) a[m][e] = 0.0;
  for (int m = 0; m < N; ++m)
    for (int m2 = m; m2 < N; ++m2)
      for (int e = 0; e < count; ++e) q[m][m2][e] = 0.0;
  for (int l = 0; l < n; ++l) {
    const double wc = y[l].centre(), awc = std::abs(wc), wr = y[l].radius();
    double wa[N], devw = wr, waMag = 0.0;
    for (int m = 0; m < N; ++m) {
      wa[m] = y[l].coefficient(m);
      devw += std::abs(wa[m]);
      waMag += std::abs(wa[m]);
    }
    const double* dc = xc[l];
    double half[Capacity], halfMag[Capacity];
    for (int e = 0; e < count; ++e) half[e] = halfMag[e] = 0.0;
    for (int m = 0; m < N; ++m) {
      const double wam = wa[m];
      const double* dm = xa[l][m];
      double* am = a[m];
      for (int e = 0; e < count; ++e) {
        am[e] += dc[e] * wam + wc * dm[e];
        const double d = dm[e] * wam;
        half[e] += d;
        halfMag[e] += std::abs(d);
      }
      for (int e = 0; e < count; ++e) q[m][m][e] += dm[e] * wam;
      for (int m2 = m + 1; m2 < N; ++m2) {
        const double wam2 = wa[m2];
        const double* dm2 = xa[l][m2];
        double* qm = q[m][m2];
        for (int e = 0; e < count; ++e) qm[e] += dm[e] * wam2 + dm2[e] * wam;
      }
    }
    // (The magnitudes of the terms of the centre, coefficients and Q, from the sums of the slopes' magnitudes: the
    // same sums but for rounding far below the 1e-14 margin's slack.)
    for (int e = 0; e < count; ++e) {
      const double x = dc[e], ax = std::abs(x);
      c[e] += x * wc + 0.5 * half[e];
      r[e] += ax * wr + awc * xr[l][e] + xr[l][e] * devw + xslope[l][e] * wr;
      plainQ[e] += xslope[l][e] * waMag - 0.5 * (1.0 - 1e-14) * halfMag[e];
      err[e] += ax * (awc + waMag) + awc * xslope[l][e] + halfMag[e] + 2.0 * xslope[l][e] * waMag;
    }
  }
  for (int e = 0; e < count; ++e) {
    double quad = 0.0;
    for (int m = 0; m < N; ++m) {
      quad += 0.5 * std::abs(q[m][m][e]);
      for (int m2 = m + 1; m2 < N; ++m2) quad += std::abs(q[m][m2][e]);
    }
    double coefficients[N];
    for (int m = 0; m < N; ++m) coefficients[m] = a[m][e];
    out[e] = AffineForm<N>::fromParts(c[e], coefficients, up(r[e] + std::min(quad, plainQ[e]) + errFactor * err[e]));
  }
}

}  // namespace interval
}  // namespace pkm_accuracy
