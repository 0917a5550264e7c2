#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

namespace pkm_accuracy {
namespace enclosure {
namespace {

// Everything below is computed in double, in midpoint-radius form, with a priori rounding-error bounds valid in
// any rounding mode (interval/Rounding.hpp): a sum of at most 64 products has relative error below gamma(66), so
//   |fl(A B) - A B| <= kGamma |A| |B|  (computed, also in floating point: the margin covers that),
// and a non-negative quantity evaluated in floating point is bounded by up(its computed value).
constexpr double kGamma = 1e-13;
static_assert(kGamma >= 4.0 * interval::rounding::gamma(66), "kGamma covers the products and their own rounding");
using interval::rounding::up;

/// up() of every entry.
template <typename M>
M upAll(const M& m) {
  return interval::rounding::upEach(m);
}

/// Midpoint and radius (rounded up) of an interval.
inline void split(const Interval& x, double& m, double& r) {
  m = x.mid();
  r = up(interval::radiusAbout(x, m));
}

template <typename M>
void split(const IMat& a, M& m, M& r) {
  m.resize(a.rows(), a.cols());
  r.resize(a.rows(), a.cols());
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) split(a(i, j), m(i, j), r(i, j));
}

/// Rigorous midpoint-radius product: [am +- ar] [bm +- br] within [m +- r], with
///   r = up(|am| (br + gamma |bm|) + ar (|bm| + br))
/// (plain loops, column by column with the rows innermost: these matrices are at most 64 x 6 times 6 x 6, too small
/// for blocked GEMM, and Eigen's lazy products of dynamic sizes do not vectorise here).
/// (kRows > 0: the row count known at compile time, so that the inner loops unroll; the same operations in the same
/// order as with kRows = 0, i.e. bit-identical results.)
template <int kRows, typename A, typename B, typename R>
void productRows(const A& am, const A& ar, const B& bm, const B& br, R& m, R& r) {
  const int rows = kRows > 0 ? kRows : static_cast<int>(am.rows());
  const int inner = static_cast<int>(am.cols()), cols = static_cast<int>(bm.cols());
  m.setZero(rows, cols);
  r.setZero(rows, cols);
  for (int c = 0; c < cols; ++c) {
    double* mc = &m(0, c);
    double* rc = &r(0, c);
    for (int l = 0; l < inner; ++l) {
      const double b = bm(l, c), ba = std::abs(b);
      const double in = br(l, c) + kGamma * ba, out = ba + br(l, c);
      const double* a = &am(0, l);
      const double* ad = &ar(0, l);
      for (int i = 0; i < rows; ++i) {
        mc[i] += a[i] * b;
        rc[i] += std::abs(a[i]) * in + ad[i] * out;
      }
    }
    for (int i = 0; i < rows; ++i) rc[i] = up(rc[i]);
  }
}

template <typename A, typename B, typename R>
void product(const A& am, const A& ar, const B& bm, const B& br, R& m, R& r) {
  if (am.rows() == 6) {
    productRows<6>(am, ar, bm, br, m, r);  // the Gough platform's 6 x 6 products
  } else {
    productRows<0>(am, ar, bm, br, m, r);
  }
}

/// up(A B) for non-negative A (entries x n, column-major) and B (n x m): the loop runs over A's rows innermost, so it
/// vectorises (Eigen's lazy product of these dynamic sizes does not); every term is >= 0, so up() covers the roundings.
template <typename A, typename B>
A nonNegativeProduct(const A& a, const B& b) {
  const int rows = static_cast<int>(a.rows()), inner = static_cast<int>(a.cols()), cols = static_cast<int>(b.cols());
  A out(rows, cols);
  if (inner == 6) {
    // The common case in one pass per column (the same sums in the same order as below, so the same results).
    // (Pointers from data(), not a(0, l): the matrices may have no rows.)
    const double* __restrict c0 = a.data() + 0 * a.outerStride();
    const double* __restrict c1 = a.data() + 1 * a.outerStride();
    const double* __restrict c2 = a.data() + 2 * a.outerStride();
    const double* __restrict c3 = a.data() + 3 * a.outerStride();
    const double* __restrict c4 = a.data() + 4 * a.outerStride();
    const double* __restrict c5 = a.data() + 5 * a.outerStride();
    for (int j = 0; j < cols; ++j) {
      double* __restrict o = out.data() + j * out.outerStride();
      const double x0 = b(0, j), x1 = b(1, j), x2 = b(2, j), x3 = b(3, j), x4 = b(4, j), x5 = b(5, j);
      for (int e = 0; e < rows; ++e) {
        double s = 0.0;
        s += c0[e] * x0;
        s += c1[e] * x1;
        s += c2[e] * x2;
        s += c3[e] * x3;
        s += c4[e] * x4;
        s += c5[e] * x5;
        o[e] = up(s);
      }
    }
    return out;
  }
  out.setZero();
  for (int j = 0; j < cols; ++j) {
    double* o = out.data() + j * out.outerStride();
    for (int l = 0; l < inner; ++l) {
      const double x = b(l, j);
      const double* col = a.data() + l * a.outerStride();
      for (int e = 0; e < rows; ++e) o[e] += col[e] * x;
    }
    for (int e = 0; e < rows; ++e) o[e] = up(o[e]);
  }
  return out;
}

/// The product a b in floating point (a: at most kEntries rows, column-major; b: a.cols() x m), each column's sums in
/// the order of b's rows, the rows innermost (so it vectorises; Eigen's lazy products of these dynamic sizes do not):
/// f(e, j, (a b)(e, j)) for every entry. The callers' rounding margins hold for any order of the sums.
template <int kRows, typename A, typename B, typename F>
void productEachRows(const A& a, const B& b, F& f) {
  const int rows = kRows > 0 ? kRows : static_cast<int>(a.rows());
  const int inner = static_cast<int>(a.cols()), cols = static_cast<int>(b.cols());
  eigen_assert(rows <= PreconditionedInverseEnclosure::kEntries);
  double acc[kRows > 0 ? kRows : PreconditionedInverseEnclosure::kEntries];
  for (int j = 0; j < cols; ++j) {
    for (int e = 0; e < rows; ++e) acc[e] = 0.0;
    for (int l = 0; l < inner; ++l) {
      const double x = b(l, j);
      const double* __restrict col = a.data() + l * a.outerStride();
      for (int e = 0; e < rows; ++e) acc[e] += col[e] * x;
    }
    for (int e = 0; e < rows; ++e) f(e, j, acc[e]);
  }
}

template <typename A, typename B, typename F>
void productEach(const A& a, const B& b, F&& f) {
  if (a.rows() == 6) {
    productEachRows<6>(a, b, f);  // (the Gough platform's n x n factors: the loops unroll)
  } else {
    productEachRows<0>(a, b, f);
  }
}

/// a b as an R, computed by productEach().
template <typename R, typename A, typename B>
R mul(const A& a, const B& b) {
  R out(a.rows(), b.cols());
  productEach(a, b, [&out](int e, int j, double x) { out(e, j) = x; });
  return out;
}

/// z >= (I - a)^-1 rhs column by column for a >= 0 (square), verified (approx: any approximation of (I - a)^-1).
/// @return false if the verification fails.
template <typename A, typename R>
bool fixedPoint(const A& a, const A& approx, const R& rhs, R& z) {
  // If (I - A) z >= w > 0 with w >= rhs then A z < z, so rho(A) < 1, (I - A)^-1 >= 0 and every x >= 0 with
  // x <= rhs + A x satisfies x <= (I - A)^-1 rhs <= z.
  const int m = static_cast<int>(rhs.cols()), n = static_cast<int>(rhs.rows());
  R w = rhs;
  for (int j = 0; j < m; ++j) {
    const double largest = rhs.col(j).maxCoeff();
    // A floor relative to the column keeps the verification below from failing on entries of rhs that are tiny
    // next to the others (their slack would drown in the rounding margins); it only loosens z by 1e-9 of rhs max.
    for (int l = 0; l < n; ++l) w(l, j) += 1e-300 + 1e-9 * largest;
  }
  z = mul<R>(approx, w);
  for (int j = 0; j < m; ++j)
    for (int l = 0; l < n; ++l) z(l, j) = up(std::max(z(l, j), w(l, j))) * (1.0 + 1e-9);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const R next = upAll(R(w + upAll(mul<R>(a, z))));
    bool ok = true;
    for (int j = 0; j < m; ++j) {
      bool column = true;
      for (int l = 0; l < n; ++l) column = column && next(l, j) <= z(l, j);
      if (column) continue;
      // Raise the whole column (raising single entries would break the others through |E|).
      ok = false;
      for (int l = 0; l < n; ++l) z(l, j) = std::max(z(l, j), next(l, j)) * 1.01;
    }
    if (ok) return z.allFinite();
  }
  return false;
}

/// Accumulators for productEach(): to(e, j) += |x| scale, and to(e, j) += x.
template <typename M>
auto addAbsTo(M& to, double scale) {
  return [&to, scale](int e, int j, double x) { to(e, j) += std::abs(x) * scale; };
}

template <typename M>
auto addTo(M& to) {
  return [&to](int e, int j, double x) { to(e, j) += x; };
}

}  // namespace

bool PreconditionedInverseEnclosure::fixedPointBound(const DMat& a, const DMat& approx, const DMat& rhs, DMat& z) {
  return fixedPoint(a, approx, rhs, z);
}

bool PreconditionedInverseEnclosure::prepare(const model::RobotModel& model, const BoxInput& box,
                                             GeometryTerms geometry) {
  if (!prepareCentre(model, box, geometry == GeometryTerms::Expanded)) return false;
  preparePoseSlopes(model, box);
  boundPoseMagnitudes();
  storeGeometryEntries(model);
  const DMat magL = boundGeometryMagnitudes();
  boundDotProducts();
  prepareBilinear(box);
  prepareAffineDeviations();
  approximateInverses();
  return q_.allFinite() && magE_.allFinite() && alpha_.allFinite() && magL.allFinite();
}

bool PreconditionedInverseEnclosure::prepareCentre(const model::RobotModel& model, const BoxInput& box,
                                                   bool withGeometry) {
  n_ = model.dof();
  vars_ = box.variables;
  params_ = withGeometry ? model.geometryParameterCount() : 0;
  if ((withGeometry && params_ <= 0) || params_ > kMaxGeometryParameters) return false;
  const IMat centre = model.inverseJacobianAtGeometryCentre(box.centrePose);
  if (!approximateInverse(midpoint(centre), c_)) return false;
  GeometryDerivatives& geo = work_.geo;
  // E(t, g) - E0 = [E(t, g) - E(t, g0)] + [E(t, g0) - E(t0, g0)]: geometry derivatives over the pose box and every
  // geometry, pose derivatives over the pose box at the centre geometry (both mean-value forms, exact).
  geo.count = 0;
  if (withGeometry && (!model.geometryDerivatives(box.pose, geo) || geo.count <= 0)) return false;
  entries_ = geo.count;

  IMat e0 = multiplyMidRad(c_, centre);
  for (int i = 0; i < n_; ++i) e0(i, i) -= Interval(1.0);
  split(e0, e0m_, e0r_);
  return true;
}

