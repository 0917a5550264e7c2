// Affine forms of N V over a box of poses t AND the box of uncertain geometry parameters g, where
// N = (C J^-1(t, g))^-1 and C is an approximate inverse of J^-1 at the box centre with the geometry at its centre
// (so N C = J): each entry of N V is enclosed as a centre plus one exact first-order term per pose variable and per
// geometry parameter, plus a radius, in noise symbols shared by all the entries, so that linear combinations of the
// entries keep their cancellations across legs. The radius bounds the second-order remainder E^2 N V
// (E = C J^-1 - I) through a verified Neumann majorant of |N V|; nothing here is heuristic: every bound is rigorous,
// roundings included (midpoint-radius double arithmetic with a priori error bounds, valid in any rounding mode).
//
// Derivations: docs/uncertainty.md ("First-order (affine) treatment of the geometry", "Bilinear pose x geometry
// terms", "Monotonicity in the geometry") and docs/enclosures.md (pose slopes through the Hessian, |S S|, the residual
// radius, and the key of the symbols used here: "Symbols of the affine forms in the code").
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

class PreconditionedInverseEnclosure {
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
    /// apply(v, a, Refinements::ForErrorBounds), for boxes whose variables are the pose coordinates and models with
    /// affine geometry derivatives (else false and empty): q1[i](e, j) = c_e . (D_i v_j) and sv[i](e, j) = s_{e,i} .
    /// v_j (midpoints: c_e the centre of d_e's affine form, s_{e,i} its slope in pose coordinate i, D_i the pose
    /// slopes), and bilinearRadius(k, j) bounds
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

  /// What prepare() expands J^-1 in.
  enum class GeometryTerms {
    Expanded,  ///< the box variables and the geometry parameters (models with geometry parameters only)
    /// the box variables only, J^-1 at the centre of the geometry parameters (no geometry terms: the model's geometry
    /// must then be exact for the forms to hold, or the caller bounds the geometry's part apart; also for models
    /// without parameters)
    AtCentre,
  };
  /// Builds the expansion for a box (box.dualPose must be filled).
  /// @return false if it cannot be built: singular centre, no geometry derivatives, or sizes out of range.
  bool prepare(const model::RobotModel& model, const BoxInput& box, GeometryTerms geometry = GeometryTerms::Expanded);

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

  /// Which refinements apply() makes.
  enum class Refinements {
    Standard,  ///< those that pay for any columns (J = N C, its signs, N itself)
    /// the columns bound f_k, so the refinements that pay only there are made too: the dot-product bound of
    /// |d_e . (S y)| and, where the box allows it, the bilinear terms (AffineMatrix::bilinear, for upperBilinear())
    ForErrorBounds,
  };
  /// Affine forms of N V (V: n rows, at most kMaxDof columns) valid for every (t, g) of the box.
  /// @return false if |N v| could not be bounded for some column (the Neumann majorant does not converge).
  bool apply(const IMat& v, AffineMatrix& out, Refinements refinements = Refinements::Standard) const;

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

  // prepare(), step by step (docs/enclosures.md and docs/uncertainty.md give the derivations).
  /// Which bound of |C H_il| over the box the pose slopes come from (preparePoseSlopes()).
  struct HessianSource {
    bool affine = false;    ///< the model's affine bound (RobotModel::preconditionedHessianMagnitude)
    bool box = false;       ///< the interval Hessian over the box
    bool midpoint = false;  ///< a workspace box expanded at its midpoint (the affine bound in three parts)
    bool centred() const { return affine || box; }
  };
  /// n_, vars_, params_, C, the geometry derivatives (into the workspace) and E0; false if they cannot be built.
  bool prepareCentre(const model::RobotModel& model, const BoxInput& box, bool withGeometry);
  /// The pose slopes dm_, dr_ (and the residual radius's data when it applies) and devMag_.
  void preparePoseSlopes(const model::RobotModel& model, const BoxInput& box);
  HessianSource boundHessian(const model::RobotModel& model, const BoxInput& box);
  /// The direct ranges of D_i over the box (where the model's affine Hessian bound is not used) and devMag_.
  void rangeSlopes(const model::RobotModel& model, const BoxInput& box, const HessianSource& source);
  /// The centred range of D_i (intersected with the direct one), and its Taylor slope [tm -+ tr].
  void centredSlope(int i, const HessianSource& source, DMat& tm, DMat& tr);
  /// Entry by entry, the Taylor slopes where their sum of radii is the smaller.
  void chooseTaylorSlopes(const std::array<DMat, kMaxDof>& tm, const std::array<DMat, kMaxDof>& tr);
  void prepareResidualWeights();
  /// |S|, |P|, the bisection weights and |S S|.
  void boundPoseMagnitudes();
  void boundPoseSquare();
  /// h, the entries' derivatives d_e (and their affine forms) and the runs of entries per row.
  void storeGeometryEntries(const model::RobotModel& model);
  /// |C|, |d_e|, alpha, d_e . C, |E|, |E| |E|, |E0|; returns the bound of |L|.
  DMat boundGeometryMagnitudes();
  /// |d_e^T S|, |S C| and |d_e^T S C| with their dot products' cancellations.
  void boundDotProducts();
  void boundDotProductsWithC(const DMat& w, const DMat& sc, const EntryMat& absGm);
  void prepareBilinear(const BoxInput& box);
  void prepareAffineDeviations();
  /// ~(I - |E|)^-1, ~(I - R(alpha))^-1 and the joint system's approximate inverse.
  void approximateInverses();

