// The increase of the worst error f_k over the nominal geometry, bounded separately from the nominal error
// ("decomposed" geometry form, docs/uncertainty.md; key of symbols: docs/enclosures.md).
//
// Contract: prepare() once per box (from the nominal PreconditionedInverseEnclosure and its forms of J0 = N C); where
// it is Ready, bound(), rowBound(), centreIncrease(), entryIncrease() and signs() hold for that box and every geometry
// of the model's geometry box until the next prepare(). Every bound but centreIncrease() is rigorous.
//
// With J0 = J(t, g0) (nominal geometry g0, the centre of the geometry box), J = J(t, g) and Delta J = J - J0: where
// J_kj keeps a sign s_j over the pose box Q and every geometry, e_j |J_kj| = e_j |J0_kj| + s_j e_j Delta J_kj, and
// elsewhere e_j |J_kj| <= e_j |J0_kj| + e_j |Delta J_kj|. So for every (t, g) of Q x G
//   f_k(t, g) <= f_k(t, g0) + e_k^T Delta J u + sum_{j unstable} e_j |Delta J_kj|,   u_j = s_j e_j (stable j, else 0),
// and the first term is bounded by the nominal form (PreconditionedInverseEnclosure without geometry). With M = J^-1
// and Delta M = M(t, g) - M(t, g0), whose row i depends on leg i's parameters only (delta r_i, the anchor coordinates
// of leg i), J = J0 - J0 Delta M J gives exactly
//   e_k^T Delta J u = - sum_i J0_ki (delta r_i . w) + sum_{i,i'} J0_ki (delta r_i . J0_{.,i'}) (delta r_i' . y),
//   w = J0 u, y = J u,  delta r_i = sum_{p of row i} (g_p - g0_p) dbar_p,  dbar_p = int_0^1 d_p(t, g0 + s (g - g0)) ds,
// d_p the derivative of row i of J^-1 with respect to parameter p, enclosed over Q and every geometry by the model's
// affine forms in the pose (GeometryRowDerivative::affine), so dbar_p too. The first sum is sum_p gamma_p h_p b_p(t),
// b_p = -J0_{k,i(p)} (dbar_p . w), an affine form in the pose symbols tau of the box (the products of the J0 entries'
// affine forms, from the nominal PreconditionedInverseEnclosure, with those of dbar_p): its maximum over gamma is
// sum_p h_p |b_p|, bounded by the secant of |x| over b_p's range, a linear form in tau plus a constant. The linear
// part joins the nominal bound's own linear part (the same tau), so the pose slopes of the nominal error and of its
// geometry increase cancel where they do. The second sum is bounded by sum_i |J0_ki| phi_i(B), phi_i(B) >=
// |sum_i' (delta r_i . J0_{.,i'}) z_i'| for every |z| <= B (the signs of z chosen jointly with leg i's geometry; at
// most (A B)_i, A_ii' >= sum_{p of row i} h_p |dbar_p . J0_{.,i'}|), B_i' >= sum_{q of row i'} h_q |dbar_q . y| the
// verified fixed point of B <= B0 + phi(B), B0_i >= sum h_q |dbar_q . w| (y = w - J0 Delta M y; the dot products keep
// their cancellations), and |Delta J| <= DJ = |J0| Y, Y the verified fixed point of |Y_.j| <= A_.j + phi(|Y_.j|) (Y =
// Delta M J, Delta J = -J0 Y), which also decides which entries keep their signs over Q x G (|J0_kj| > DJ_kj) and
// bounds the others' e_j |Delta J_kj|.
//
// Refinements (docs/uncertainty.md, "Decomposed form"): the part S S y of w's radius (the nominal expansion's pose
// remainder) enters dbar_e . w as |dbar_e^T S| |S y| where that is smaller (columnDots); with the model's
// parameter terms (GeometryDerivatives::withParameterSlopes) dbar_e = (pose form) + sum_s kappa_s gamma'_s / 2 + its
// remainder, and the products gamma_p gamma'_s are bounded apart (parameterDots) instead of widening dbar_e;
// rowBound() is the coarse bound for rows that are split anyway, and Row::fixed / straddle let the caller take the
// exact maximum of the first-order part over the pose vertices; phi() couples the signs in the second-order terms.
//
// Why: the combined form (PreconditionedInverseEnclosure with the geometry) expands N = (C J^-1(t, g))^-1 around the
// pose AND the geometry at once, so its remainder carries the products of pose and geometry deviations through the
// inverse
// (|L S y|, |S L y|, |L L y|, ...), each bounded in magnitude; here the nominal part keeps the nominal remainder and
// the geometry part is exact to first order in the geometry with a remainder of second order in h. With the
// increment known exactly to first order (an unsound point estimate, docs/design-notes.md) the search would need
// fewer boxes at +-1 mm than the nominal case; with the combined form it needs more boxes than with this one
// (docs/uncertainty.md): the radii of the forms of w and J0 (the nominal expansion's remainder) still enter the
// strongly cancelling dot products dbar_p . w in magnitude, and so the second-order sum and the secants.
//
// Rounding: the affine forms' arithmetic (interval::AffineForm) is rigorous; the non-negative bounds are sums of
// products computed in double and rounded up with a relative margin of 1e-12 (sums of at most 64 products have
// relative error below 1.5e-14).
#pragma once