void PreconditionedInverseEnclosure::preparePoseSlopes(const model::RobotModel& model, const BoxInput& box) {
  // Centred form of the pose derivatives: D_i(t) = C dJ^-1/dt_i(t) = D_i(t0) + sum_l C H_il(xi) (t_l - t0_l), xi in the
  // box (entry by entry), so D_i over the box lies in D_i(t0) + sum_l [C H_il(box)] [-dev_l, dev_l]. C H keeps the
  // cancellations between legs (C ~ J) that the direct enclosure C [dJ^-1/dt_i(box)] loses, where every leg's
  // variation over the box adds up in magnitude: on boxes of 1/8 of every range at the paper workspace's corners the
  // bounds of f_k drop from 22-104% to 5-26% above the sampled maxima (ErrorEnclosureTest), and the search keeps 8x
  // fewer boxes. With the interval Hessian both enclosures are valid and their intersection is kept; with the model's
  // affine bound of |C H_il| (below) the centred range alone, which is then always the narrower. Only where the box
  // variables are the pose coordinates themselves (workspace boxes; the Hessian is with respect to the pose) and the
  // model provides it. (A model call gives the first derivatives at the centre, in place of the dual-number evaluation
  // of the direct path; the interval Hessian's call also those over the box.)
  const HessianSource source = boundHessian(model, box);
  rangeSlopes(model, box, source);
  if (!source.centred()) return;
  std::array<DMat, kMaxDof> tm, tr;  // Taylor slopes D_i(t0) + (1/2) sum_l C H_il(box) [-dev_l, dev_l] (below)
  for (int i = 0; i < vars_; ++i) centredSlope(i, source, tm[i], tr[i]);
  chooseTaylorSlopes(tm, tr);
  if (residualOk_) prepareResidualWeights();
}

PreconditionedInverseEnclosure::HessianSource PreconditionedInverseEnclosure::boundHessian(
    const model::RobotModel& model, const BoxInput& box) {
  Workspace& w = work_;
  HessianSource source;
  residualOk_ = false;
  magNOk_ = magNFailed_ = false;
  const bool poseBox = vars_ == n_ && box.variablesArePose(n_);
  source.midpoint = poseBox;
  for (int i = 0; i < vars_ && source.midpoint; ++i) {
    const Interval& c = box.centrePose[i];
    source.midpoint = c.lower() == c.upper() && c.lower() == box.pose[i].mid();
  }
  bool atCentreOk = poseBox && model.inverseJacobianHessianAtGeometryCentre(box.centrePose, w.atCentre, false);
  for (int i = 0; i < vars_ && atCentreOk; ++i) atCentreOk = w.atCentre.first[i].rows() == n_;
  // |C H_il| over the box: preferably the model's bound through affine forms of H in the pose (C keeps its
  // cancellations against the Hessian's variation over the box, which |C| rad(H) of the interval Hessian loses: on the
  // paper workspace's deciding boxes the sampled variation of C H is 1/14 of that; docs/enclosures.md);
  // else the interval Hessian over the box, |C Hm| + |C| Hr, which also gives the first derivatives' ranges.
  const bool mid = source.midpoint;
  source.affine = atCentreOk && model.preconditionedHessianMagnitude(
                                    box.pose, c_, w.magCH, mid ? &w.linCH : nullptr, mid ? &w.quadCH : nullptr,
                                    mid ? &w.restCH : nullptr, mid ? &w.centreCH : nullptr);
  residualOk_ = source.affine && source.midpoint && params_ == 0 && n_ == kMaxDof && vars_ == n_;
  if (atCentreOk && !source.affine) {
    source.box = model.inverseJacobianHessianAtGeometryCentre(box.pose, w.hessian);
    for (int i = 0; i < vars_ && source.box; ++i) source.box = w.hessian.first[i].rows() == n_;
    for (int p = 0; p < MatrixHessian::kPairs && source.box; ++p) source.box = w.hessian.d[p].rows() == n_;
  }
  return source;
}

void PreconditionedInverseEnclosure::rangeSlopes(const model::RobotModel& model, const BoxInput& box,
                                                 const HessianSource& source) {
  Workspace& w = work_;
  if (vars_ > 0 && !source.centred()) model.inverseJacobianAtGeometryCentre(box.dualPose, w.poseD);
  const DMat zero = DMat::Zero(n_, n_);  // (C is exact: zero radius)
  if (source.box) {
    DMat m, r, hm, hr;
    for (int p = 0; p < MatrixHessian::kPairs; ++p) {
      split(w.hessian.d[p], m, r);
      product(c_, zero, m, r, hm, hr);
      w.magCH[p] = upAll(DMat(hm.cwiseAbs() + hr));
    }
  }
  for (int i = 0; i < vars_; ++i) {
    if (!source.affine) split(multiplyMidRad(c_, source.box ? w.hessian.first[i] : w.poseD.d[i]), dm_[i], dr_[i]);
    devMag_[i] = box.deviation[i].mag();
  }
}

void PreconditionedInverseEnclosure::centredSlope(int i, const HessianSource& source, DMat& tm, DMat& tr) {
  // With the box midpoint as the expansion's centre t0, the model's bound comes in three parts: at t0 + s dt,
  // |C H_il| <= magCH + s linCH + s^2 quadCH (linCH >= sum_m |C A_m|, the part that varies linearly in the pose
  // symbols; quadCH >= |C| R2, the affine forms' nonlinearity, which vanishes quadratically at t0; magCH the rest):
  // the mean-value form of D_i weights them by int_0^1 s^k ds = 1, 1/2, 1/3 and the Taylor slopes by
  // int_0^1 (1 - s) s^k ds / int_0^1 (1 - s) ds = 1, 1/3, 1/6.
  const Workspace& w = work_;
  const DMat zero = DMat::Zero(n_, n_);  // (C is exact: zero radius)
  DMat cm, cr, m, r;
  split(w.atCentre.first[i], m, r);
  product(c_, zero, m, r, cm, cr);
  if (residualOk_) {
    rg_[i] = cm;
    rgr_[i] = cr;
    rgAbs_[i] = cm.cwiseAbs();
  }
  DMat half = cr;  // the Taylor slope's radius (below)
  for (int l = 0; l < n_; ++l) {
    const int p = MatrixHessian::index(i, l);
    const DMat t = upAll(DMat(w.magCH[p] * devMag_[l]));
    if (source.affine && source.midpoint) {
      const DMat u = upAll(DMat(w.linCH[p] * devMag_[l])), v = upAll(DMat(w.quadCH[p] * devMag_[l]));
      // (1/3, 1/6, 1/12 rounded: within upAll's relative margin)
      cr = upAll(DMat(cr + t + 0.5 * u + (1.0 / 3.0) * v));
      half = upAll(DMat(half + 0.5 * t + (1.0 / 6.0) * u + (1.0 / 12.0) * v));
    } else {
      cr = upAll(DMat(cr + t));
      half = upAll(DMat(half + 0.5 * t));
    }
  }
  tm = cm;
  tr = half;
  if (source.affine) {
    // (No interval range of D_i over the box: the centred one.)
    dm_[i] = cm;
    dr_[i] = cr;
    return;
  }
  // Intersection of [dm -+ dr] and [cm -+ cr] (both contain every D_i(t), t in the box).
  for (int k = 0; k < n_; ++k) {
    for (int l = 0; l < n_; ++l) {
      using interval::rounding::addUp;
      using interval::rounding::subDown;
      const double lo = std::max(subDown(dm_[i](k, l), dr_[i](k, l)), subDown(cm(k, l), cr(k, l)));
      const double hi = std::min(addUp(dm_[i](k, l), dr_[i](k, l)), addUp(cm(k, l), cr(k, l)));
      if (lo <= hi) split(Interval(lo, hi), dm_[i](k, l), dr_[i](k, l));
    }
  }
}

void PreconditionedInverseEnclosure::chooseTaylorSlopes(const std::array<DMat, kMaxDof>& tm,
                                                        const std::array<DMat, kMaxDof>& tr) {
  // Taylor slopes (second order, integral remainder): E(t, g0) = E0 + sum_i D_i(t0) dt_i + sum_{i,l} dt_i dt_l
  // int_0^1 (1 - s) C H_il(t0 + s dt) ds, and int_0^1 (1 - s) ds = 1/2, so entry by entry
  // E(t, g0) - E0 = sum_i T_i dt_i with T_i in D_i(t0) + (1/2) sum_l [C H_il(box)] [-dev_l, dev_l]: half the radius of
  // the centred range above. T_i is a slope for expansions at the box centre, not a range of D_i, so for each entry
  // (k, j) either every T_i(k, j) or every range D_i(k, j) is used (each choice is a valid representation of that
  // entry of E(t, g0) - E0): the one with the smaller sum_i radius dev_i.
  for (int k = 0; k < n_; ++k) {
    for (int l = 0; l < n_; ++l) {
      double rangeCost = 0.0, taylorCost = 0.0;
      for (int i = 0; i < vars_; ++i) {
        rangeCost += dr_[i](k, l) * devMag_[i];
        taylorCost += tr[i](k, l) * devMag_[i];
      }
      if (!(taylorCost < rangeCost)) continue;
      for (int i = 0; i < vars_; ++i) {
        dm_[i](k, l) = tm[i](k, l);
        dr_[i](k, l) = tr[i](k, l);
      }
    }
  }
}

void PreconditionedInverseEnclosure::prepareResidualWeights() {
  // (tightenByResidual(): the remainder's part |C| R0 and the centre C Hc of the same affine Hessian forms.)
  const Workspace& w = work_;
  for (int p = 0; p < MatrixHessian::kPairs && residualOk_; ++p) {
    residualOk_ = w.centreCH[p].rows() == n_ && w.restCH[p].rows() == n_ && w.linCH[p].rows() == n_ &&
                  w.quadCH[p].rows() == n_ && w.centreCH[p].allFinite();
    if (!residualOk_) break;
    rh_[p] = w.centreCH[p];
    rhAbs_[p] = rh_[p].cwiseAbs();
    // int_0^1 (1 - s) (s L + R + s^2 Q) ds = L / 6 + R / 2 + Q / 12 (the constants' rounding: within upAll's margin)
    rw_[p] = upAll(M6(w.linCH[p] / 6.0 + w.restCH[p] / 2.0 + w.quadCH[p] / 12.0));
  }
}

void PreconditionedInverseEnclosure::boundPoseMagnitudes() {
  magS_ = e0m_.cwiseAbs() + e0r_;
  magSP_ = DMat::Zero(n_, n_);
  for (int i = 0; i < vars_; ++i) {
    const DMat term = (dm_[i].cwiseAbs() + dr_[i]) * devMag_[i];
    poseWeight_[i] = term.rowwise().sum();
    magS_ += term;
    magSP_ += term;
  }
  magS_ = upAll(magS_);
  magSP_ = upAll(magSP_);
  boundPoseSquare();
}