  // apply(), step by step: the terms of one call (defined in the .cpp file).
  struct ColumnTerms;
  /// V's midpoint-radius form, Y0 = V - E0 V and the majorant z >= |N V|; false if it does not converge.
  bool startColumns(const IMat& v, ColumnTerms& s) const;
  /// d_e . v (with the slope products sv for the bilinear terms).
  void geometryDots(ColumnTerms& s, std::array<EntryMat, kMaxDof>* sv) const;
  /// D_i V, |P V|, |L V| and the bound delta of |Y - Y0|.
  void posePart(ColumnTerms& s) const;
  /// q: sum_i dev_i |c_e . (D_i v)| (with the products q1 for the bilinear terms).
  void centreDots(ColumnTerms& s, std::array<EntryMat, kMaxDof>* q1) const;
  const EntryMat& poseDotRestOnce(ColumnTerms& s) const;
  /// spread >= |y - v| (jointly with R(|d_e . (y - v)|) where the joint system is available).
  void boundSpread(ColumnTerms& s) const;
  bool boundSpreadJointly(const DMat& first, ColumnTerms& s) const;
  /// sy >= |S y|.
  void boundPoseProduct(ColumnTerms& s) const;
  /// gsy >= |d_e . (S y)| through the affine forms' centres (columns that bound f_k).
  void boundPoseDotsByCentre(ColumnTerms& s) const;
  /// rho >= |d_e . (y - v)|, B, z refined, sigma.
  void refineDots(ColumnTerms& s, AffineMatrix& out) const;
  /// The bound of |E^2 N V| = |S S y| + |S L y| + |L S y| + |L L y| (its parts into `out`).
  DMat boundRemainder(ColumnTerms& s, AffineMatrix& out) const;
  void writePoseForms(ColumnTerms& s, const DMat& remainder, AffineMatrix& out) const;
  void writeBilinear(const ColumnTerms& s, AffineMatrix& out) const;
  void sharePoseRemainder(const ColumnTerms& s, AffineMatrix& out) const;
  void writeGeometryForms(ColumnTerms& s, AffineMatrix& out) const;
  /// R(x)(i, j) = up(sum over the entries e of row i of h_p(e) x(e, j)) (x >= 0, m columns).
  DMat rowSums(const EntryMat& x, int m) const;
  /// up(|C| R(x)) >= cgh x.
  DMat chProduct(const EntryMat& x, int m) const;

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

  // upperOnFace(), step by step: u_e = d_e . y, Lambda_i and T_e = d_e . L y in midpoint-radius form.
  struct FaceTerms {
    double um[kEntries], ur[kEntries], tm[kEntries], tr[kEntries];
    double lm[kMaxDof], lr[kMaxDof];
  };
  void faceLambdas(const double* s, FaceTerms& f) const;
  void faceDots(FaceTerms& f) const;
  /// (L L y)_k on the face: midpoint llm, radius llr (both start at 0).
  void faceLL(int k, const double* s, const FaceTerms& f, double& llm, double& llr) const;

  // tightenByResidual(), step by step.
  using V6 = Eigen::Matrix<double, kMaxDof, 1>;
  struct ResidualCentre {
    M6 e0m, e0r, absE0;
    double dev[kMaxDof];
  };
  /// One column: v (midpoint, radius) and its affine part x-hat = xc + sum_m xm[m] tau_m.
  struct ResidualColumn {
    V6 vm, vr, xc, axc, lin, ax;
    V6 xm[kMaxDof], axm[kMaxDof];
  };
  /// The residual's bound (sum of |terms|), its roundings' magnitudes and the radii's part.
  struct ResidualSums {
    V6 bound, scale, rest;
  };
  /// |N| over the box (magN_) on first use; false if it cannot be bounded.
  bool inverseMagnitudeReady() const;
  /// >= |v - C J^-1(t) x-hat(tau)| over the box for column j.
  V6 residualBound(const ResidualCentre& centre, const IMat& v, const AffineMatrix& a, int j) const;
  void addQuadraticResidual(const double* dev, const ResidualColumn& x, ResidualSums& sums) const;

  /// Scratch reused from box to box, so that nothing is allocated per box: the model's derivatives and Hessian
  /// bounds (prepare()) and the forms of N I (tightenByResidual()). Callers keep one PreconditionedInverseEnclosure per
  /// thread.
  struct Workspace {
    GeometryDerivatives geo;
    MatrixHessian hessian, atCentre;  ///< over the box; at its centre
    MatrixWithGradient poseD;         ///< J^-1 and its pose derivatives over the box (dual numbers)
    /// >= |C H_il| over the box, per pair; with the box midpoint as centre t0 its three parts at t0 + s dt,
    /// |C H_il| <= magCH + s linCH + s^2 quadCH, and the remainder's part restCH = |C| R0 and centre centreCH = C Hc
    /// of the same affine Hessian forms (RobotModel::preconditionedHessianMagnitude).
    std::array<DMat, MatrixHessian::kPairs> magCH, linCH, quadCH, restCH, centreCH;
    AffineMatrix identityForms;  ///< N I (tightenByResidual(): |N| over the box)
  };
  mutable Workspace work_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