#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/interval/AffineForm.hpp"

namespace pkm_accuracy {
namespace enclosure {

class GeometryIncrement {
 public:
  using Form = interval::AffineForm<kMaxDof>;

  /// The bound of e_k^T (J(t, g) - J(t, g0)) u over the box and every geometry, for one component k and weights u:
  ///   e_k^T Delta J u <= linear(tau) + constant,  |e_k^T Delta J u| <= magnitude,
  /// tau the pose symbols of the nominal PreconditionedInverseEnclosure's forms (tau_i = (t_i - t0_i) / |t_i -
  /// t0_i|max).
  struct Row {
    Form linear;
    double constant = 0.0;   ///< secant offsets and the second-order sum (>= 0, rounded up)
    double magnitude = 0.0;  ///< (for lower bounds valid for every geometry)
    /// The same bound split for an exact maximum over the pose symbols (MeanValueEnclosure): e_k^T Delta J u <=
    /// fixed(tau) + sum_s straddleH[s] |straddle[s](tau)| + second, `fixed` the secant terms of the parameters whose
    /// b_q keeps its sign (exact), straddle[s] the b_q whose range contains 0 (their secants, offsets included, are
    /// in `linear` and `constant`). A convex function of tau: its maximum over the box is at a vertex.
    Form fixed;
    Form straddle[kMaxGeometryParameters];
    double straddleH[kMaxGeometryParameters];
    int straddling = 0;
    double second = 0.0;
    /// Centre of the coefficient of gamma_p = (g_p - g0_p) / h_p in the first-order part (hints; not certified).
    double coefficient[kMaxGeometryParameters];
    int params = 0;
  };

  /// What prepare() achieved.
  enum class Preparation {
    Ready,        ///< the rows can be bounded
    Unsupported,  ///< the box variables are not the pose coordinates with the centre at the box midpoint, or the
                  ///< model gives no affine geometry derivatives for every entry (e.g. tool-point uncertainty)
    Unverified,   ///< the fixed point for |Delta J| does not verify: the geometry's effect is too large on this box
  };

  /// Builds the parts shared by the rows for a box: j0 are the affine forms of J0 = N C over the box (all n columns
  /// of C, from PreconditionedInverseEnclosure::apply after prepare(model, box, false)). Where it is not Ready the
  /// caller uses another form.
  Preparation prepare(const model::RobotModel& model, const BoxInput& box, const PreconditionedInverseEnclosure& act,
                      const PreconditionedInverseEnclosure::AffineMatrix& j0);

  /// The part S S y of a column x = N v of the nominal expansion that columnDots() bounds apart, from its
  /// PreconditionedInverseEnclosure::AffineMatrix (per row l): ssy >= |S S y|, sy >= |S y|, and splitRadius, a bound of
  /// |x - x-hat| of which ssy is a separable part (|x - x-hat - S S y| <= splitRadius - ssy). The column's form may
  /// carry a smaller radius without such a part (the residual radius).
  struct SeparablePart {
    double ssy[kMaxDof], sy[kMaxDof], splitRadius[kMaxDof];
    /// Column j of `a`.
    static SeparablePart ofColumn(const PreconditionedInverseEnclosure::AffineMatrix& a, int j);
  };

  /// The increase of sum_j u_j J_kj(t, g) over its value at g0, e_k^T Delta J u, bounded over the box and every
  /// geometry, for weights u given by w = J0 u (the affine forms of the column N C u of the nominal expansion, all
  /// n rows; |u_j| <= e_j for the bounds of f_k), with `part` that column's separable part. Valid after prepare().
  /// @return false if a bound is not finite.
  bool bound(int k, const Form* w, const SeparablePart& part, Row& out) const;