void PreconditionedInverseEnclosure::boundPoseSquare() {
  // magS2_ >= |S(t) S(t)|. S(t) = E0 + sum_i T_i dt_i (T_i in [dm_i +- dr_i] entry by entry, |dt_i| <= dev_i) is
  // Sm(t) + X with Sm(t) = e0m + sum_i dm_i dt_i, |X| <= rS = e0r + sum_i dr_i dev_i and |Sm(t)| <= aS = |e0m|
  // + sum_i |dm_i| dev_i, so |S S| <= |Sm Sm| + aS rS + rS (aS + rS), and
  //   Sm Sm = e0m e0m + sum_i dt_i (e0m dm_i + dm_i e0m) + sum_i dt_i^2 dm_i dm_i + sum_{i<l} dt_i dt_l (dm_i dm_l
  //           + dm_l dm_i),
  // whose products of midpoints keep the cancellations between the terms of each entry that |S| |S| loses. They
  // are computed in floating point: each is off by less than kGamma times the product of the magnitudes, and the
  // sums of two by less than that again, so 2 kGamma aS aS covers them all. (The radii's part is the same sum of
  // terms as the midpoint-radius product of every pair would give, factored.) |S| |S| is kept where smaller.
  const auto addAbs = [](const DMat& x, double weight, DMat& sum) { sum += x.cwiseAbs() * weight; };
  DMat m2 = mul<DMat>(e0m_, e0m_).cwiseAbs();
  DMat aS = e0m_.cwiseAbs(), rS = e0r_;
  for (int i = 0; i < vars_; ++i) {
    aS += dm_[i].cwiseAbs() * devMag_[i];
    rS += dr_[i] * devMag_[i];
    addAbs(DMat(mul<DMat>(e0m_, dm_[i]) + mul<DMat>(dm_[i], e0m_)), devMag_[i], m2);
    addAbs(mul<DMat>(dm_[i], dm_[i]), devMag_[i] * devMag_[i], m2);
    for (int l = i + 1; l < vars_; ++l)
      addAbs(DMat(mul<DMat>(dm_[i], dm_[l]) + mul<DMat>(dm_[l], dm_[i])), devMag_[i] * devMag_[l], m2);
  }
  aS = upAll(aS);
  rS = upAll(rS);
  m2 = upAll(DMat(upAll(m2) + upAll(DMat(upAll(DMat(mul<DMat>(aS, rS))) + upAll(DMat(mul<DMat>(rS, DMat(aS + rS))))))));
  m2 = upAll(DMat(m2 + 2.0 * kGamma * upAll(DMat(mul<DMat>(aS, aS)))));
  magS2_ = upAll(m2).cwiseMin(upAll(DMat(mul<DMat>(magS_, magS_))));
}

void PreconditionedInverseEnclosure::storeGeometryEntries(const model::RobotModel& model) {
  for (int p = 0; p < params_; ++p) {
    h_[p] = (model.geometryParameterRange(p) - Interval(model.geometryParameterCentre(p))).mag();
  }
  const GeometryDerivatives& geo = work_.geo;
  gm_.resize(entries_, n_);
  gr_.resize(entries_, n_);
  cg_.resize(n_, entries_);
  for (int e = 0; e < entries_; ++e) {
    const GeometryRowDerivative& g = geo.entries[e];
    param_[e] = g.parameter;
    row_[e] = g.row;
    entryH_[e] = h_[g.parameter];
    for (int l = 0; l < n_; ++l) {
      gm_(e, l) = g.d[l].mid();
      gr_(e, l) = g.d[l].rad();
    }
    for (int k = 0; k < n_; ++k) cg_(k, e) = c_(k, g.row);
  }
  runs_ = 0;
  for (int e = 0; e < entries_; ++e)
    if (e == 0 || row_[e] != row_[e - 1]) runStart_[runs_++] = e;
  runStart_[runs_] = entries_;
  // The affine forms (when the model gives them for every entry).
  affine_ = entries_ > 0 && n_ == kMaxDof;
  for (int e = 0; e < entries_ && affine_; ++e) affine_ = geo.entries[e].affine;
  for (int e = 0; e < entries_ && affine_; ++e) {
    const GeometryRowDerivative& g = geo.entries[e];
    for (int l = 0; l < kMaxDof; ++l) {
      affCentre_[l][e] = g.centre[l];
      affRadius_[l][e] = g.radius[l];
      double w = std::abs(g.centre[l]);
      for (int m = 0; m < kMaxDof; ++m) {
        affSlope_[m][l][e] = g.slope[l][m];
        w += std::abs(g.slope[l][m]);
      }
      affWeight_[l][e] = up(w);
    }
  }
}

DMat PreconditionedInverseEnclosure::boundGeometryMagnitudes() {
  absC_ = c_.cwiseAbs();
  // |L| <= sum_e |C_{., row(e)}| h_p |d_e|^T = |C| R with R(i, l) = sum over the entries e of row i of h_p |d_e|_l.
  magG_ = upAll(EntryMat(gm_.cwiseAbs() + gr_));
  DMat rowG = DMat::Zero(n_, n_);
  for (int e = 0; e < entries_; ++e) rowG.row(row_[e]) += h_[param_[e]] * magG_.row(e);
  const DMat magL = upAll(DMat(mul<DMat>(absC_, upAll(rowG))));
  // alpha(e, j) >= |d_e . C_{.,j}| for every d_e in its enclosure.
  {
    const DMat zero = DMat::Zero(n_, n_);  // (C is exact: zero radius)
    EntryMat m, r;
    if (affine_) {  // (the affine form is the narrower one, as in apply(): the same boxes without the product)
      affineDots(c_, zero, m, r);
    } else {
      product(gm_, gr_, c_, zero, m, r);
    }
    alpha_ = upAll(EntryMat(m.cwiseAbs() + r));
    dcm_ = m;
    dcr_ = r;
  }
  magE_ = upAll(DMat(magS_ + magL));
  magE2_ = upAll(DMat(mul<DMat>(magE_, magE_)));
  magE0_ = upAll(DMat(e0m_.cwiseAbs() + e0r_));
  return magL;
}

void PreconditionedInverseEnclosure::boundDotProducts() {
  // |d_e^T S| <= |d_e^T E0| + sum_i |d_e^T D_i| |dev_i| and |S C| <= |E0 C| + sum_i |D_i C| |dev_i|: the dot products
  // keep their cancellations, which |d_e|^T |S| and |S| |C| lose (both bounds are valid: the smaller is kept).
  // They bound |d_e . (S y)| <= dS z (so |L S y| <= cgh dS z) and |S L y| = |S C Lambda| <= |S C| B. With
  // X in [xm +- xr] (X = E0, D_i), |d_e^T X| <= |gm xm| + |gm| (xr + gamma |xm|) + gr (|xm| + xr), so the radius
  // parts of all the terms add up to two products: |gm| W + gr |S| with W = sum over the terms of |dev| (xr +
  // gamma |xm|) (the plain products' rounding errors are in the gamma part); likewise |S C| with |C| W.
  // (The entries x n products through productEach(): as Eigen's lazy products they are a third of prepare()'s
  // instructions at +-0.5 mm.)
  DMat w = upAll(DMat(e0r_ + kGamma * e0m_.cwiseAbs()));
  EntryMat ds = EntryMat::Zero(entries_, n_);
  productEach(gm_, e0m_, addAbsTo(ds, 1.0));
  DMat sc = mul<DMat>(e0m_, c_).cwiseAbs();
  for (int i = 0; i < vars_; ++i) {
    w += upAll(DMat((dr_[i] + kGamma * dm_[i].cwiseAbs()) * devMag_[i]));
    productEach(gm_, dm_[i], addAbsTo(ds, devMag_[i]));
    dc_[i] = mul<DMat>(dm_[i], c_);  // (also for the bilinear terms)
    sc += dc_[i].cwiseAbs() * devMag_[i];
  }
  w = upAll(w);
  const EntryMat absGm = gm_.cwiseAbs();
  productEach(absGm, w, addTo(ds));
  productEach(gr_, magS_, addTo(ds));
  sc += mul<DMat>(w, absC_);
  EntryMat plain = EntryMat::Zero(entries_, n_);  // |d_e|^T |S|
  productEach(magG_, magS_, addTo(plain));
  dS_ = upAll(ds).cwiseMin(upAll(plain));
  sc_ = upAll(sc).cwiseMin(upAll(DMat(mul<DMat>(magS_, absC_))));
  if (entries_ > 0) boundDotProductsWithC(w, sc, absGm);
}

void PreconditionedInverseEnclosure::boundDotProductsWithC(const DMat& w, const DMat& sc, const EntryMat& absGm) {
  // |d_e^T S C| as |d_e^T S| (boundDotProducts()): the midpoints' products gm (E0m C), gm (D_i C) keep their
  // cancellations; their roundings: kGamma |gm| sc.
  const DMat e0c = mul<DMat>(e0m_, c_);
  EntryMat dsc = EntryMat::Zero(entries_, n_);
  productEach(gm_, e0c, addAbsTo(dsc, 1.0));
  for (int i = 0; i < vars_; ++i) productEach(gm_, dc_[i], addAbsTo(dsc, devMag_[i]));
  productEach(absGm, DMat(upAll(DMat(mul<DMat>(w, absC_)))), addTo(dsc));
  productEach(gr_, sc_, addTo(dsc));
  productEach(absGm, DMat(upAll(sc)), addAbsTo(dsc, kGamma));
  EntryMat plain = EntryMat::Zero(entries_, n_);  // |d_e^T S| |C|
  productEach(dS_, absC_, addTo(plain));
  dSC_ = upAll(dsc).cwiseMin(upAll(plain));
}

void PreconditionedInverseEnclosure::prepareBilinear(const BoxInput& box) {
  // The bilinear terms (apply(), bilinearCoefficients()): the affine forms' pose symbols must be the box variables
  // (tau'_i = (t_i - mid_i) / a_i with a_i their scale, tau_i = (t_i - t0_i) / dev_i, t0 = mid: tau'_i = kappa_i
  // tau_i), and each parameter must have one entry (anchor coordinates: one row each).
  bilinear_ = affine_ && vars_ == n_ && box.variablesArePose(n_);
  if (bilinear_) {
    int count[kMaxGeometryParameters] = {};
    for (int e = 0; e < entries_; ++e) bilinear_ = bilinear_ && ++count[param_[e]] == 1;
  }
  if (!bilinear_) return;
  DMat dr = DMat::Zero(n_, n_), dmc = DMat::Zero(n_, n_);
  for (int i = 0; i < n_; ++i) {
    const double a = interval::AffineForm<kMaxDof>::variable(box.pose[i], i).coefficient(i);
    kappa_[i] = a > 0.0 ? devMag_[i] / a : 0.0;
    if (!(a > 0.0) && devMag_[i] > 0.0) bilinear_ = false;
    dcAbs_[i] = upAll(DMat(mul<DMat>(DMat(dm_[i].cwiseAbs()), absC_)));
    dmc += (dc_[i].cwiseAbs() + kGamma * dcAbs_[i]) * devMag_[i];
    dr += dr_[i] * devMag_[i];
  }
  dmc_ = upAll(upAll(dmc));
  drc_ = upAll(DMat(mul<DMat>(upAll(dr), absC_)));
  e0c_ = upAll(DMat(mul<DMat>(magE0_, absC_)));
}

void PreconditionedInverseEnclosure::prepareAffineDeviations() {
  if (!affine_) return;
  // |d_e - c_e| <= sum_m |slope_m| + radius and |c_e|, component by component (apply()).
  devE_.resize(entries_, n_);
  absCe_.resize(entries_, n_);
  for (int e = 0; e < entries_; ++e) {
    for (int l = 0; l < n_; ++l) {
      double w = affRadius_[l][e];
      for (int m = 0; m < n_; ++m) w += std::abs(affSlope_[m][l][e]);
      devE_(e, l) = up(w);
      absCe_(e, l) = std::abs(affCentre_[l][e]);
    }
  }
}

