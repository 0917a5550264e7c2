// Enclosure of N(t, g) v over a box of poses t AND the box of uncertain geometry parameters g, where
// N = (C J^-1(t, g))^-1 and C is an approximate inverse of J^-1 at the box centre with the geometry at its centre.
//
// With E = C J^-1 - I = E0 + sum_i D_i (t_i - t0_i) + sum_p G_p (g_p - g0_p) (D_i: pose slopes at the centre geometry,
// entry by entry the range of the derivative over the pose box or its second-order Taylor slope at the box centre,
// half as wide; G_p: mean-value form over the pose box and every geometry), N = I - E + E^2 N:
//   (N v)_k in (v - E0 v)_k - sum_i (D_i v)_k dev_i - sum_p (G_p v)_k dev_p  +/-  second-order remainder,
// where every first-order term is exact per variable (the cancellations across legs are kept, unlike interval
// coefficients, which widen every entry of E independently). The remainder splits E = S + L, S the pose part
// (including E0) and L the geometry part, and bounds E^2 N v = S S y + S L y + L S y + L L y (y = N v) with
//   |S S y| <= |S| |S y|,  z >= |y| from (I - |E|) z >= |v| (verified, so rho(|E|) < 1),
//   |S y| <= min(|S| z, |S v| + |S| |y - v|)  (|S v| through the products D_i v, which keep their cancellations),
//   |L S y| <= sum_p |C_{.,i(p)}| h_p min(|d_p^T S| z, |d_p| |S y|),
//     |d_p^T S| <= |d_p^T E0| + sum_i |d_p^T D_i| |t_i - t0_i|,
//   |S L y| <= |S C| B  (L y keeps its cancellations: B_j = sum over row j's parameters of |d_p . y| h_p),
// and L L y through the structure of L: each parameter moves one row i of J^-1 (G_p = C e_i d_p^T, d_p the
// derivative of that row), so (L L y)_k = sum_{p,q} C_ki(p) (d_p . C_{.,i(q)}) (d_q . y) dev_p dev_q keeps the
// cancellations inside the dot products; |d_q . y| <= |d_q . v| + |d_q . (y - v)|, the last bounded through
// y - v = -(E0 + P) y - L y (P the pose part) with the dot products d_q . C_{.,i} again (the magnitude bound
// |d_q| |y - v| alone loses about a factor of two at 1 mm); that also tightens z. On a face of the geometry box
// (upperOnFace) d_q . y is refined once more through the same identity, with the fixed parameters' signs kept. Nothing
// here is heuristic: every bound is rigorous (rounding included, midpoint-radius double arithmetic with a priori error
// bounds).
//
// The dot products d_p . v (and d_p . C_{.,j}) come from the model's affine forms of d_p in the pose where it gives
// them (GeometryRowDerivative::affine: the Gough platform's anchor coordinates), which keep the correlations between
// the components of d_p over the pose box; the interval product of d_p's enclosure with v adds up their ranges.
//
// For the columns that bound the error (apply(v, a, true)), the products tau_i gamma_p of the pose and geometry
// deviations are also kept as one coefficient each (their three sources nearly cancel), and upperBilinear() bounds a
// column through the sign of each parameter's term over the box (docs/uncertainty.md, "Bilinear pose x geometry
// terms").
//
// This is what makes bounded anchor uncertainty cheap: the geometry enters as first-order terms that are exact to
// O(h^2), instead of as interval coefficients whose overestimation never shrinks with the pose box.
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class AffineInverseAction {
 public:
  /// Capacity of the geometry entries (GeometryDerivatives::kCapacity).
  static constexpr int kEntries = GeometryDerivatives::kCapacity;
  using EntryMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kEntries, kMaxDof>;     ///< entries x n
  using RowEntryMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDof, kEntries>;  ///< n x entries

  /// Affine forms of the entries of N V over the box: entry (k, j) is
  ///   centre(k, j) + sum_i pose[i](k, j) tau_i + sum_p geometry[j](k, p) gamma_p + [-radius(k, j), radius(k, j)]
  /// for every (t, g) of the box, with tau_i = (t_i - t0_i) / |t_i - t0_i|max and gamma_p = (g_p - g0_p) / h_p in
  /// [-1, 1], the same for every entry. So linear combinations of entries (sum_j w_j (N V)_kj) keep their
  /// first-order cancellations: combine() encloses them.
  struct AffineMatrix {
    int rows = 0, cols = 0, vars = 0, params = 0;
    DMat centre, radius;
    std::array<DMat, kMaxDof> pose;  ///< pose[i](k, j)
    /// The part of radius(k, j) due to variable i: the uncertainty of pose[i](k, j) itself (the derivative
    /// enclosure's radius times the reach) plus a share of the remainder's terms through the pose part S of E, in
    /// proportion to i's part of |S| - |E0|. With |pose| it is variable i's share of the width (bisection hints);
    /// the shares of all the variables add up to at most radius(k, j).
    std::array<DMat, kMaxDof> poseSpread;
    std::array<GMat, kMaxDof> geometry;  ///< geometry[j](k, p)
    /// For monotoneDirections() and upperOnFace(): d_e . v_j in midpoint-radius form, rho(e, j) >= |d_e . (y_j - v_j)|
    /// (for every d_e in its enclosure and every (t, g) of the box), and the bound of |L L y| included in radius.
    EntryMat dvm, dvr, rho;
    EntryMat sigma;  ///< sigma(e, j) >= |d_e . ((E0 + P) y_j)| (the pose part of E applied to y)
    DMat ll;
    /// The other parts of the remainder's bound in radius: ssy >= |S S y|, cross >= |S L y| + |L S y| (tests).
    DMat ssy, cross;
    /// A second bound of |x - x-hat| (x = entry (k, j) of N V, x-hat its affine part) in which ssy(k, j) is a
    /// separable part: |x - x-hat - (S S y)_k| <= splitRadius(k, j) - ssy(k, j) (GeometryIncrement bounds the dot
    /// products with S S y apart). apply() sets it to radius; tightenByResidual() may lower radius below it, to a
    /// bound with no such part, and keeps it.
    DMat splitRadius;
    /// sy(k, j) >= |(S y_j)_k| (S = E0 + P the pose part of E; GeometryIncrement bounds d . (S S y) through it).
    DMat sy;
    /// The pose x geometry terms kept as products tau_i gamma_p (bilinearCoefficients(), upperBilinear()); only from
    /// apply(v, a, true), for boxes whose variables are the pose coordinates and models with affine geometry
    /// derivatives (else false and empty): q1[i](e, j) = c_e . (D_i v_j) and sv[i](e, j) = s_{e,i} . v_j (midpoints:
    /// c_e the centre of d_e's affine form, s_{e,i} its slope in pose coordinate i, D_i the pose slopes), and
    /// bilinearRadius(k, j) bounds
    /// |(N V)_kj - the bilinear form - (L L y)_kj| (the first-order parts' radii and every remainder term but the
    /// bilinear ones and |L L y|, which upperBilinear() bounds with the geometry terms).
    bool bilinear = false;
    std::array<EntryMat, kMaxDof> q1, sv;
    EntryMat gammaDot;  ///< (e, j) >= |d_e . L y_j| (the L L y part of upperBilinear())
    /// (e, j) >= |d_e . (S y_j) - sum_i (t_i - t0_i) q1[i](e, j)|, S = E0 + P the pose part of E (in bilinearRadius
    /// through L S y; tests)
    EntryMat dotRest;
    DMat rowB;  ///< (i, j) >= |sum over row i's entries of h gamma (d_e . y_j)|
    DMat bilinearRadius;
    /// Enclosure of entry (k, j).
    Interval entry(int k, int j) const;
  };

  /// A linear combination sum_j w_j (N V)_kj of one row, as an affine form (rigorous: rounding in `radius`).
  struct Combination {
    double centre = 0.0, radius = 0.0;
    double pose[kMaxDof];
    double poseSpread[kMaxDof];  ///< for bisection hints (a share of radius; MeanValueEnclosure may weight it)
    double geometry[kMaxGeometryParameters];
    /// Upper / lower end of its range over the box (rounded outward).
    double upper() const;
    double lower() const;
    /// this += other (same box): coefficients add, radii add (rounded up).
    void add(const Combination& other);
    int vars = 0, params = 0;
  };
  /// sum_j w[j] (N V)_kj for row k of an AffineMatrix (w: one exact weight per column).
  static void combine(const AffineMatrix& a, int k, const double* w, Combination& out);

  /// Builds the expansion for a box (box.dualPose must be filled). With withGeometry false, the expansion is in the
  /// box variables only, of J^-1 at the centre of the geometry parameters (no geometry terms: the model's geometry
  /// must then be exact for the forms to hold; also for models without parameters).
  /// @return false if it cannot be built: singular centre, no geometry derivatives, or sizes out of range.
  bool prepare(const model::RobotModel& model, const BoxInput& box, bool withGeometry = true);

  /// The preconditioner C (valid after prepare()).
  const DMat& preconditioner() const { return c_; }
  /// The pose slopes (valid after prepare()): for every t of the box, entry by entry,
  /// C (J^-1(t, g0) - J^-1(t0, g0)) = sum_i T_i (t_i - t0_i) with T_i(k, l) in [mid(k, l) -+ rad(k, l)] (tests).
  const DMat& poseSlopeMid(int i) const { return dm_[i]; }
  const DMat& poseSlopeRad(int i) const { return dr_[i]; }
  int parameters() const { return params_; }
  /// E0 = C J^-1(t0, g0) - I, midpoint and radius, and |t_i - t0_i| <= deviation(i) (valid after prepare()).
  const DMat& residualMid() const { return e0m_; }
  const DMat& residualRad() const { return e0r_; }
  double deviation(int i) const { return devMag_[i]; }
  /// >= |S| = |E0| + sum_i |T_i| |t_i - t0_i|, the pose part of E (valid after prepare()).
  const DMat& poseMagnitude() const { return magS_; }
  /// >= |S(t) S(t)| at every pose t of the box (valid after prepare()): the expansion of (E0 + sum_i T_i dt_i)^2 with
  /// the midpoints' products, which keep their cancellations, and the radii's part in magnitude; never above |S| |S|.
  const DMat& poseSquareMagnitude() const { return magS2_; }

  /// Affine forms of N V (V: n rows, at most kMaxDof columns) valid for every (t, g) of the box.
  /// @return false if |N v| could not be bounded for some column (the Neumann majorant does not converge).
  /// forBounds: the columns bound f_k (not only the signs of J), so the refinements that pay only there are made too:
  /// the dot-product bound of |d_e . (S y)| and, where the box allows it, the bilinear terms (AffineMatrix::bilinear,
  /// for upperBilinear()).
  bool apply(const IMat& v, AffineMatrix& out, bool forBounds = false) const;

  /// Monotonicity in the geometry (the seed paper's section 4.2, for the uncertain parameters). For
  /// phi = (N v)_k, v column j of `a`: d phi / d g_p = -sum over p's entries e of J_{k,row(e)} (d_e . y), y = N v
  /// (each entry moves one row of J^-1). Sets dir[p] to +1 (-1) where that derivative is certified >= 0 (<= 0) over
  /// the box and every admissible geometry, else 0; returns how many are nonzero. `jSign[i]`: the sign of J_ki
  /// certified over the box and geometry (+1, -1; 0: unknown).
  int monotoneDirections(const AffineMatrix& a, int j, const double* jSign, double* dir) const;

  /// Upper bound of entry (k, j) over the box and the face of the geometry box where gamma_p = s[p] for every
  /// s[p] != 0 (+1 / -1; 0: the whole range). Tighter than entry(k, j) there: the first-order terms of the fixed
  /// parameters keep their signs, and so does |L L y|, which is then bounded as the quadratic form it is on the
  /// face instead of term by term in magnitude.
  double upperOnFace(const AffineMatrix& a, int k, int j, const double* s) const;

  /// The pose x geometry terms of entry (k, j) (a.bilinear must be true): with them,
  ///   (N V)_kj in centre + sum_i pose_i tau_i + sum_p (geometry_p + sum_i m[i][p] tau_i) gamma_p +- bilinearRadius,
  /// the products tau_i gamma_p being those of S L v + L S v (S the pose part of E, L the geometry part) and of the
  /// geometry derivatives' own pose slopes in the first-order geometry terms, which the entry's radius bounds in
  /// magnitude. The coefficients are computed in floating point: `rounding` (>= 0) bounds their error
  /// (sum over (i, p) of |computed - exact|, to be added to the radius).
  void bilinearCoefficients(const AffineMatrix& a, int k, int j, double m[kMaxDof][kMaxGeometryParameters],
                            double& rounding) const;

  /// Upper bound of entry (k, j) over the box and every geometry from its bilinear form (a.bilinear must be true):
  /// each parameter's term is gamma_p u_p with u_p = geometry_p + sum_i m[i][p] tau_i + C(k, row) h_p (d_p . L y)
  /// (the last: its share of L L y); its maximum over gamma_p, |u_p|, is bounded by a linear function of u_p (u_p
  /// itself where its sign is certain, the secant over its range elsewhere), and those linear parts join the pose
  /// coefficients and the dot products d_p . C, so that they cancel where the signs of the geometry terms are stable
  /// over the box (what the faces give when every direction is certified, without needing the certificates).
  double upperBilinear(const AffineMatrix& a, int k, int j) const;

  /// z >= (I - a)^-1 rhs column by column for a >= 0 (square, at most kMaxDof), verified: a z > 0 with rhs + a z <= z
  /// (roundings included) proves rho(a) < 1 and bounds every x >= 0 with x <= rhs + a x. approx: any approximation of
  /// (I - a)^-1 (the starting point). The same check as the expansion's own fixed points (GeometryIncrement uses it).
  /// @return false if the verification fails.
  static bool fixedPointBound(const DMat& a, const DMat& approx, const DMat& rhs, DMat& z);

  /// Tightens the radii of `a` = the forms of N V from apply(v, a) through the residual (docs/enclosures.md,
  /// "Residual radius"): with x-hat(tau) the affine part of a column x = N v (its centre and pose coefficients),
  ///   x - x-hat = N (v - C J^-1(t) x-hat)   exactly (N = (C J^-1(t))^-1),
  /// and C J^-1(t) is expanded to second order at the box centre, C J^-1(t0) + sum_i C D_i(t0) dt_i + (1/2) sum_il
  /// C H_il(t0) dt_i dt_l, with the third-order rest bounded through the model's affine Hessian forms over the box
  /// (RobotModel::preconditionedHessianMagnitude: its linear part, remainder and quadratic part), so that the
  /// residual's quadratic terms keep their cancellations (the pose slopes' products against the Hessian). Then
  /// |x - x-hat| <= |N| |residual| with |N| from N's own forms (one apply(I) per prepare()). Each radius is replaced
  /// where the new bound is smaller (every other field of `a` is kept, splitRadius too: they stay valid). Only after
  /// prepare() without geometry terms on workspace boxes centred at their midpoint, with the model's affine Hessian;
  /// otherwise (and for matrices with geometry terms) nothing changes. Rigorous: every product in floating point is
  /// covered by kGamma times the product of the magnitudes, every non-negative sum is rounded up.
  void tightenByResidual(const IMat& v, AffineMatrix& a) const;

 private:
  /// z >= (I - |E|)^-1 rhs column by column, verified (so also z >= |x| for every x with |x| <= rhs + |E| |x|).
  /// @return false if the verification fails (the Neumann majorant does not converge).
  bool majorant(const DMat& rhs, DMat& z) const;

  int n_ = 0, vars_ = 0, params_ = 0, entries_ = 0;
  DMat c_;
  DMat e0m_, e0r_;  ///< C J^-1(centre, g0) - I, midpoint and radius
  /// Pose slopes T_i at the centre geometry, midpoint and radius: entry by entry the range of C dJ^-1/dt_i over the
  /// box or the second-order Taylor slope (prepare()); either way E(t, g0) - E0 = sum_i T_i (t_i - t0_i).
  std::array<DMat, kMaxDof> dm_, dr_;
  double devMag_[kMaxDof];  ///< |t_i - t0_i| <=
  EntryMat gm_, gr_;        ///< row derivative d_e per geometry entry (over the pose box and geometry box)
  /// The same derivatives as affine forms in the pose, where the model gives them for every entry
  /// (GeometryRowDerivative::affine; then gm_, gr_ are their ranges). Stored per component l (and symbol m), entry by
  /// entry, so that the loops over the entries vectorise: centres, radii, slopes (coefficient of tau_m in component
  /// l) and weights |centre| + sum_m |slope| (for the roundings and v's radius).
  bool affine_ = false;
  double affCentre_[kMaxDof][kEntries], affRadius_[kMaxDof][kEntries], affWeight_[kMaxDof][kEntries];
  double affSlope_[kMaxDof][kMaxDof][kEntries];
  /// The coefficients m[i] of tau_i gamma_p for entry e (parameter p) of entry (k, j) of `a` (bilinearCoefficients());
  /// adds the magnitudes their rounding is relative to to `scale`.
  void bilinearEntry(const AffineMatrix& a, int k, int j, int e, double* m, double& scale) const;
  /// With the affine forms (affine_ must be true): [dm -+ dr](e, j) encloses d_e . v_j for every pose of the box
  /// and every geometry, centre . v +- (sum_m |slope_m . v| + the radii's and roundings' parts), which keeps the
  /// first-order correlations between the components of d_e over the pose box (the interval product [d_e] . v adds
  /// up their ranges, and is never the narrower one: measured, the same boxes without it).
  /// With dr0 (and sv): also the radius without the slope part sum_m |slope_m . v| (the rest covers the roundings of
  /// the slope products too) and the slope products slope_m . vm themselves (sv[m](e, j)).
  void affineDots(const DMat& vm, const DMat& vr, EntryMat& dm, EntryMat& dr, EntryMat* dr0 = nullptr,
                  std::array<EntryMat, kMaxDof>* sv = nullptr) const;
  /// The bilinear terms (AffineMatrix::bilinear) can be built for this box: workspace boxes (pose = box variables),
  /// affine geometry derivatives for every entry, one entry per parameter.
  bool bilinear_ = false;
  std::array<DMat, kMaxDof> dc_;     ///< D_i C (midpoints of the pose slopes times C, computed in floating point)
  std::array<DMat, kMaxDof> dcAbs_;  ///< up(|D_i| |C|): bounds the rounding of dc_
  double kappa_[kMaxDof];            ///< dev_i / (the affine forms' scale of tau_i): their tau'_i = kappa_i tau_i
  DMat e0c_, drc_, dmc_;             ///< >= |E0| |C|, >= (sum_i dr_i dev_i) |C|, >= sum_i |D_i C| dev_i
  EntryMat devE_;                    ///< (e, l) >= |d_e - c_e|_l: sum_m |slope| + radius
  EntryMat absCe_;                   ///< |c_e|
  RowEntryMat cg_;                   ///< (k, e): C_{k, row(e)}
  EntryMat alpha_;                   ///< (e, j): bound of |d_e . C_{.,j}|
  EntryMat dcm_, dcr_;               ///< (e, j): d_e . C_{.,j}, midpoint and radius
  int param_[kEntries];              ///< parameter of each entry
  int row_[kEntries];                ///< row of J^-1 each entry moves
  /// Runs of consecutive entries moving the same row: run r is entries runStart_[r] to runStart_[r + 1] - 1.
  int runs_ = 0;
  int runStart_[kEntries + 1];
  double h_[kMaxGeometryParameters];      ///< |g_p - g0_p| <=
  double entryH_[kEntries];               ///< h_p of each entry's parameter
  DMat magE_, magS_, magE0_, absC_, q_;   ///< |E| <= |S| + |L|, |S|, |E0|, |C|, ~(I - |E|)^-1
  DMat magSP_;                            ///< sum_i |D_i| |dev_i| >= |P|, the pose part of E - E0
  DMat magE2_;                            ///< >= |E| |E|
  DMat magS2_;                            ///< >= |S(t) S(t)| over the box (poseSquareMagnitude())
  std::array<DVec, kMaxDof> poseWeight_;  ///< row sums of |D_i| |dev_i| (bisection hints only)
  EntryMat magG_;                         ///< |d_e|
  EntryMat dS_;                           ///< (e, l): >= |d_e^T S|_l, S = E0 + P
  DMat sc_;                               ///< >= |S C|
  EntryMat dSC_;                          ///< (e, l) >= |d_e^T S C|_l
  DMat alphaRows_, alphaRowsInv_;         ///< R(alpha): row sums of h alpha per row of J^-1; ~(I - R(alpha))^-1
  bool alphaRowsOk_ = false;
  using JSquare = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2 * kMaxDof, 2 * kMaxDof>;
  using JMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2 * kMaxDof, kMaxDof>;
  JSquare joint_, jointInv_;  ///< [[|S|, |C|], [R(dS), R(alpha)]] and ~(I - it)^-1 (apply(): |y - v| and rho jointly)
  bool jointOk_ = false;
  /// tightenByResidual(): C D_i(t0) (midpoint, radius: its rounding), C H_il(t0) per pair (the affine Hessian forms'
  /// centre times C, in floating point), W_il >= the third-order rest's weight per ordered pair (L / 6 + rest / 2 +
  /// Q / 12), and |N| over the box (computed on first use).
  using M6 = Eigen::Matrix<double, kMaxDof, kMaxDof>;
  bool residualOk_ = false;
  std::array<M6, kMaxDof> rg_, rgr_, rgAbs_;  ///< (rgAbs_ = |rg_|, for the roundings' magnitudes)
  std::array<M6, MatrixHessian::kPairs> rh_, rhAbs_, rw_;
  mutable bool magNOk_ = false, magNFailed_ = false;
  mutable M6 magN_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