  /// The cheap bound of the same increase for every weights |u_j| <= e_j: |e_k^T Delta J u| <= sum_j e_j DJ_kj (a
  /// constant; no first-order terms). For columns whose box is split whatever their increment (MeanValueEnclosure).
  void rowBound(int k, Row& out) const;

  /// An estimate (NOT certified) of the largest first-order increase at the box centre, sum_p h_p |b_p(centre)|, for
  /// the centres wc of w = J0 u.
  double centreIncrease(int k, const double* wc) const;

  /// Entry (k, j) of an PreconditionedInverseEnclosure::AffineMatrix without its geometry terms, as a Form in the same
  /// pose symbols (exact: the same centre, coefficients and radius; only for matrices built without geometry terms).
  static Form entryForm(const PreconditionedInverseEnclosure::AffineMatrix& a, int k, int j);

  /// DJ_kj >= |J_kj(t, g) - J_kj(t, g0)| over the box and every geometry (valid after prepare()).
  double entryIncrease(int k, int j) const { return dj_[k][j]; }

  /// The signs of J certified over the box and every geometry by |J0_kj| > DJ_kj (valid after prepare()).
  const SignPattern& signs() const { return signs_; }

 private:
  // The steps of prepare(), in this order.
  /// kappa_i = dev_i / a_i relating the nominal forms' pose symbols to the model's (tau'_i = kappa_i tau_i).
  /// @return false unless the box variables are the pose coordinates centred at the box midpoint.
  bool poseScales(const BoxInput& box, double* kappa) const;
  /// The model's affine geometry derivatives over the box (into derivatives_), the sensor errors and the half-widths
  /// h_p. @return false unless every entry has an affine form.
  bool loadDerivatives(const model::RobotModel& model, const BoxInput& box);
  /// dbar_e's affine forms (dC_, dA_, dR_, dSlope_, dDev_) and parameter terms (dK_, dDevK_) from derivatives_.
  void storeDerivativeForms(const double* kappa);
  /// dS_ >= |dbar_e^T S| (S the pose part of the nominal expansion's E). @return false if act's sizes do not fit.
  bool boundDerivativesTimesPosePart(const PreconditionedInverseEnclosure& act);
  /// A (a_, not yet rounded up) and the centres and deviations of the dot products dbar_e . J0_{.,j}.
  void boundCouplings(const PreconditionedInverseEnclosure::AffineMatrix& j0, double (*dotCentre)[kMaxDof],
                      double (*dotDev)[kMaxDof]);
  /// phi()'s tables (rowEntries_, rowEntry_, phiD_, phiP_) from those dot products.
  void buildPhiTables(const double (*dotCentre)[kMaxDof], const double (*dotDev)[kMaxDof]);
  /// DJ >= |Delta J| (dj_) through the verified fixed point Y of |Y| <= A + A |Y|. @return false if it fails.
  bool boundJacobianIncrease();
  /// signs_ from |J0_kj| > DJ_kj.
  void certifySigns();

  // The steps of bound().
  /// b_p = sum over p's entries e of J0_{k,row(e)} (dbar_e . w) for every parameter p, as sums of affine forms in the
  /// pose symbols: centre bc, coefficients ba, radius terms br (>= 0) and the magnitudes berr their rounding is
  /// relative to.
  struct ParameterForms {
    double bc[kMaxGeometryParameters], ba[kMaxDof][kMaxGeometryParameters], br[kMaxGeometryParameters];
    double berr[kMaxGeometryParameters];
  };
  /// The b_p of column w for row k; rowB0 += the terms of B0 (not rounded up), cross += the products gamma_p
  /// gamma'_s bounded in magnitude.
  void parameterForms(int k, const Form* w, const SeparablePart& part, ParameterForms& b, DMat& rowB0,
                      double& cross) const;
  /// The first-order part of out (linear, fixed, straddle, coefficient) from the secants of h_p |b_p|, with the
  /// secants' offsets summed into `constant` and sum_p h_p |b_p|'s bound into `magnitude`.
  void firstOrderBound(const ParameterForms& b, Row& out, double& constant, double& magnitude) const;
  /// sum_i |J0_ki| phi_i(B) (rounded up), B the fixed point rowB of B <= B0 + A B tightened through phi.
  double secondOrderSum(int k, const DMat& rowB0, const DMat& rowB) const;