void PreconditionedInverseEnclosure::approximateInverses() {
  using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kMaxDof>;
  // q_ ~ (I - |E|)^-1: any approximation; apply() verifies what it gives.
  DMat iMinus = -magE_;
  for (int i = 0; i < n_; ++i) iMinus(i, i) += 1.0;
  Eigen::PartialPivLU<Square> lu(iMinus);
  q_ = lu.inverse();
  // R(alpha) (i, j) = sum over the entries e of row i of h_p(e) alpha(e, j), and an approximation of its
  // (I - R(alpha))^-1 (apply(): the fixed point of the refinement of B).
  alphaRowsOk_ = false;
  jointOk_ = false;
  if (entries_ <= 0) return;
  alphaRows_ = DMat::Zero(n_, n_);
  for (int e = 0; e < entries_; ++e) alphaRows_.row(row_[e]) += entryH_[e] * alpha_.row(e);
  alphaRows_ = upAll(alphaRows_);
  DMat iMinusA = -alphaRows_;
  for (int i = 0; i < n_; ++i) iMinusA(i, i) += 1.0;
  alphaRowsInv_ = Eigen::PartialPivLU<Square>(iMinusA).inverse();
  alphaRowsOk_ = alphaRows_.allFinite() && alphaRowsInv_.allFinite();
  // The joint system of (|y - v|, R(|d_e . (y - v)|)) (apply()): [[|S|, |C|], [R(dS), R(alpha)]].
  DMat rowDS = DMat::Zero(n_, n_);
  for (int e = 0; e < entries_; ++e) rowDS.row(row_[e]) += entryH_[e] * dS_.row(e);
  joint_.resize(2 * n_, 2 * n_);
  joint_.topLeftCorner(n_, n_) = magS_;
  joint_.topRightCorner(n_, n_) = absC_;
  joint_.bottomLeftCorner(n_, n_) = upAll(rowDS);
  joint_.bottomRightCorner(n_, n_) = alphaRows_;
  JSquare iMinusJ = -joint_;
  for (int i = 0; i < 2 * n_; ++i) iMinusJ(i, i) += 1.0;
  jointInv_ = Eigen::PartialPivLU<JSquare>(iMinusJ).inverse();
  jointOk_ = alphaRowsOk_ && joint_.allFinite() && jointInv_.allFinite();
}

bool PreconditionedInverseEnclosure::majorant(const DMat& rhs, DMat& z) const { return fixedPoint(magE_, q_, rhs, z); }

/// The terms of apply() for one matrix V (m columns), in the order it bounds them (locals of one apply() call, on the
/// stack: every matrix has a fixed maximum size).
struct PreconditionedInverseEnclosure::ColumnTerms {
  int m = 0;
  DMat vm, vr, absV;                     ///< V in midpoint-radius form, |V|
  DMat ym, yr;                           ///< Y0 = V - E0 V, midpoint and radius
  DMat absSv;                            ///< >= |E0 V|, then >= |S V| (S = E0 + P the pose part of E)
  DMat e0v;                              ///< >= |E0 V|
  DMat z;                                ///< >= |N V| (the Neumann majorant, then refined)
  EntryMat dvm, dvr, dvr0, magDV;        ///< d_e . v (midpoint, radius, radius without the slope part), |d_e . v|
  std::array<DMat, kMaxDof> dvmI, dvrI;  ///< D_i V, midpoint and radius
  DMat pv;                               ///< >= |P V|
  DMat bV;                               ///< B_v: row sums of h |d_e . v|
  DMat lv;                               ///< >= |L V|
  DMat delta;                            ///< >= |Y - Y0|
  EntryMat q;                            ///< sum_i dev_i |c_e . (D_i v)| (columns that bound f_k)
  DMat pvr;                              ///< >= sum_i dev_i (the radius of D_i v and its rounding)
  DMat spread;                           ///< >= |y - v|
  EntryMat poseDotRest;                  ///< >= devE |P v| + |c_e| pvr + |d_e| |E0 v| (empty until poseDotRestOnce())
  EntryMat dsSpread;                     ///< >= |d_e . S (y - v)| (empty if not computed)
  EntryMat rhoJoint;                     ///< >= |d_e . (y - v)| from the joint system (empty if not solved)
  DMat bRhoJoint;                        ///< >= R(|d_e . (y - v)|) from it
  DMat sy;                               ///< >= |S y|
  EntryMat gsy;                          ///< >= |d_e . (S y)|
  EntryMat dotRest;                      ///< the part of gsy beyond q (columns that bound f_k)
  EntryMat rho, beta;                    ///< >= |d_e . (y - v)|, >= |d_e . y|
  DMat b;                                ///< B: row sums of h beta
  EntryMat gamma;                        ///< >= |d_e . L y|
  DMat ssy, sly, lsy;                    ///< >= |S S y|, |S L y|, |L S y|
  DMat radius;                           ///< the radius of the forms, summed up term by term
  DMat poseRadius;                       ///< the pose coefficients' radii (the bilinear radius)
};

bool PreconditionedInverseEnclosure::apply(const IMat& v, AffineMatrix& out, Refinements refinements) const {
  const bool forBounds = refinements == Refinements::ForErrorBounds;
  ColumnTerms s;
  if (!startColumns(v, s)) return false;
  out.bilinear = forBounds && bilinear_;
  geometryDots(s, out.bilinear ? &out.sv : nullptr);
  posePart(s);
  if (affine_ && forBounds) centreDots(s, out.bilinear ? &out.q1 : nullptr);
  boundSpread(s);
  boundPoseProduct(s);
  if (entries_ > 0) s.gsy = nonNegativeProduct(magG_, s.sy);
  if (affine_ && forBounds) boundPoseDotsByCentre(s);
  refineDots(s, out);
  const DMat remainder = boundRemainder(s, out);
  writePoseForms(s, remainder, out);
  if (out.bilinear) {
    writeBilinear(s, out);
  } else {
    for (int i = 0; i < kMaxDof; ++i) out.q1[i].resize(0, 0), out.sv[i].resize(0, 0);
    out.gammaDot.resize(0, 0);
    out.dotRest.resize(0, 0);
    out.rowB.resize(0, 0);
    out.bilinearRadius.resize(0, 0);
  }
  sharePoseRemainder(s, out);
  writeGeometryForms(s, out);
  return out.radius.allFinite() && out.centre.allFinite();
}

bool PreconditionedInverseEnclosure::startColumns(const IMat& v, ColumnTerms& s) const {
  s.m = static_cast<int>(v.cols());
  split(v, s.vm, s.vr);
  s.absV = upAll(DMat(s.vm.cwiseAbs() + s.vr));
  if (!s.absV.allFinite()) return false;

  // Y0 = V - E0 V.
  product(e0m_, e0r_, s.vm, s.vr, s.ym, s.yr);
  s.absSv = upAll(DMat(s.ym.cwiseAbs() + s.yr));  // >= |E0 V|; later + |P V| >= |S V|
  s.ym = s.vm - s.ym;
  s.yr = upAll(DMat(s.yr + s.vr + kGamma * (s.vm.cwiseAbs() + s.ym.cwiseAbs())));

  // Z >= |N V| column by column: Y = V - E Y gives |Y| <= |V| + |E| |Y|.
  return majorant(s.absV, s.z);
}

void PreconditionedInverseEnclosure::geometryDots(ColumnTerms& s, std::array<EntryMat, kMaxDof>* sv) const {
  // Geometry: DV = D_G V (first-order terms; also inside L L Y, as y = v + (y - v)).
  if (affine_) {
    // (The affine form is always the narrower one: measured, the same boxes without the interval product.)
    if (sv) {
      affineDots(s.vm, s.vr, s.dvm, s.dvr, &s.dvr0, sv);
    } else {
      affineDots(s.vm, s.vr, s.dvm, s.dvr);
    }
  } else {
    product(gm_, gr_, s.vm, s.vr, s.dvm, s.dvr);
  }
  s.magDV = upAll(EntryMat(s.dvm.cwiseAbs() + s.dvr));
}

DMat PreconditionedInverseEnclosure::rowSums(const EntryMat& x, int m) const {
  // Products cgh X (n x entries times entries x m, X >= 0) through the rows the entries move: cgh(k, e) =
  // |C_{k,row(e)}| h_p(e), so cgh X = |C| R(X) with R(X)(i, j) = sum over the entries e of row i of h_p(e) X(e, j)
  // (the same sums, a sixth of the products; every term is >= 0, so up() covers the roundings).
  DMat rowSum(n_, m);
  rowSum.setZero();
  for (int j = 0; j < m; ++j) {
    double* sum = &rowSum(0, j);
    const double* column = &x(0, j);
    for (int r = 0; r < runs_; ++r) {  // (each run's entries move the same row: one sum per run)
      double t = 0.0;
      for (int e = runStart_[r]; e < runStart_[r + 1]; ++e) t += entryH_[e] * column[e];
      sum[row_[runStart_[r]]] += t;
    }
  }
  return upAll(rowSum);
}

DMat PreconditionedInverseEnclosure::chProduct(const EntryMat& x, int m) const {
  return upAll(DMat(mul<DMat>(absC_, rowSums(x, m))));
}

void PreconditionedInverseEnclosure::posePart(ColumnTerms& s) const {
  // |Y - Y0| = |-(E - E0) V + E^2 Y| <= |P V| + |L V| + |E| |E| Z  (delta), where E - E0 = P + L (P: the pose
  // part, L: the geometry part), |L V| <= cgh |DV| keeps the cancellations inside the dot products d_e . v, and
  // |P V| <= sum_i |D_i V| |dev_i| those inside D_i v (the products the pose coefficients need anyway), which |P| |V|
  // loses (the smaller of the two is kept). (|E| |E| is computed once per box in prepare().)
  s.pv = DMat::Zero(n_, s.m);
  for (int i = 0; i < vars_; ++i) {
    product(dm_[i], dr_[i], s.vm, s.vr, s.dvmI[i], s.dvrI[i]);
    s.pv += (s.dvmI[i].cwiseAbs() + s.dvrI[i]) * devMag_[i];
  }
  s.pv = upAll(s.pv).cwiseMin(upAll(DMat(mul<DMat>(magSP_, s.absV))));
  s.bV = rowSums(s.magDV, s.m);
  s.lv = upAll(DMat(mul<DMat>(absC_, s.bV)));  // >= |L V| (chProduct(magDV))
  s.delta = upAll(DMat(upAll(DMat(s.pv + s.lv)) + upAll(DMat(mul<DMat>(magE2_, s.z)))));
  s.e0v = s.absSv;  // >= |E0 V| (the product in startColumns(), midpoint-radius)
}

void PreconditionedInverseEnclosure::centreDots(ColumnTerms& s, std::array<EntryMat, kMaxDof>* q1) const {
  // q(e, j) = sum_i dev_i |c_e . (D_i v_j)| (c_e: the centre of d_e's affine form), pvr >= sum_i dev_i (the radius of
  // D_i v and its rounding): |d_e . (P v)| <= q + devE |P v| + |c_e| pvr (boundPoseDotsByCentre()). For the columns
  // that bound f_k.
  const int m = s.m;
  s.q = EntryMat::Zero(entries_, m);
  s.pvr = DMat::Zero(n_, m);
  for (int i = 0; i < vars_; ++i) {
    s.pvr += (s.dvrI[i] + kGamma * s.dvmI[i].cwiseAbs()) * devMag_[i];
    EntryMat* keep = q1 ? &(*q1)[i] : nullptr;
    if (keep) keep->resize(entries_, m);
    for (int j = 0; j < m; ++j) {
      double dot[kEntries];
      for (int e = 0; e < entries_; ++e) dot[e] = 0.0;
      for (int l = 0; l < n_; ++l) {
        const double x = s.dvmI[i](l, j);
        for (int e = 0; e < entries_; ++e) dot[e] += affCentre_[l][e] * x;
      }
      double* col = &s.q(0, j);
      for (int e = 0; e < entries_; ++e) col[e] += std::abs(dot[e]) * devMag_[i];
      if (keep)
        for (int e = 0; e < entries_; ++e) (*keep)(e, j) = dot[e];
    }
  }
  s.pvr = upAll(s.pvr);
}

const PreconditionedInverseEnclosure::EntryMat& PreconditionedInverseEnclosure::poseDotRestOnce(ColumnTerms& s) const {
  // >= devE |P v| + |c_e| pvr + |d_e| |E0 v| (the part of |d_e . (S y)|'s bound beyond q and d_e . S (y - v); only
  // with q), computed on first use.
  if (s.poseDotRest.rows() != entries_)
    s.poseDotRest = upAll(EntryMat(nonNegativeProduct(devE_, s.pv) + nonNegativeProduct(absCe_, s.pvr) +
                                   nonNegativeProduct(magG_, s.e0v)));
  return s.poseDotRest;
}

void PreconditionedInverseEnclosure::boundSpread(ColumnTerms& s) const {
  // beta(e, col) >= |d_e . y| <= |d_e . v| + rho(e, col), rho >= |d_e . (y - v)|, from spread >= |y - v|:
  // |y - v| <= |E0 V| + delta, and since y - v = -E y = -E v - E (y - v),
  //   |y - v| <= first + |E| |y - v|,   first = |E0 V| + |P V| + |L V| >= |E v|,
  // so |y - v| <= (I - |E|)^-1 first, verified by majorant() like z, where the joint bound below is not available
  // (the smaller bound is kept). (It replaced two passes of spread <- first + |E| spread, which stopped well short of
  // the fixed point where |E| is large: paper, 2 threads, 23 791 -> 23 727 boxes at h = 0, 46 133 -> 45 573 at
  // +-0.5 mm, 154 345 -> 147 155 at +-1 mm.)
  // With geometry entries, |E| |y - v| pays for L (y - v) in magnitude, |C| R(|d_e| |y - v|), where the dot products
  // d_e . (y - v) cancel. So |y - v| and rho are bounded together, with s >= |y - v| and Brho = R(rho) (R: row sums
  // of h x over each row's entries; L (y - v) = sum_i C_{.,i} sum over row i's entries of h gamma_e d_e . (y - v)):
  //   y - v = -E v - S (y - v) - L (y - v)                            gives  s <= first + |S| s + |C| Brho,
  //   d_e . (y - v) = -d_e . (E0 v + P v + L v) - d_e . S (y - v) - d_e . L (y - v)
  //                                                                    gives  rho <= rho1 + dS s + alpha Brho,
  // so [s; Brho] <= [first; R(rho1)] + [[|S|, |C|], [R(dS), R(alpha)]] [s; Brho], a 2n x 2n system whose verified
  // fixed point bounds both (rho1: |d_e| |E0 v + P v|, or through q for the columns that bound f_k, plus
  // alpha B_v).
  // Paper, 2 threads: 45 333 -> 44 207 boxes at +-0.5 mm, 139 371 -> 121 951 at +-1 mm; h = 0 has no entries.
  s.spread = upAll(DMat(s.delta + s.e0v));
  const DMat first = upAll(DMat(upAll(DMat(s.e0v + s.pv)) + s.lv));
  bool joint = false;
  if (entries_ > 0 && jointOk_) joint = boundSpreadJointly(first, s);
  // (Without the joint bound, the |E| one; with it, the |E| one never kept fewer boxes: the same counts on paper.)
  DMat fp;
  if (!joint && majorant(first, fp)) s.spread = s.spread.cwiseMin(fp);
}

bool PreconditionedInverseEnclosure::boundSpreadJointly(const DMat& first, ColumnTerms& s) const {
  // rho1 >= |d_e . (E0 v + P v + L v)|
  const int m = s.m;
  EntryMat dpv = nonNegativeProduct(magG_, DMat(upAll(DMat(s.e0v + s.pv))));
  if (s.q.rows() == entries_) {
    dpv = dpv.cwiseMin(upAll(EntryMat(upAll(s.q) + poseDotRestOnce(s))));
  }
  const EntryMat rho1 = upAll(EntryMat(dpv + nonNegativeProduct(alpha_, s.bV)));
  JMat rhs(2 * n_, m), x;
  rhs.topRows(n_) = first;
  rhs.bottomRows(n_) = rowSums(rho1, m);
  if (!fixedPoint(joint_, jointInv_, rhs, x)) return false;
  s.spread = s.spread.cwiseMin(DMat(x.topRows(n_)));
  s.bRhoJoint = x.bottomRows(n_);
  s.dsSpread = nonNegativeProduct(dS_, s.spread);  // (spread is final: the |E| bound is only without it)
  s.rhoJoint = upAll(EntryMat(rho1 + s.dsSpread + nonNegativeProduct(alpha_, s.bRhoJoint)));
  return true;
}

void PreconditionedInverseEnclosure::boundPoseProduct(ColumnTerms& s) const {
  // sy >= |S y| (S = E0 + P, the pose part of E) through y = v + (y - v): |S y| <= |S v| + |S| |y - v|, where
  // |S v| <= |E0 v| + |P v| keeps the cancellations inside S v and |y - v| <= spread is mostly well below z >= |y|.
  // The bounds through |S| z below are valid too: the smaller is kept. (Paper workspace, 2 threads: 5% fewer boxes
  // at +-0.5 mm, with the hints below 11%, bench/RESULTS.md.)
  s.absSv = upAll(DMat(s.e0v + s.pv));
  s.sy = upAll(DMat(s.absSv + upAll(DMat(mul<DMat>(magS_, s.spread)))));
  if (entries_ <= 0) return;
  // And through S (y - v) = -S E0 v - S P v - S L v + S E (E y) with |S L v| = |S C Lambda_v| <= |S C| B_v (the
  // dot products d_e . v and S C keep their cancellations, which |S| |L v| loses; paper, 2 threads: 46 895 ->
  // 46 133 boxes at +-0.5 mm, 158 999 -> 154 345 at +-1 mm).
  const DMat sLv = upAll(DMat(mul<DMat>(sc_, s.bV)));
  const DMat other = upAll(DMat(upAll(DMat(s.e0v + s.pv)) + upAll(DMat(mul<DMat>(magE_, s.spread)))));
  s.sy = s.sy.cwiseMin(upAll(DMat(s.absSv + upAll(DMat(upAll(DMat(mul<DMat>(magS_, other))) + sLv)))));
  if (s.bRhoJoint.rows() == n_) {
    // S (y - v) = -S (E0 v + P v) - S S (y - v) - S L (v + (y - v)), |S L x| = |S C Lambda_x| <= |S C| R(|d_e . x|).
    const DMat inner = upAll(DMat(s.absSv + upAll(DMat(mul<DMat>(magS_, s.spread)))));
    const DMat sl = upAll(DMat(mul<DMat>(sc_, upAll(DMat(s.bV + s.bRhoJoint)))));
    s.sy = s.sy.cwiseMin(upAll(DMat(s.absSv + upAll(DMat(upAll(DMat(mul<DMat>(magS_, inner))) + sl)))));
  }
}

void PreconditionedInverseEnclosure::boundPoseDotsByCentre(ColumnTerms& s) const {
  // gsy >= |d_e . (S y)| is |d_e| |S y| (apply()); with the affine forms of d_e (centre c_e, |d_e - c_e| <= devE),
  // d_e . (S y) = d_e . (E0 v) + d_e . (P v) + d_e . (S (y - v)) and d_e . (P v) = (d_e - c_e) . (P v) + sum_i dev_i
  // tau_i c_e . (T_i v), T_i v in [D_i v -+ dvr_i], so
  //   |d_e . (S y)| <= sum_i dev_i |c_e . D_i v| + rest,
  //   rest = devE |P v| + |c_e| sum_i dev_i dvr_i + |d_e| |E0 v| + |d_e^T S| |y - v|,
  // which keeps the cancellations inside c_e . (D_i v) (first order in the box) where |d_e| |S y| adds up the
  // components of S y. (The c_e . (D_i v) are computed in floating point: kGamma |c_e| |D_i v| in rest covers that.)
  // Only for columns that bound f_k (Refinements::ForErrorBounds): for J's signs it costs more time than the boxes it
  // removes save (paper, 1 thread: +-0.5 mm 46 545 instead of 46 895 boxes but 2.5% more time; +-1 mm 153 155
  // instead of 158 999, the same time within the noise).
  // |d_e . S (y - v)| <= dS spread, or through S (y - v) = -S (E0 v + P v) - S S (y - v) - S L (v + (y - v)):
  // dS (|E0 v| + |P v| + |S| spread) + |d_e^T S C| R(|d_e . v| + rho).
  if (s.dsSpread.rows() != entries_) s.dsSpread = nonNegativeProduct(dS_, s.spread);
  if (s.bRhoJoint.rows() == n_)
    s.dsSpread = s.dsSpread.cwiseMin(
        upAll(EntryMat(nonNegativeProduct(dS_, DMat(upAll(DMat(s.absSv + upAll(DMat(mul<DMat>(magS_, s.spread))))))) +
                       nonNegativeProduct(dSC_, DMat(upAll(DMat(s.bV + s.bRhoJoint)))))));
  s.dotRest = upAll(EntryMat(poseDotRestOnce(s) + s.dsSpread));
  s.gsy = s.gsy.cwiseMin(upAll(EntryMat(upAll(s.q) + s.dotRest)));
}

void PreconditionedInverseEnclosure::refineDots(ColumnTerms& s, AffineMatrix& out) const {
  const int m = s.m;
  s.rho = nonNegativeProduct(magG_, s.spread);
  if (s.rhoJoint.rows() == entries_ && s.rhoJoint.cols() == m) s.rho = s.rho.cwiseMin(s.rhoJoint);
  s.beta = upAll(EntryMat(s.magDV + s.rho));
  // Then one refinement: y - v = -(E0 + P) y - L y with L y = sum_i C_{.,i} (delta_i . y), so
  //   |d_e . (y - v)| <= |d_e| |E0 + P| z + sum_i alpha(e, i) B_i   and   |y| <= |v| + |E0 + P| z + |C| B,
  // with B_i = sum over row i's entries of h_p beta >= |delta_i . y|: it maps valid bounds to valid bounds, and the
  // dot products d_e . C_{.,i} keep their cancellations, where |d_e| spread and |E| z did not. (Measured: a second
  // pass gains a tenth of the first at a sixth of the cost per box; not worth it.)
  s.b = rowSums(s.beta, m);
  const DMat pz = upAll(DMat(mul<DMat>(magS_, s.z))).cwiseMin(s.sy);  // >= |(E0 + P) y|, |E0 + P| <= |S|
  EntryMat dsz = nonNegativeProduct(dS_, s.z);                        // >= |d_e . (S y)|
  if (entries_ > 0) dsz = dsz.cwiseMin(s.gsy);
  // The same refinement to its fixed point: with rho <= dsz + alpha B, B = R(|d_e . v| + rho) satisfies
  // B <= R(|DV|) + R(dsz) + R(alpha) B (R: the row sums of h x, linear), so B <= (I - R(alpha))^-1 (...), verified
  // (R(alpha) is n x n: cheap); the smaller bound is kept.
  if (entries_ > 0 && alphaRowsOk_) {
    DMat fixed;
    const DMat rhs = upAll(DMat(s.bV + rowSums(dsz, m)));
    if (fixedPoint(alphaRows_, alphaRowsInv_, rhs, fixed)) s.b = s.b.cwiseMin(fixed);
  }
  const EntryMat rho2 = upAll(EntryMat(dsz + nonNegativeProduct(alpha_, s.b)));
  const DMat z2 = upAll(DMat(s.absV + pz + upAll(DMat(mul<DMat>(absC_, s.b)))));
  s.rho = s.rho.cwiseMin(rho2);
  s.z = s.z.cwiseMin(z2);
  out.sigma = nonNegativeProduct(dS_, s.z);
  if (entries_ > 0) out.sigma = out.sigma.cwiseMin(s.gsy);
  s.beta = upAll(EntryMat(s.magDV + s.rho));
  s.b = rowSums(s.beta, m);
}