  /// out[e] >= dbar_e . w for every entry e (w: n forms in the same pose symbols).
  void dots(const Form* w, Form* out) const;
  /// out[e] >= sum_s |kappa_s . w| / 2 over the box for every entry e (the parameter terms of dbar_e . w, every
  /// gamma').
  void parameterDots(const Form* w, double* out) const;
  /// The same for a column of the nominal expansion (w: its forms with their complete radii) and its separable part:
  /// each out[e] is the smaller of two complete bounds with the same centre and coefficients, dots(w) and the split
  /// one, where S S y enters as |dbar_e^T S| sy (the dot products keep their cancellations) where that is smaller
  /// than |dbar_e| ssy, and the rest of w - w-hat through splitRadius - ssy.
  void columnDots(const Form* w, const SeparablePart& part, Form* out) const;

  /// phi_i(x) >= max over |z| <= x of |sum_i' (delta r_i . J0_{.,i'}) z_i'| over the box and every geometry, for x >=
  /// 0: the coupling of row i through A with the signs of the z_i' chosen jointly (one geometry of leg i for all i'),
  /// phi_i(x) = max_eta sum_i' x_i' |sum_{e of row i} eta_e h_e c_ei'| + sum_i' x_i' D_ii' (c_ei' the centre of
  /// dbar_e . J0_{.,i'}, D_ii' = sum_e h_e times its deviation and parameter terms). Monotone and subadditive in x,
  /// phi_i(x) <= (A x)_i; equal to (A x)_i where the row has more than kPhiEntries entries.
  double phi(int i, const double* x) const;
  /// Tightens a bound z >= 0 with z >= rhs + A z (A's spectral radius below 1, verified) to z = min(z, rhs + phi(z)),
  /// `rounds` times: each result is again such a bound (see bound()).
  void tightenFixedPoint(const double* rhs, double* z, int rounds) const;
  static constexpr int kPhiEntries = 8;
  int n_ = 0, params_ = 0, entries_ = 0;
  std::vector<double> e_;
  double h_[kMaxGeometryParameters];
  int param_[GeometryDerivatives::kCapacity], row_[GeometryDerivatives::kCapacity];
  double entryH_[GeometryDerivatives::kCapacity];
  Form j0_[kMaxDof][kMaxDof];       ///< J0 entries over the box
  double magJ0_[kMaxDof][kMaxDof];  ///< >= |J0| over the box
  /// dbar_e's affine forms, component l, entry e (entries innermost, for dots()): centre, coefficient of tau_m,
  /// radius and deviation (sum_m |coefficient| + radius, rounded up).
  double dC_[kMaxDof][GeometryDerivatives::kCapacity], dA_[kMaxDof][kMaxDof][GeometryDerivatives::kCapacity];
  double dR_[kMaxDof][GeometryDerivatives::kCapacity], dDev_[kMaxDof][GeometryDerivatives::kCapacity];
  double dSlope_[kMaxDof][GeometryDerivatives::kCapacity];  ///< >= sum_m |coefficient of tau_m|
  double dS_[kMaxDof][GeometryDerivatives::kCapacity];      ///< >= |dbar_e^T S|, component l, entry e
  /// d_e's parameter terms (kappa, coefficient of gamma'_s in component l; 0 where the model gives none) and half
  /// the sum of their magnitudes (dbar_e's deviation through them).
  double dK_[kMaxDof][kMaxDof][GeometryDerivatives::kCapacity], dDevK_[kMaxDof][GeometryDerivatives::kCapacity];
  double a_[kMaxDof][kMaxDof];  ///< A
  /// phi(): per row, its entries (rowEntry_), the sign patterns' |sum_e eta_e h_e c_ei'| (phiP_, pattern-major) and D.
  int rowEntries_[kMaxDof], rowEntry_[kMaxDof][GeometryDerivatives::kCapacity];
  double phiP_[kMaxDof][(1 << (kPhiEntries - 1)) * kMaxDof], phiD_[kMaxDof][kMaxDof];
  double dj_[kMaxDof][kMaxDof];  ///< DJ >= |Delta J|
  DMat aMat_, aApprox_;          ///< A and ~(I - A)^-1 (for the fixed points)
  SignPattern signs_;
  /// prepare()'s scratch: the model's geometry derivatives over the box (kept with its capacity, box after box).
  GeometryDerivatives derivatives_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