DMat PreconditionedInverseEnclosure::boundRemainder(ColumnTerms& s, AffineMatrix& out) const {
  // Gamma = alpha B;  L L Y <= cgh Gamma.
  s.gamma = nonNegativeProduct(alpha_, s.b);
  // E^2 Y = S S Y + S L Y + L S Y + L L Y (S: pose part with E0, L: geometry part):
  //   |S S y| <= |S| min(|S| z, sy);   |S L y| = |S C Lambda| <= |S C| B (the dot products d_e . y keep their
  //   cancellations); |L S y| <= cgh |d_e . (S y)| <= cgh min(dS z, |d_e| sy);   |L L y| <= cgh Gamma.
  // (And through |S S| <= magS2_, whose products keep their cancellations: |S S y| <= magS2_ z, and with
  // y = v + (y - v), |S S y| <= |S| |S v| + magS2_ |y - v|. Paper, 2 threads: h = 0 2 583 -> 2 319 boxes, +-0.5 mm
  // 5 007 -> 4 631, +-1 mm 10 127 -> 9 763.)
  s.ssy = upAll(DMat(mul<DMat>(magS_, upAll(DMat(mul<DMat>(magS_, s.z))).cwiseMin(s.sy))))
              .cwiseMin(upAll(DMat(mul<DMat>(magS2_, s.z))))
              .cwiseMin(upAll(DMat(upAll(DMat(mul<DMat>(magS_, s.absSv))) + upAll(DMat(mul<DMat>(magS2_, s.spread))))));
  s.sly = upAll(DMat(mul<DMat>(sc_, s.b)));
  s.lsy = chProduct(out.sigma, s.m);
  const DMat ll = chProduct(s.gamma, s.m);
  out.dvm = s.dvm;
  out.dvr = s.dvr;
  out.rho = s.rho;
  out.ll = ll;
  out.ssy = s.ssy;
  out.sy = s.sy;
  out.cross = upAll(DMat(s.sly + s.lsy));
  return upAll(DMat(upAll(DMat(s.ssy + s.sly)) + upAll(DMat(s.lsy + ll))));
}

void PreconditionedInverseEnclosure::writePoseForms(ColumnTerms& s, const DMat& remainder, AffineMatrix& out) const {
  // Affine forms (N V = Y0 - sum_i D_i V dev_i - sum_p G_p V dev_p + E^2 N V). Pose terms -(D_i V)(k, j) (t_i - t0_i)
  // = -[pm +- pr] devMag tau_i: coefficient -pm devMag, the rest
  // (pr devMag and the rounding of the product) to the radius. Geometry terms (G_p V)(k, j) (g_p - g0_p) with
  // (G_p V)(k, j) = sum over the entries e of p of C_{k,row(e)} [dvm +- dvr](e, j): coefficient
  // sum_e C_{k,row(e)} dvm(e, j) h_p, the rest (|C| h dvr and the roundings) to the radius (writeGeometryForms()).
  out.rows = n_;
  out.cols = s.m;
  out.vars = vars_;
  out.params = params_;
  out.centre = s.ym;
  s.radius = upAll(DMat(s.yr + remainder));
  s.poseRadius = DMat::Zero(n_, s.m);
  for (int i = 0; i < vars_; ++i) {
    const DMat& pm = s.dvmI[i];
    const DMat& pr = s.dvrI[i];
    out.pose[i] = -pm * devMag_[i];
    out.poseSpread[i] = upAll(DMat(upAll(DMat(pr * devMag_[i])) + kGamma * out.pose[i].cwiseAbs()));
    s.radius += out.poseSpread[i];
    s.poseRadius += out.poseSpread[i];
  }
}

void PreconditionedInverseEnclosure::writeBilinear(const ColumnTerms& s, AffineMatrix& out) const {
  // The bilinear form (bilinearCoefficients()): the products tau_i gamma_e of
  //   -L v     through d_e . v = c_e . v + sum_i (s_{e,i} . v) tau'_i + ...,   and of
  //   S L y + L S y = [P_m L_c v + L_c P_m v] + S L (y - v) + E0 L v + (P L v - P_m L_c v)
  //                                          + L S (y - v) + L E0 v + (L P v - L_c P_m v),
  // P = sum_i T_i dev_i tau_i the pose part of E (T_i in [dm_i -+ dr_i], P_m with the midpoints), L_c v and
  // L_c P_m v with c_e . v and c_e . (D_i v) at their computed midpoints dvm, q1. The rest, in magnitude:
  //   |S L (y - v)| <= |S C| B_rho,   |E0 L v| <= |E0| |C| B_v,   |(P - P_m) L v| <= (sum_i dr_i dev_i) |C| B_v,
  //   |P_m (L v - L_c v)| <= (sum_i |D_i C| dev_i) B_dvr,   (B_x: row sums of h x over the entries of each row)
  //   |d_e . (S (y - v))| <= dS spread,   |d_e . (E0 v)| <= |d_e| |E0 v|,
  //   |(d_e - c_e) . (P v)| <= devE |P v|,   |c_e . ((P - P_m) v)| <= |c_e| sum_i dvr_i dev_i
  // (dotRest; the last also covers the rounding of q1), times |C| h (chProduct). With the first-order parts'
  // radii (poseSpread, |C| h dvr0: d_e . v without its slope part) and |S S y| as above.
  const int m = s.m;
  const DMat bRho = rowSums(s.rho, m);
  const DMat bDvr = rowSums(s.dvr, m);
  const DMat rowPart = upAll(DMat(upAll(DMat(mul<DMat>(sc_, bRho))) + upAll(DMat(mul<DMat>(e0c_, s.bV))) +
                                  upAll(DMat(mul<DMat>(drc_, s.bV))) + upAll(DMat(mul<DMat>(dmc_, bDvr)))));
  const DMat firstOrder = chProduct(upAll(EntryMat(s.dvr0 + (2.0 * kGamma) * s.dvm.cwiseAbs())), m);
  // (|L L y| is not in it: upperBilinear() bounds it with the geometry terms, from gamma and B.)
  out.bilinearRadius =
      upAll(DMat(upAll(DMat(s.yr + s.ssy + s.poseRadius)) + firstOrder + rowPart + chProduct(s.dotRest, m)));
  out.gammaDot = s.gamma;
  out.dotRest = s.dotRest;
  out.rowB = s.b;
}

void PreconditionedInverseEnclosure::sharePoseRemainder(const ColumnTerms& s, AffineMatrix& out) const {
  // Bisection hints only (the radius is summed already): the remainder's terms through S (|S S y|, |S L y|, |L S y|)
  // shrink with the pose box too, so each pose variable's poseSpread also gets a share of them, in proportion to its
  // part of |P| (row sums of |D_i| |dev_i|). The shares add up to at most these terms, so poseSpread stays a part of
  // the radius. (Paper workspace, 2 threads: 6-7% fewer boxes, with and without anchor uncertainty.)
  if (vars_ <= 0) return;
  const DMat poseRem = s.ssy + s.sly + s.lsy;
  for (int k = 0; k < n_; ++k) {
    double total = 0.0;
    for (int i = 0; i < vars_; ++i) total += poseWeight_[i][k];
    if (!(total > 0.0)) continue;
    for (int i = 0; i < vars_; ++i) {
      const double share = poseWeight_[i][k] / total;
      for (int j = 0; j < s.m; ++j) out.poseSpread[i](k, j) += poseRem(k, j) * share;
    }
  }
}

void PreconditionedInverseEnclosure::writeGeometryForms(ColumnTerms& s, AffineMatrix& out) const {
  // |C| h dvr, plus the rounding of the coefficient sums below (at most a few products and sums each, relative
  // error < kGamma of sum |terms|, i.e. kGamma cgh |dvm|).
  s.radius += chProduct(upAll(EntryMat(s.dvr + (2.0 * kGamma) * s.dvm.cwiseAbs())), s.m);
  for (int j = 0; j < s.m; ++j) {
    GMat& g = out.geometry[j];
    g = GMat::Zero(n_, params_);
    for (int e = 0; e < entries_; ++e) {
      const double d = s.dvm(e, j) * h_[param_[e]];
      for (int k = 0; k < n_; ++k) g(k, param_[e]) -= cg_(k, e) * d;
    }
  }
  out.radius = upAll(s.radius);
  out.splitRadius = out.radius;
}

void PreconditionedInverseEnclosure::affineDots(const DMat& vm, const DMat& vr, EntryMat& dm, EntryMat& dr,
                                                EntryMat* dr0, std::array<EntryMat, kMaxDof>* sv) const {
  // d_e . v = centre . vm + sum_m tau_m (slope_m . vm) + (the radii's part) . vm + d_e . (v - vm). The computed dot
  // products are off by at most kGamma times the dot products of the magnitudes, and |d_e . (v - vm)| <= |d_e| vr
  // with |d_e| <= |centre| + sum_m |slope_m| + radius componentwise, so with weight = |centre| + sum_m |slope_m| the
  // radius is
  //   sum_m |slope_m . vm| + weight . (vr + kGamma |vm|) + radius . (|vm| + vr).
  const int m = static_cast<int>(vm.cols());
  dm.resize(entries_, m);
  dr.resize(entries_, m);
  if (dr0) dr0->resize(entries_, m);
  if (sv)
    for (int s = 0; s < kMaxDof; ++s) (*sv)[s].resize(entries_, m);
  double centre[kEntries], rad[kEntries], t[kEntries];
  for (int j = 0; j < m; ++j) {
    double v[kMaxDof], extra[kMaxDof], absV[kMaxDof];
    for (int l = 0; l < kMaxDof; ++l) {
      v[l] = vm(l, j);
      extra[l] = vr(l, j) + kGamma * std::abs(v[l]);
      absV[l] = std::abs(v[l]) + vr(l, j);
    }
    for (int e = 0; e < entries_; ++e) centre[e] = rad[e] = 0.0;
    for (int l = 0; l < kMaxDof; ++l) {
      const double vl = v[l], xl = extra[l], al = absV[l];
      for (int e = 0; e < entries_; ++e) {
        centre[e] += affCentre_[l][e] * vl;
        rad[e] += affWeight_[l][e] * xl + affRadius_[l][e] * al;
      }
    }
    if (dr0) {
      // (The slope products' roundings are in the weight's part already.)
      for (int e = 0; e < entries_; ++e) (*dr0)(e, j) = up(up(rad[e]) * (1.0 + 4.0 * kGamma));
    }
    for (int s = 0; s < kMaxDof; ++s) {
      for (int e = 0; e < entries_; ++e) t[e] = 0.0;
      for (int l = 0; l < kMaxDof; ++l) {
        const double vl = v[l];
        for (int e = 0; e < entries_; ++e) t[e] += affSlope_[s][l][e] * vl;
      }
      for (int e = 0; e < entries_; ++e) rad[e] += std::abs(t[e]);
      if (sv)
        for (int e = 0; e < entries_; ++e) (*sv)[s](e, j) = t[e];
    }
    // (Every term of rad is >= 0 and their sum has relative rounding error < 4 kGamma.)
    for (int e = 0; e < entries_; ++e) {
      dm(e, j) = centre[e];
      dr(e, j) = up(up(rad[e]) * (1.0 + 4.0 * kGamma));
    }
  }
}

int PreconditionedInverseEnclosure::monotoneDirections(const AffineMatrix& a, int j, const double* jSign,
                                                       double* dir) const {
  using interval::rounding::addUp;
  using interval::rounding::subDown;
  for (int p = 0; p < params_; ++p) dir[p] = 0.0;
  if (a.rows != n_ || j >= a.cols || a.dvm.rows() != entries_) return 0;
  // Per entry, the certified sign of J_{k,row(e)} (d_e . y) (0: none), with d_e . y = d_e . v + d_e . (y - v) in
  // [dvm -+ dvr] +- rho.
  double t[kEntries];
  for (int e = 0; e < entries_; ++e) {
    const double r = addUp(a.dvr(e, j), a.rho(e, j));
    const double m = a.dvm(e, j);
    const double sign = subDown(m, r) > 0.0 ? 1.0 : (addUp(m, r) < 0.0 ? -1.0 : 0.0);
    t[e] = sign * jSign[row_[e]];
  }
  // d phi / d g_p = -(sum of those terms over p's entries): certified when they all have the same certified sign.
  double seen[kMaxGeometryParameters];
  for (int p = 0; p < params_; ++p) seen[p] = 2.0;  // 2: no entry yet
  for (int e = 0; e < entries_; ++e) {
    const int p = param_[e];
    seen[p] = seen[p] == 2.0 ? t[e] : (seen[p] == t[e] ? seen[p] : 0.0);
  }
  int fixed = 0;
  for (int p = 0; p < params_; ++p) {
    if (seen[p] == 2.0 || seen[p] == 0.0 || !(h_[p] > 0.0)) continue;
    dir[p] = -seen[p];
    ++fixed;
  }
  return fixed;
}

double PreconditionedInverseEnclosure::upperOnFace(const AffineMatrix& a, int k, int j, const double* s) const {
  using interval::rounding::addUp;
  using interval::rounding::subDown;
  using interval::rounding::subUp;
  // L L y = sum_e C_{.,row(e)} gamma_e h_e T_e with T_e = delta_e . L y = sum_i (delta_e . C_{.,i}) Lambda_i,
  // Lambda_i = sum over the entries e of row i of h_e gamma_e u_e, u_e = delta_e . y; gamma_e = s_p(e) on the face
  // where s is not 0 and in [-1, 1] elsewhere, delta_e . C_{.,i} in [dcm -+ dcr]. Midpoint-radius throughout (kGamma
  // covers the roundings of the sums). u_e starts from [dvm -+ (dvr + rho)] and is refined once through
  //   u_e = delta_e . v - delta_e . (S y) - T_e   (y - v = -(E0 + P) y - L y),  |delta_e . (S y)| <= sigma,
  // with T_e from the first u: on the face T_e keeps the signs of its first-order part, so the width of u drops from
  // first to second order in h (with every parameter free it is the refinement apply() already made).
  FaceTerms f;
  for (int e = 0; e < entries_; ++e) {
    f.um[e] = a.dvm(e, j);
    f.ur[e] = addUp(a.dvr(e, j), a.rho(e, j));
  }
  faceLambdas(s, f);
  faceDots(f);
  for (int e = 0; e < entries_; ++e) {
    const double m1 = a.dvm(e, j) - f.tm[e];
    const double r1 = up(a.dvr(e, j) + a.sigma(e, j) + f.tr[e] + kGamma * (std::abs(a.dvm(e, j)) + std::abs(f.tm[e])));
    // Both enclose u_e: intersect them.
    const double lo = std::max(subDown(f.um[e], f.ur[e]), subDown(m1, r1));
    const double hi = std::min(addUp(f.um[e], f.ur[e]), addUp(m1, r1));
    if (!(lo <= hi)) continue;  // cannot happen (both contain u_e) unless NaN; keep the first
    const double mid = 0.5 * (lo + hi);
    f.um[e] = mid;
    f.ur[e] = up(std::max(subUp(mid, lo), subUp(hi, mid)));
  }
  faceLambdas(s, f);
  faceDots(f);
  double llm = 0.0, llr = 0.0;
  faceLL(k, s, f, llm, llr);
  // The entry on the face: centre + sum_i |pose_i| + sum_p (s_p geometry_p on the face, |geometry_p| elsewhere)
  // + (radius - |L L y| bound) + [L L y on the face].
  double positive = subUp(a.radius(k, j), a.ll(k, j));
  for (int i = 0; i < a.vars; ++i) positive += std::abs(a.pose[i](k, j));
  double signedSum = 0.0, scale = 0.0;
  for (int p = 0; p < a.params; ++p) {
    const double g = a.geometry[j](k, p);
    scale += std::abs(g);
    if (s[p] != 0.0) {
      signedSum += s[p] * g;
    } else {
      positive += std::abs(g);
    }
  }
  positive = up(positive + kGamma * (scale + std::abs(a.centre(k, j))));
  return addUp(addUp(addUp(a.centre(k, j), positive), signedSum), addUp(llm, llr));
}

void PreconditionedInverseEnclosure::faceLambdas(const double* s, FaceTerms& f) const {
  // Lambda_i = sum over the entries e of row i of h_e gamma_e u_e (upperOnFace()), midpoint lm and radius lr.
  double scale[kMaxDof];
  for (int i = 0; i < n_; ++i) f.lm[i] = f.lr[i] = scale[i] = 0.0;
  for (int e = 0; e < entries_; ++e) {
    const int i = row_[e];
    const double h = h_[param_[e]];
    const double sp = s[param_[e]];
    if (sp != 0.0) {
      const double t = h * sp * f.um[e];
      f.lm[i] += t;
      scale[i] += std::abs(t);
      f.lr[i] += h * f.ur[e];
    } else {
      f.lr[i] += h * (std::abs(f.um[e]) + f.ur[e]);
    }
  }
  for (int i = 0; i < n_; ++i) f.lr[i] = up(f.lr[i] + kGamma * scale[i]);
}

void PreconditionedInverseEnclosure::faceDots(FaceTerms& f) const {
  // T_e = sum_i (delta_e . C_{.,i}) Lambda_i (upperOnFace()), midpoint tm and radius tr.
  for (int e = 0; e < entries_; ++e) {
    double m = 0.0, r = 0.0, scale = 0.0;
    for (int i = 0; i < n_; ++i) {
      const double am = dcm_(e, i), ar = dcr_(e, i);
      m += am * f.lm[i];
      scale += std::abs(am * f.lm[i]);
      r += std::abs(am) * f.lr[i] + ar * (std::abs(f.lm[i]) + f.lr[i]);
    }
    f.tm[e] = m;
    f.tr[e] = up(r + kGamma * scale);
  }
}

void PreconditionedInverseEnclosure::faceLL(int k, const double* s, const FaceTerms& f, double& llm,
                                            double& llr) const {
  // (L L y)_k = sum_e C_{k,row(e)} h_e gamma_e T_e.
  double llScale = 0.0;
  for (int e = 0; e < entries_; ++e) {
    const double ch = c_(k, row_[e]) * h_[param_[e]];
    const double sp = s[param_[e]];
    if (sp != 0.0) {
      const double t = ch * sp * f.tm[e];
      llm += t;
      llScale += std::abs(t);
      llr += std::abs(ch) * f.tr[e];
    } else {
      llr += std::abs(ch) * (std::abs(f.tm[e]) + f.tr[e]);
    }
  }
  llr = up(llr + kGamma * llScale);
}

void PreconditionedInverseEnclosure::bilinearEntry(const AffineMatrix& a, int k, int j, int e, double* m,
                                                   double& scale) const {
  // Coefficient of tau_i gamma_p (p the parameter of entry e, r its row, h its half-width):
  //   dev_i h ((D_i C)(k, r) (c_e . v) + C(k, r) c_e . (D_i v))   (P_m L_c v + L_c P_m v)
  //   - C(k, r) h kappa_i (s_{e,i} . v)                           (-L v through d_e's slope in tau'_i = kappa_i tau_i)
  // Errors of the computed values: dc_ within kGamma dcAbs_, the few operations here and kappa_i's division within
  // kGamma of their terms (added to `scale`; c_e . v, c_e . (D_i v) and s . v: in bilinearRadius).
  const int r = row_[e];
  const double h = entryH_[e], ckr = c_(k, r), dv = a.dvm(e, j), ch = ckr * h;
  for (int i = 0; i < vars_; ++i) {
    const double dh = devMag_[i] * h;
    const double t1 = dc_[i](k, r) * dv, t2 = ckr * a.q1[i](e, j), t3 = ch * kappa_[i] * a.sv[i](e, j);
    m[i] = dh * (t1 + t2) - t3;
    scale += dh * (std::abs(t1) + std::abs(t2) + dcAbs_[i](k, r) * std::abs(dv)) + std::abs(t3);
  }
}

void PreconditionedInverseEnclosure::bilinearCoefficients(const AffineMatrix& a, int k, int j,
                                                          double m[kMaxDof][kMaxGeometryParameters],
                                                          double& rounding) const {
  for (int i = 0; i < kMaxDof; ++i)
    for (int p = 0; p < params_; ++p) m[i][p] = 0.0;
  double scale = 0.0, mi[kMaxDof];
  for (int e = 0; e < entries_; ++e) {
    bilinearEntry(a, k, j, e, mi, scale);
    for (int i = 0; i < vars_; ++i) m[i][param_[e]] = mi[i];
  }
  rounding = up(2.0 * kGamma * up(scale));
}

double PreconditionedInverseEnclosure::upperBilinear(const AffineMatrix& a, int k, int j) const {
  using interval::rounding::addUp;
  using interval::rounding::subDown;
  // max over gamma_p of gamma_p u_p = |u_p|, u_p = b_p + sum_i m_ip tau_i + C(k, r_p) h_p (d_p . L y) in [b_p -+ w_p]:
  // |u_p| <= lambda_p u_p + mu_p with lambda_p = sign(b_p), mu_p = 0 where the sign is certain, else the secant
  // lambda_p = b_p / w_p and mu_p = max((1 - lambda_p)(b_p + w_p), (1 + lambda_p)(w_p - b_p)) (|u| - lambda u is
  // convex: largest at the ends). Then sum_p lambda_p u_p joins the pose terms, and the L L y parts
  // sum_p lambda_p C(k, r_p) h_p (d_p . L y) = sum_i Lambda_i A_i with Lambda_i = sum over row i's entries of
  // h gamma (d . y), |Lambda_i| <= B_i (a.rowB), A_i = sum_p lambda_p C(k, r_p) h_p (d_p . C_{.,i}) in [am -+ ar]
  // (d_p . C_{.,i} in [dcm -+ dcr]); |d_p . L y| <= Gamma_p (a.gammaDot). (Each parameter has one entry here.)
  double acc[kMaxDof];
  for (int i = 0; i < a.vars; ++i) acc[i] = a.pose[i](k, j);
  double am[kMaxDof] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, ar[kMaxDof] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  double constant = 0.0, scale = std::abs(a.centre(k, j)), coefficientScale = 0.0, llScale = 0.0;
  for (int e = 0; e < entries_; ++e) {
    const int p = param_[e];
    const double b = a.geometry[j](k, p);
    const double ch = c_(k, row_[e]) * entryH_[e];
    double mi[kMaxDof];
    bilinearEntry(a, k, j, e, mi, coefficientScale);
    double w = std::abs(ch) * a.gammaDot(e, j);
    for (int i = 0; i < a.vars; ++i) w += std::abs(mi[i]);
    w = up(w * (1.0 + 8.0 * kGamma));
    double lambda;
    if (subDown(b, w) >= 0.0) {
      lambda = 1.0;
      constant += b;
    } else if (addUp(b, w) <= 0.0) {
      lambda = -1.0;
      constant -= b;
    } else {
      lambda = std::max(-1.0, std::min(1.0, b / w));
      const double mu = up(std::max((1.0 - lambda) * (b + w), (1.0 + lambda) * (w - b)) * (1.0 + 8.0 * kGamma));
      constant += lambda * b + mu;
      scale += mu;
    }
    scale += std::abs(b);
    for (int i = 0; i < a.vars; ++i) {
      acc[i] += lambda * mi[i];
      scale += std::abs(mi[i]);
    }
    const double lch = lambda * ch;
    for (int i = 0; i < n_; ++i) {
      const double t = lch * dcm_(e, i);
      am[i] += t;
      ar[i] += std::abs(lch) * dcr_(e, i);
      llScale += std::abs(t) * a.rowB(i, j);
    }
  }
  double ll = 0.0;
  for (int i = 0; i < n_; ++i) ll += (std::abs(am[i]) + ar[i]) * a.rowB(i, j);
  ll = up(up(ll) + 4.0 * kGamma * up(llScale));
  double linear = 0.0;
  for (int i = 0; i < a.vars; ++i) {
    linear += std::abs(acc[i]);
    scale += std::abs(a.pose[i](k, j));
  }
  // (Sums of at most 40 terms each: relative rounding below kGamma of the sum of their magnitudes, <= scale; the
  // coefficients' own errors: 2 kGamma coefficientScale, as in bilinearCoefficients().)
  const double rounding = up(2.0 * kGamma * up(coefficientScale));
  const double rest = up(up(a.bilinearRadius(k, j) + rounding) + up(linear) + ll + 4.0 * kGamma * up(scale));
  return addUp(addUp(a.centre(k, j), constant), rest);
}

Interval PreconditionedInverseEnclosure::AffineMatrix::entry(int k, int j) const {
  double r = radius(k, j);
  for (int i = 0; i < vars; ++i) r += std::abs(pose[i](k, j));
  for (int p = 0; p < params; ++p) r += std::abs(geometry[j](k, p));
  r = up(r);
  return Interval(interval::rounding::subDown(centre(k, j), r), interval::rounding::addUp(centre(k, j), r));
}

void PreconditionedInverseEnclosure::combine(const AffineMatrix& a, int k, const double* w, Combination& out) {
  out.vars = a.vars;
  out.params = a.params;
  double centre = 0.0, radius = 0.0, scale = 0.0;
  for (int i = 0; i < a.vars; ++i) out.pose[i] = out.poseSpread[i] = 0.0;
  for (int p = 0; p < a.params; ++p) out.geometry[p] = 0.0;
  for (int j = 0; j < a.cols; ++j) {
    if (w[j] == 0.0) continue;
    const double aw = std::abs(w[j]);
    centre += w[j] * a.centre(k, j);
    radius += aw * a.radius(k, j);
    double size = std::abs(a.centre(k, j));
    for (int i = 0; i < a.vars; ++i) {
      out.pose[i] += w[j] * a.pose[i](k, j);
      out.poseSpread[i] += aw * a.poseSpread[i](k, j);
      size += std::abs(a.pose[i](k, j));
    }
    for (int p = 0; p < a.params; ++p) {
      out.geometry[p] += w[j] * a.geometry[j](k, p);
      size += std::abs(a.geometry[j](k, p));
    }
    scale += aw * size;
  }
  // Every coefficient is a sum of at most kMaxDof products: its rounding error is below kGamma * aw * size.
  out.centre = centre;
  out.radius = up(up(radius) + kGamma * up(scale));
}

void PreconditionedInverseEnclosure::Combination::add(const Combination& other) {
  // Each sum a + b has rounding error below 2^-53 |a + b| <= kGamma (|a| + |b|).
  double scale = std::abs(centre) + std::abs(other.centre);
  centre += other.centre;
  for (int i = 0; i < vars; ++i) {
    scale += std::abs(pose[i]) + std::abs(other.pose[i]);
    pose[i] += other.pose[i];
    poseSpread[i] += other.poseSpread[i];
  }
  for (int p = 0; p < params; ++p) {
    scale += std::abs(geometry[p]) + std::abs(other.geometry[p]);
    geometry[p] += other.geometry[p];
  }
  radius = up(up(radius + other.radius) + kGamma * up(scale));
}

double PreconditionedInverseEnclosure::Combination::upper() const {
  double r = radius;
  for (int i = 0; i < vars; ++i) r += std::abs(pose[i]);
  for (int p = 0; p < params; ++p) r += std::abs(geometry[p]);
  return interval::rounding::addUp(centre, up(r));
}

double PreconditionedInverseEnclosure::Combination::lower() const {
  double r = radius;
  for (int i = 0; i < vars; ++i) r += std::abs(pose[i]);
  for (int p = 0; p < params; ++p) r += std::abs(geometry[p]);
  return interval::rounding::subDown(centre, up(r));
}

void PreconditionedInverseEnclosure::tightenByResidual(const IMat& v, AffineMatrix& a) const {
  if (!residualOk_ || a.params != 0 || a.vars != vars_ || a.rows != n_ || v.rows() != n_ || v.cols() != a.cols) return;
  if (!inverseMagnitudeReady()) return;
  ResidualCentre centre;
  centre.e0m = e0m_;
  centre.e0r = e0r_;
  centre.absE0 = centre.e0m.cwiseAbs();
  for (int i = 0; i < n_; ++i) centre.dev[i] = devMag_[i];
  for (int j = 0; j < a.cols; ++j) {
    const V6 radius = upAll(V6(magN_ * residualBound(centre, v, a, j)));
    if (!radius.allFinite()) continue;
    for (int k = 0; k < n_; ++k) a.radius(k, j) = std::min(a.radius(k, j), radius[k]);
  }
}

bool PreconditionedInverseEnclosure::inverseMagnitudeReady() const {
  if (magNOk_) return true;
  if (magNFailed_) return false;
  // |N| over the box from N's own forms: N = N I.
  AffineMatrix& nf = work_.identityForms;
  IMat eye(n_, n_);
  for (int j = 0; j < n_; ++j)
    for (int l = 0; l < n_; ++l) eye(l, j) = Interval(l == j ? 1.0 : 0.0);
  if (!apply(eye, nf)) {
    magNFailed_ = true;
    return false;
  }
  M6 mag = nf.centre.cwiseAbs() + nf.radius;
  for (int i = 0; i < vars_; ++i) mag += nf.pose[i].cwiseAbs();
  magN_ = upAll(mag);
  if (!magN_.allFinite()) {
    magNFailed_ = true;
    return false;
  }
  magNOk_ = true;
  return true;
}

PreconditionedInverseEnclosure::V6 PreconditionedInverseEnclosure::residualBound(const ResidualCentre& centre,
                                                                                 const IMat& v, const AffineMatrix& a,
                                                                                 int j) const {
  ResidualColumn x;
  for (int l = 0; l < n_; ++l) {
    split(v(l, j), x.vm[l], x.vr[l]);
    x.xc[l] = a.centre(l, j);
  }
  x.lin = V6::Zero();  // sum_m |X_m|
  for (int m = 0; m < n_; ++m) {
    for (int l = 0; l < n_; ++l) x.xm[m][l] = a.pose[m](l, j);
    x.axm[m] = x.xm[m].cwiseAbs();
    x.lin += x.axm[m];
  }
  x.axc = x.xc.cwiseAbs();
  x.ax = x.axc + x.lin;  // >= |x-hat| over the box (up to rounding, covered by the margins below)
  // The residual r(tau) = v - C J^-1(t) x-hat(tau), dt_i = dev_i tau_i, |tau_i| <= 1:
  //   constant   vm - (I + e0m) xc
  //   linear     -(I + e0m) X_m - dev_m G_m xc                     (G_m = rg_[m]: C D_m(t0))
  //   quadratic  -dev_i G_i X_m - dev_m G_m X_i - f dev_i dev_m H_im xc   (pairs i <= m; f = 1/2 on the diagonal)
  //   cubic      -f dev_i dev_m H_im sum_l X_l tau_l                  (in magnitude)
  //   radii      vr + e0r |x-hat| + sum_i dev_i rgr_i |x-hat| + sum_{il ordered} dev_i dev_l W_il |x-hat|
  // Each floating-point product A x is within kGamma |A| |x| of the exact one; `scale` collects those magnitudes.
  const M6& e0m = centre.e0m;
  const M6& absE0 = centre.absE0;
  const double* dev = centre.dev;
  ResidualSums sums;
  sums.bound = (x.vm - x.xc - e0m * x.xc).cwiseAbs();
  sums.scale = x.vm.cwiseAbs() + x.axc + absE0 * x.axc;
  sums.rest = x.vr + centre.e0r * x.ax;
  for (int m = 0; m < n_; ++m) {
    const V6 gxc = rg_[m] * x.xc;
    sums.bound += (-x.xm[m] - e0m * x.xm[m] - dev[m] * gxc).cwiseAbs();
    sums.scale += x.axm[m] + absE0 * x.axm[m] + dev[m] * (rgAbs_[m] * x.axc);
    sums.rest += dev[m] * (rgr_[m] * x.ax);
  }
  addQuadraticResidual(dev, x, sums);
  // Every term's rounding: at most a few roundings per product and sums of at most ~100 terms, below kGamma.
  return upAll(V6(upAll(sums.bound) + upAll(sums.rest) + 4.0 * kGamma * upAll(sums.scale)));
}

void PreconditionedInverseEnclosure::addQuadraticResidual(const double* dev, const ResidualColumn& x,
                                                          ResidualSums& sums) const {
  // The residual's quadratic and cubic terms and the third-order rest (residualBound()), pair by pair.
  for (int i = 0; i < n_; ++i) {
    for (int m = i; m < n_; ++m) {
      const int p = MatrixHessian::index(i, m);
      const double f = i == m ? 0.5 : 1.0;
      const double dd = dev[i] * dev[m];
      V6 q = -dev[i] * (rg_[i] * x.xm[m]) - (f * dd) * (rh_[p] * x.xc);
      const M6& absH = rhAbs_[p];
      V6 qs = dev[i] * (rgAbs_[i] * x.axm[m]) + (f * dd) * (absH * x.axc);
      if (m != i) {
        q -= dev[m] * (rg_[m] * x.xm[i]);
        qs += dev[m] * (rgAbs_[m] * x.axm[i]);
      }
      sums.bound += q.cwiseAbs();
      sums.scale += qs;
      sums.rest += (f * dd) * (absH * x.lin);                      // the cubic terms
      sums.rest += ((i == m ? 1.0 : 2.0) * dd) * (rw_[p] * x.ax);  // the third-order rest (ordered pairs)
    }
  }
}

}  // namespace enclosure
}  // namespace pkm_accuracy
