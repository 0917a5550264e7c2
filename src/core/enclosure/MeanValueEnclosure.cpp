#include "pkm_accuracy/core/enclosure/MeanValueEnclosure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "pkm_accuracy/core/enclosure/GeometryIncrement.hpp"
#include "pkm_accuracy/core/enclosure/IntervalLinearAlgebra.hpp"
#include "pkm_accuracy/core/enclosure/PreconditionedInverseEnclosure.hpp"
#include "pkm_accuracy/core/interval/Rounding.hpp"

namespace pkm_accuracy {
namespace enclosure {
namespace {
/// At most this many faces per row and box, each on the smaller face the previous one certified (on the probe's
/// small boxes, bench/uncertainty_probe, the bound stops improving after 2-3).
constexpr int kFaceIterations = 4;

using interval::rounding::up;  // a non-negative quantity computed in double (a few sums): up() bounds the exact one

/// Second-order bound of f_k from the affine forms of N V (PreconditionedInverseEnclosure). With uncertain geometry
/// parameters the geometry enters as first-order terms too; with an exact geometry the expansion is in the box
/// variables only (the same identities as the interval-Gauss form in encloseImpl(), the remainder bounded through a
/// verified Neumann majorant of |N v| column by column; the search keeps far fewer boxes with it, docs/enclosures.md).
/// J = N C is enclosed first (for the signs); then, with s_j the sign of J_kj where it is known,
///   f_k = sum_j |J_kj| e_j = max over the signs s_q of the undetermined entries of (N C w_s)_k,
///   w_s,j = s_j e_j,
/// each choice one column N v (v = C w_s) whose first-order terms cancel across legs (much tighter than adding
/// |J_kj| e_j for the undetermined entries). Beyond kMaxOpen undetermined entries in a row (or negligible ones),
/// |J_kj| e_j is bounded by the secant of |x| e_j over J_kj's enclosure: a weight in the column plus a constant.
/// Only the components in `rows` (a subset of box.rows) are bounded. The geometry directions certified for a row
/// are added to out.faces (which the caller initialised).
/// @return false if the affine form cannot be built (then the interval path runs instead).
/// Upper bound of a decomposed column from the nominal column at g0 and its increase split as in
/// GeometryIncrement::Row: the maximum over the vertices of the pose symbols' box of the convex function
///   nominal(tau) + fixed(tau) + sum_s h_s |straddle_s(tau)|
/// (exact, where the secants of |straddle_s| lose their offsets at the box's inner points), plus every radius and
/// the second-order constant. Computed in double, the vertices in Gray-code order: from one vertex to the next one
/// symbol changes sign, so the linear part and each straddle_s(tau) are updated by +-2 x its coefficient (exact
/// doubling, one rounded addition). Each running value stays within (its centre + the sum of its coefficients'
/// magnitudes) of the terms counted in `scale`, so after at most 63 updates its rounding error is below
/// 63 * 2^-52 of those terms (any rounding mode); with the per-vertex sum of at most 1 + kMaxGeometryParameters
/// weighted terms the whole error stays below 1e-13 scale.
double upperAtVertices(const PreconditionedInverseEnclosure::Combination& nominal, const GeometryIncrement::Row& r,
                       int vars) {
  double scale = std::abs(nominal.centre) + std::abs(r.fixed.centre());
  double slope[kMaxDof];
  for (int i = 0; i < vars; ++i) {
    slope[i] = nominal.pose[i] + r.fixed.coefficient(i);
    scale += std::abs(nominal.pose[i]) + std::abs(r.fixed.coefficient(i));
  }
  double radii = nominal.radius + r.fixed.radius() + r.second;
  const int straddling = r.straddling;
  double x[kMaxGeometryParameters];
  for (int s = 0; s < straddling; ++s) {
    const GeometryIncrement::Form& b = r.straddle[s];
    scale += r.straddleH[s] * b.deviation() + r.straddleH[s] * std::abs(b.centre());
    radii += r.straddleH[s] * b.radius();
    x[s] = b.centre();
    for (int i = 0; i < vars; ++i) x[s] -= b.coefficient(i);  // the vertex with every tau_i = -1
  }
  double linear = nominal.centre + r.fixed.centre();
  for (int i = 0; i < vars; ++i) linear -= slope[i];
  const auto value = [&]() {
    double v = linear;
    for (int s = 0; s < straddling; ++s) v += r.straddleH[s] * std::abs(x[s]);
    return v;
  };
  double best = value();
  for (int g = 1; g < (1 << vars); ++g) {
    const int i = __builtin_ctz(static_cast<unsigned>(g));  // the symbol that changes sign
    const bool rising = ((g ^ (g >> 1)) >> i) & 1;          // -1 -> +1
    linear += rising ? 2.0 * slope[i] : -2.0 * slope[i];
    for (int s = 0; s < straddling; ++s) {
      const double a = 2.0 * r.straddle[s].coefficient(i);
      x[s] += rising ? a : -a;
    }
    best = std::max(best, value());
  }
  const double result = best + up(up(radii) + 1e-13 * scale);
  return std::isfinite(result) ? interval::rounding::nextUp(result) : std::numeric_limits<double>::infinity();
}

bool encloseAffine(const model::RobotModel& model, const BoxInput& box, unsigned rows, ErrorBounds& out) {
  const auto wants = [rows](int k) { return ((rows >> k) & 1u) != 0; };
  // Measured on the paper workspace at +-0.5 mm (bench/RESULTS.md): 2 and 1e-2 beat 1 / 3 and 2e-3 by 1.3-1.7x.
  constexpr int kMaxOpen = 2;
  constexpr double kNegligible = 1e-2;
  static thread_local PreconditionedInverseEnclosure act;
  static thread_local PreconditionedInverseEnclosure::AffineMatrix jac, nv;
  static thread_local PreconditionedInverseEnclosure::Combination comb;
  static thread_local GeometryIncrement increment;
  const int n = model.dof();
  const int vars = box.variables;
  // The decomposed geometry form: the nominal expansion (no geometry terms) plus GeometryIncrement's bound of the
  // increase over the geometry; the combined form where it cannot be built. Where it is built but does not verify
  // (the nominal expansion's fixed point, or the increase's), neither does the combined form, whose E contains the
  // nominal one and the geometry's terms: the caller's interval path then. (Measured, paper +-1 mm / +-0.5 mm: 3 405
  // / 2 327 such boxes, the same boxes and bounds without the combined form's attempt.)
  bool decomposed = model.hasGeometryUncertainty() && box.decomposeGeometry && vars == n;
  if (decomposed) {
    decomposed = act.prepare(model, box, PreconditionedInverseEnclosure::GeometryTerms::AtCentre);
    if (decomposed) {
      const DMat& c0 = act.preconditioner();
      IMat all(n, n);
      for (int j = 0; j < n; ++j)
        for (int l = 0; l < n; ++l) all(l, j) = Interval(c0(l, j));
      if (!act.apply(all, jac)) return false;
      act.tightenByResidual(all, jac);
      const GeometryIncrement::Preparation built = increment.prepare(model, box, act, jac);
      if (built == GeometryIncrement::Preparation::Unverified) return false;
      decomposed = built == GeometryIncrement::Preparation::Ready;
    }
  }
  if (!decomposed &&
      !act.prepare(model, box,
                   model.hasGeometryUncertainty() ? PreconditionedInverseEnclosure::GeometryTerms::Expanded
                                                  : PreconditionedInverseEnclosure::GeometryTerms::AtCentre))
    return false;
  const int params = act.parameters();
  const int modelParams = decomposed ? model.geometryParameterCount() : params;
  const DMat& c = act.preconditioner();
  // Only the rows (components) asked for (`rows`): the others keep +inf.
  // J = N C, column by column, for the columns with an entry of a wanted row whose sign is not known yet (from a
  // containing box).
  const SignPattern& known = box.knownSigns;
  int need[kMaxDof];
  int needed = 0;
  for (int j = 0; j < n; ++j) {
    bool all = true;
    for (int k = 0; k < n; ++k) all = all && (known.known(k * n + j) || !wants(k));
    if (!all || decomposed) need[needed++] = j;
  }
  // Entries not computed (columns not needed, unknown sign): [-1, 1] stands for "sign unknown"; only signs are read
  // from entries of rows that are not wanted.
  Interval entryOf[kMaxDof][kMaxDof];
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) entryOf[k][j] = Interval(-1.0, 1.0);
  if (needed > 0) {
    IMat cols(n, needed);
    for (int q = 0; q < needed; ++q)
      for (int l = 0; l < n; ++l) cols(l, q) = Interval(c(l, need[q]));
    if (!decomposed) {  // (decomposed: all the columns, computed above)
      if (!act.apply(cols, jac)) return false;
      act.tightenByResidual(cols, jac);
    }
    // (Decomposed: the ranges over every geometry, J0_kj +- DJ_kj, for the signs and the secants below.)
    for (int q = 0; q < needed; ++q)
      for (int k = 0; k < n; ++k)
        entryOf[k][need[q]] = jac.entry(k, q) + (decomposed ? Interval(-increment.entryIncrease(k, need[q]),
                                                                       increment.entryIncrease(k, need[q]))
                                                            : Interval(0.0));
  }
  out.signs = SignPattern();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      const int bit = k * n + j;
      if (known.known(bit)) {
        // Only the sign is used for a known entry (its magnitude bound is never needed: it is not undetermined).
        entryOf[k][j] = Interval(known.sign(bit));
      }
      if (entryOf[k][j].lower() > 0.0) out.signs.positive |= std::uint64_t(1) << bit;
      if (entryOf[k][j].upper() < 0.0) out.signs.negative |= std::uint64_t(1) << bit;
    }
  const std::vector<double>& e = model.sensorError();
  // One column per row and choice of the undetermined signs.
  struct Column {
    int row;
    IVec v;
  };
  static thread_local std::vector<Column> columns;
  columns.clear();
  Interval rest[kMaxDof];
  // Row k has entries bounded by their secants: its columns bound f_k without being f_k (then no monotonicity).
  bool secantTerms[kMaxDof];
  int columnsOfRow[kMaxDof];
  for (int k = 0; k < n; ++k) {
    rest[k] = Interval(0.0);
    secantTerms[k] = false;
    columnsOfRow[k] = 0;
    if (!wants(k)) continue;
    Interval entries[kMaxDof];
    double rowSize = 0.0;
    for (int j = 0; j < n; ++j) {
      entries[j] = entryOf[k][j];
      rowSize += std::abs(c(k, j)) * e[j];  // C ~ J at the box centre: the scale of f_k
    }
    double w[kMaxDof];
    int open[kMaxDof];
    int opened = 0;
    // The undetermined entries: the kMaxOpen whose linear bound below costs most get both signs (one column per
    // choice); the others are bounded by the secant of |x| over their enclosure, |J_kj| e_j <= s_j J_kj + o_j
    // (interval::absSecant: weight s_j in [-e_j, e_j], offset o_j into `rest`), so their first-order terms still
    // join the column's, where the magnitude bound |J_kj| <= mag([J_kj]) lost them. (Paper workspace, 1.05 x the
    // maxima, 2 threads: +-1 mm 113 061 -> 93 651 boxes, +-0.5 mm 42 981 -> 40 847, h = 0 23 727 -> 23 783.)
    interval::AbsSecant secant[kMaxDof];
    int undetermined[kMaxDof];
    int count = 0;
    for (int j = 0; j < n; ++j) {
      const Interval& x = entries[j];
      w[j] = x.lower() > 0.0 ? e[j] : (x.upper() < 0.0 ? -e[j] : 0.0);  // exact
      if (w[j] != 0.0) continue;
      secant[j] = interval::absSecant(x, e[j]);
      undetermined[count++] = j;
    }
    std::stable_sort(undetermined, undetermined + count,
                     [&secant](int a, int b) { return secant[a].offset > secant[b].offset; });
    for (int q = 0; q < count; ++q) {
      const int j = undetermined[q];
      if (opened < kMaxOpen && entries[j].mag() * e[j] > kNegligible * rowSize) {
        open[opened++] = j;
      } else {
        w[j] = secant[j].weight;
        rest[k] += Interval(secant[j].offset);
        secantTerms[k] = true;
      }
    }
    // The choice with the signs of the entries' midpoints first (the row's largest column at the box centre), so
    // that a row which misses its target tends to do so on its first column (the bilinear bound is skipped after).
    int preferred = 0;
    for (int q = 0; q < opened; ++q)
      if (entries[open[q]].mid() < 0.0) preferred |= 1 << q;
    for (int index = 0; index < (1 << opened); ++index) {
      const int choice = index ^ preferred;
      for (int q = 0; q < opened; ++q) w[open[q]] = (choice & (1 << q)) ? -e[open[q]] : e[open[q]];
      Column col{k, IVec::Constant(n, Interval(0.0))};
      for (int j = 0; j < n; ++j) {
        if (w[j] == 0.0) continue;
        for (int l = 0; l < n; ++l) col.v[l] += Interval(c(l, j)) * Interval(w[j]);
      }
      columns.push_back(col);
      ++columnsOfRow[k];
    }
  }
  out.componentSmear = DMat::Zero(n, vars);
  out.geometrySmear = GMat::Zero(n, modelParams);
  out.geometrySensitivity = GMat::Zero(n, modelParams);
  double upper[kMaxDof], lower[kMaxDof];
  bool missed[kMaxDof];  // a column of the row has missed its target (BoxInput::targets) already
  static thread_local PreconditionedInverseEnclosure::Combination best[kMaxDof];
  static thread_local double bestCoefficient[kMaxDof][kMaxGeometryParameters];  // (decomposed: geometry hints)
  double atCentre[kMaxDof];  // the largest column's value estimate at the box centre (not certified)
  // Decomposed: some columns' increase bounded coarsely (coarse), and the row's bound without those increases.
  bool coarse[kMaxDof];
  double atG0[kMaxDof];
  for (int k = 0; k < n; ++k) {
    upper[k] = -std::numeric_limits<double>::infinity();
    missed[k] = false;
    lower[k] = 0.0;
    atCentre[k] = -std::numeric_limits<double>::infinity();
    coarse[k] = false;
    atG0[k] = -std::numeric_limits<double>::infinity();
  }
  double unit[kMaxDof];
  // Monotonicity in the geometry: where f_k (the largest of its columns' functions, no secant terms) is certified
  // monotone in some parameters over the box and geometry, its maximum lies on the face with those parameters at
  // their raising ends, and upperOnFace() bounds every column there (while the row's affine forms are at hand).
  double onFace[kMaxDof];
  for (int k = 0; k < n; ++k) onFace[k] = std::numeric_limits<double>::infinity();
  double dir[kMaxGeometryParameters], common[kMaxGeometryParameters], jSign[kMaxDof];
  // A bound of row k misses its target (BoxInput::targets; never without targets).
  const bool targeted = box.targets.size() == n;
  const auto misses = [&](int k, double bound) {
    return targeted && (Interval(bound) + rest[k]).upper() > box.targets[k];
  };
  // Bisection hints: an increase not in the nominal column's pose terms (its radius and constant, mostly second
  // order in the pose box; for a coarse column the estimated increase at the centre) shared out over the pose
  // variables like the nominal column's radius, twice over (such terms shrink faster than first-order ones when
  // a variable is halved). Measured (paper, 5% margins): +-1 mm 61 643 -> 59 255 boxes (full bounds) -> 58 099
  // (coarse columns too), +-0.5 mm 34 115 -> 33 303 -> 32 823; once over: 60 079 / 33 475 (full bounds); by the
  // increase's own slopes: 61 023.
  const auto shareIncrease = [&](double increase) {
    constexpr double kIncreaseShare = 2.0;
    double spread = 0.0;
    for (int i = 0; i < vars; ++i) spread += comb.poseSpread[i];
    if (!(spread > 0.0) || !(increase > 0.0)) return;
    const double scale = kIncreaseShare * increase / spread;
    for (int i = 0; i < vars; ++i) comb.poseSpread[i] += scale * comb.poseSpread[i];
  };
  // The rows' columns in segments of at most n (a row's columns are one segment unless it has more than n), and the
  // segments in batches of at most n columns, one apply per batch: apply() works column by column (the same bounds
  // as one apply per row), and its cost per call beyond the columns' is paid once per batch instead of once per
  // row.
  for (std::size_t batchFirst = 0; batchFirst < columns.size();) {
    int segmentRow[kMaxDof], segmentFirst[kMaxDof], segmentSize[kMaxDof];
    int segments = 0, batchSize = 0;
    while (batchFirst + batchSize < columns.size()) {
      const std::size_t first = batchFirst + static_cast<std::size_t>(batchSize);
      const int k = columns[first].row;
      int m = 0;
      while (first + m < columns.size() && columns[first + m].row == k && m < n) ++m;
      if (batchSize + m > n) break;
      segmentRow[segments] = k;
      segmentFirst[segments] = batchSize;
      segmentSize[segments] = m;
      ++segments;
      batchSize += m;
    }
    IMat batch(n, batchSize);
    for (int q = 0; q < batchSize; ++q) batch.col(q) = columns[batchFirst + q].v;
    if (!act.apply(batch, nv, PreconditionedInverseEnclosure::Refinements::ForErrorBounds)) return false;
    act.tightenByResidual(batch, nv);
    for (int segment = 0; segment < segments; ++segment) {
      const int k = segmentRow[segment], offset = segmentFirst[segment], m = segmentSize[segment];
      for (int q = offset; q < offset + m; ++q) {
        for (int j = 0; j < batchSize; ++j) unit[j] = j == q ? 1.0 : 0.0;
        PreconditionedInverseEnclosure::combine(nv, k, unit, comb);
        double first = 0.0;
        const double centreAtG0 = comb.centre;
        GeometryIncrement::Row r;
        PreconditionedInverseEnclosure::Combination nominal;  // (decomposed: the column at g0)
        // (Decomposed: the box is split whatever this column's increase, which is then bounded coarsely.)
        bool doomed = false, easy = false;
        if (decomposed) {
          // f_k(t, g) <= sum_j w_j J_kj(t, g) + rest[k] (the signs and secants above hold over J's range over every
          // geometry) = (this column at g0) + e_k^T Delta J w: the increment's linear part joins the column's, its
          // constant goes to the radius.
          const double lowerAtG0 = comb.lower();
          if (targeted && !(lowerAtG0 > box.targets[k])) {
            doomed = missed[k] || misses(k, comb.upper());
          }
          if (doomed) {
            increment.rowBound(k, r);
            coarse[k] = true;
            double wc[kMaxDof];
            for (int l = 0; l < n; ++l) wc[l] = nv.centre(l, q);
            const double centreIncrease = increment.centreIncrease(k, wc);
            atG0[k] = std::max(atG0[k], comb.upper() + centreIncrease);
            shareIncrease(centreIncrease);
          } else if (targeted) {
            // Where the coarse increase certifies this column already, no full bound (44% of them at +-1 mm, the
            // same boxes).
            increment.rowBound(k, r);
            easy = !misses(k, comb.upper() + r.constant);
          }
          if (!doomed && !easy) {
            GeometryIncrement::Form w[kMaxDof];
            for (int l = 0; l < n; ++l) w[l] = GeometryIncrement::entryForm(nv, l, q);
            if (!increment.bound(k, w, GeometryIncrement::SeparablePart::ofColumn(nv, q), r)) return false;
          }
          nominal = comb;
          double err = std::abs(comb.centre) + std::abs(r.linear.centre());
          comb.centre += r.linear.centre();
          for (int i = 0; i < vars; ++i) {
            err += std::abs(comb.pose[i]) + std::abs(r.linear.coefficient(i));
            comb.pose[i] += r.linear.coefficient(i);
          }
          comb.radius = up(comb.radius + r.linear.radius() + r.constant + 1e-15 * err);
          if (!doomed && !easy) shareIncrease(r.linear.radius() + r.constant);
          lower[k] = std::max(lower[k], interval::rounding::subDown(lowerAtG0, r.magnitude));
          for (int p = 0; p < r.params; ++p) first += std::abs(r.coefficient[p]);
          if (doomed || easy) first += r.constant;  // (no coefficients: the coarse bound, above the first order)
        }
        // At the box centre, over the geometries: the first-order terms' maximum G, plus G^2 / value for the
        // second-order ones (measured: ~1.3% of f_k at +-1 mm, where G is 10-18% of it; G itself for a column whose
        // value is not positive, a sign choice far from the row's maximum).
        for (int p = 0; p < comb.params; ++p) first += std::abs(comb.geometry[p]);
        const double second = centreAtG0 > first ? first * first / centreAtG0 : first;
        const double estimate = centreAtG0 + first + second;
        atCentre[k] = std::max(atCentre[k], estimate);
        if (!decomposed) lower[k] = std::max(lower[k], comb.lower());  // |x| e >= w x for every |w| <= e
        // The bilinear bound (pose x geometry terms kept as products) where this column's bound misses the target,
        // unless an earlier column of the row has missed it already (the row is undecided whatever this one gives).
        double columnUpper = comb.upper();
        if (decomposed && !doomed && r.straddling > 0 && (!targeted || misses(k, columnUpper)))
          columnUpper = std::min(columnUpper, upperAtVertices(nominal, r, vars));
        if (nv.bilinear && (!targeted || (!missed[k] && misses(k, columnUpper))))
          columnUpper = std::min(columnUpper, act.upperBilinear(nv, k, q));
        missed[k] = missed[k] || misses(k, columnUpper);
        if (!doomed) atG0[k] = std::max(atG0[k], columnUpper);
        if (columnUpper > upper[k]) {
          upper[k] = columnUpper;
          best[k] = comb;
          for (int p = 0; p < modelParams && decomposed; ++p) bestCoefficient[k][p] = r.coefficient[p];
        }
      }
      // Only where the bound is not good enough already (BoxInput::targets), f_k has no secant terms, and every
      // column of the row is in this segment.
      const bool enough = targeted && upper[k] <= box.targets[k];
      int directions = secantTerms[k] || enough || m != columnsOfRow[k] ? 0 : params;
      for (int i = 0; i < n; ++i) jSign[i] = out.signs.sign(k * n + i);
      for (int q = 0; q < m && directions > 0; ++q) {
        act.monotoneDirections(nv, offset + q, jSign, dir);
        directions = 0;
        for (int p = 0; p < params; ++p) {
          common[p] = q == 0 ? dir[p] : (common[p] == dir[p] ? dir[p] : 0.0);
          directions += common[p] != 0.0 ? 1 : 0;
        }
      }
      if (directions > 0) {
        for (int p = 0; p < params; ++p) {
          if (common[p] > 0.0) out.faces.up[k] |= std::uint64_t(1) << p;
          if (common[p] < 0.0) out.faces.down[k] |= std::uint64_t(1) << p;
        }
        double largestOnFace = -std::numeric_limits<double>::infinity();
        for (int q = offset; q < offset + m; ++q)
          largestOnFace = std::max(largestOnFace, act.upperOnFace(nv, k, q, common));
        onFace[k] = largestOnFace;
      }
    }
    batchFirst += static_cast<std::size_t>(batchSize);
  }
  double smear[kMaxDof] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  double largest = 0.0;
  out.centreEstimate = DVec::Constant(n, std::numeric_limits<double>::infinity());
  for (int k = 0; k < n; ++k) {
    if (!wants(k)) continue;
    if (columnsOfRow[k] > 0) out.centreEstimate[k] = atCentre[k] + rest[k].upper();
    // (onFace only where there are no secant terms, i.e. rest = 0.)
    const double bound = std::min((Interval(upper[k]) + rest[k]).upper(), onFace[k]);
    out.lower[k] = std::max(out.lower[k], lower[k]);
    if (!(bound < out.upper[k])) continue;
    out.upper[k] = bound;
    if (coarse[k]) {
      if (out.searchUpper.size() != n) out.searchUpper = out.upper;
      out.searchUpper[k] = std::min(bound, (Interval(atG0[k]) + rest[k]).upper());
    } else if (out.searchUpper.size() == n) {
      out.searchUpper[k] = bound;
    }
    if (!(bound > 0.0) || !std::isfinite(bound)) continue;
    // Bisection hints: each variable's share of the bound's width (of the search's bound, relative to which the
    // verifier reads them); sensitivities d f_k / d g_p ~ coefficient / h_p (only the sign is used).
    const double searchBound = out.searchUpper.size() == n ? out.searchUpper[k] : bound;
    for (int i = 0; i < vars; ++i) {
      out.componentSmear(k, i) = (std::abs(best[k].pose[i]) + best[k].poseSpread[i]) / searchBound;
      smear[i] = std::max(smear[i], out.componentSmear(k, i));
      largest = std::max(largest, smear[i]);
    }
    for (int p = 0; p < params; ++p) {
      out.geometrySmear(k, p) = std::abs(best[k].geometry[p]) / bound;
      out.geometrySensitivity(k, p) = best[k].geometry[p];
    }
    for (int p = 0; p < modelParams && decomposed; ++p) {
      out.geometrySmear(k, p) = std::abs(bestCoefficient[k][p]) / bound;
      out.geometrySensitivity(k, p) = bestCoefficient[k][p];
    }
  }
  if (largest > 0.0) {
    for (int i = 0; i < vars; ++i) out.splitScore[i] = smear[i];
  }
  return true;
}

}  // namespace

bool MeanValueEnclosure::encloseOnFace(const model::RobotModel& model, const BoxInput& box, int k,
                                       ErrorBounds& out) const {
  const int n = model.dof();
  const int vars = box.variables;
  const int params = model.geometryParameterCount();
  // The face: every parameter with a certified direction at its raising end; the others stay parameters (their
  // numbering on the face model is `free`).
  const std::uint64_t up = out.faces.up[k], down = out.faces.down[k];
  GVec values(params);
  int free[kMaxGeometryParameters];
  int freeCount = 0;
  for (int p = 0; p < params; ++p) {
    const std::uint64_t bit = std::uint64_t(1) << p;
    if (up & bit) {
      values[p] = model.geometryParameterRange(p).upper();
    } else if (down & bit) {
      values[p] = model.geometryParameterRange(p).lower();
    } else {
      values[p] = std::numeric_limits<double>::quiet_NaN();
      free[freeCount++] = p;
    }
  }
  const std::unique_ptr<model::RobotModel> face = model.fixGeometryParameters(values);
  BoxInput in = box;
  in.rows = 1u << k;
  in.faces = GeometryFaces();
  // Signs certified over every geometry hold on the face; those certified on the face (row k's) as well.
  const std::uint64_t rowBits = ((std::uint64_t(1) << n) - 1u) << (k * n);
  in.knownSigns.positive |= out.faces.signs.positive & rowBits;
  in.knownSigns.negative |= out.faces.signs.negative & rowBits;
  ErrorBounds f;
  encloseImpl(*face, in, f, true);
  // What the face certified: more directions (on the face, hence on its sub-faces) and row k's signs there.
  bool more = false;
  for (int q = 0; q < freeCount; ++q) {
    const std::uint64_t bit = std::uint64_t(1) << free[q];
    if ((f.faces.up[k] >> q) & 1u) out.faces.up[k] |= bit, more = true;
    if ((f.faces.down[k] >> q) & 1u) out.faces.down[k] |= bit, more = true;
  }
  out.faces.signs.positive |= f.signs.positive & rowBits;
  out.faces.signs.negative |= f.signs.negative & rowBits;
  if (!(f.upper[k] < out.upper[k])) return more;
  out.upper[k] = f.upper[k];
  if (f.componentSmear.rows() == n && f.componentSmear.cols() == vars) {
    out.componentSmear.row(k) = f.componentSmear.row(k);
  } else if (f.splitScore.size() == vars) {
    out.componentSmear.row(k) = f.splitScore.transpose();
  }
  out.geometrySmear.row(k).setZero();
  out.geometrySensitivity.row(k).setZero();
  if (f.geometrySmear.rows() == n && f.geometrySmear.cols() == freeCount) {
    for (int q = 0; q < freeCount; ++q) {
      out.geometrySmear(k, free[q]) = f.geometrySmear(k, q);
      out.geometrySensitivity(k, free[q]) = f.geometrySensitivity(k, q);
    }
  }
  return more;
}

void MeanValueEnclosure::enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const {
  // (Thin boxes, e.g. errorAtPose()'s, keep the combined form, whose lower bounds hold for every tool point.)
  if (secondOrder_ && box.variables > 0 && box.hasGradient && encloseAtToolVertices(model, box, out)) return;
  encloseImpl(model, box, out, false);
}

bool MeanValueEnclosure::encloseAtToolVertices(const model::RobotModel& model, const BoxInput& box,
                                               ErrorBounds& out) const {
  // For a pose X and the other parameters g fixed, J(c) = T(R (c - c')) J(c') (RobotModel::toolPointCoordinate):
  // the rotation rows do not depend on the tool point c, the translation rows are affine in c. So f_k (k < 3), a sum
  // of magnitudes of affine functions of c, is convex in c: its maximum over the box of tool points is at a vertex,
  // and over X, g and c it is the largest of the vertices' bounds. A sign of J_kj certified at every vertex holds
  // over the whole box of c (affine), the rotation rows' signs and bounds at any one vertex hold for every c.
  constexpr int n = 6;
  const int params = model.geometryParameterCount();
  if (model.dof() != n || params == 0) return false;
  int open[3], openCount = 0, free[kMaxGeometryParameters], freeCount = 0;
  bool tool = false;
  double squares = 0.0;  // bounds sum over the open coordinates of (hi - lo)^2 >= |c - c_v|^2
  // The vertex with every tool coordinate at its lower end (NaN: the other parameters stay parameters).
  GVec lowest = GVec::Constant(params, std::numeric_limits<double>::quiet_NaN());
  for (int p = 0; p < params; ++p) {
    if (model.toolPointCoordinate(p) < 0) {
      free[freeCount++] = p;
      continue;
    }
    tool = true;
    const Interval r = model.geometryParameterRange(p);
    lowest[p] = r.lower();
    if (r.isPoint() || openCount == 3) continue;
    open[openCount++] = p;
    const double w = interval::rounding::subUp(r.upper(), r.lower());
    squares = up(squares + up(w * w));
  }
  if (!tool) return false;
  const double distance = interval::rounding::nextUp(std::sqrt(squares));  // |c - c_v| <= distance for every vertex
  const int vertices = 1 << openCount;
  constexpr unsigned kTranslation = 0x7u;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<ErrorBounds, 8> at;
  std::array<bool, 8> done{};
  for (int v = 0; v < vertices; ++v) {
    GVec values = lowest;
    for (int j = 0; j < openCount; ++j)
      if ((v >> j) & 1) values[open[j]] = model.geometryParameterRange(open[j]).upper();
    BoxInput in = box;
    in.rows = v == 0 ? box.rows : (box.rows & kTranslation);
    if (in.rows == 0) continue;
    in.faces = GeometryFaces();  // (the faces of one vertex do not hold at the others: none are handed down)
    encloseImpl(*model.fixGeometryParameters(values), in, at[v], false);
    done[v] = at[v].upper.size() == n;
  }
  if (!done[0]) return false;
  const int vars = box.variables;
  out = ErrorBounds();
  out.upper = DVec::Constant(n, kInf);
  out.lower = DVec::Zero(n);
  out.splitScore = at[0].splitScore;
  out.componentSmear = DMat::Zero(n, vars);
  out.geometrySmear = GMat::Zero(n, params);
  out.geometrySensitivity = GMat::Zero(n, params);
  bool estimates = true, search = false;
  for (int v = 0; v < vertices; ++v) {
    estimates = estimates && done[v] && at[v].centreEstimate.size() == n;
    search = search || (done[v] && at[v].searchUpper.size() == n);
  }
  if (estimates) out.centreEstimate = DVec::Constant(n, 0.0);
  if (search) out.searchUpper = DVec::Constant(n, 0.0);
  const auto searchOf = [&at](int v, int k) {
    return at[v].searchUpper.size() == n ? std::min(at[v].searchUpper[k], at[v].upper[k]) : at[v].upper[k];
  };
  for (int k = 0; k < n; ++k) {
    const std::uint64_t rowBits = ((std::uint64_t(1) << n) - 1u) << (k * n);
    int source = 0;  // the vertex whose bound is kept (its hints go with it)
    if (k < 3) {
      std::uint64_t positive = rowBits, negative = rowBits;
      double upper = -kInf, lower = -kInf;
      for (int v = 0; v < vertices; ++v) {
        if (!done[v]) {
          upper = kInf;
          positive = negative = 0;
          continue;
        }
        if (at[v].upper[k] > upper) upper = at[v].upper[k], source = v;
        lower = std::max(lower, at[v].lower[k]);
        positive &= at[v].signs.positive;
        negative &= at[v].signs.negative;
        if (estimates) out.centreEstimate[k] = std::max(out.centreEstimate[k], at[v].centreEstimate[k]);
        if (search) out.searchUpper[k] = std::max(out.searchUpper[k], searchOf(v, k));
      }
      out.upper[k] = upper;
      out.signs.positive |= positive;
      out.signs.negative |= negative;
      // f_k(c) >= f_k(c_v) - |R (c - c_v)| (f_a + f_b), a, b the other two rotation components: the column j term of
      // row k changes by (omega_j x R (c - c_v))_k, omega_j the rotation rows' column j.
      const double a = at[0].upper[3 + (k + 1) % 3], b = at[0].upper[3 + (k + 2) % 3];
      if (std::isfinite(a) && std::isfinite(b) && lower > 0.0) {
        out.lower[k] = std::max(0.0, interval::rounding::subDown(lower, up(distance * up(a + b))));
      }
      // The tool point's sensitivities (units of its half-widths; hints only): half the change between the vertices
      // at its two ends, each the largest over the other coordinates.
      for (int j = 0; j < openCount; ++j) {
        double high = 0.0, low = 0.0;
        for (int v = 0; v < vertices; ++v) {
          if (!done[v]) continue;
          const double value = estimates ? at[v].centreEstimate[k] : at[v].upper[k];
          double& side = ((v >> j) & 1) ? high : low;
          side = std::max(side, value);
        }
        if (std::isfinite(high - low)) out.geometrySensitivity(k, open[j]) = 0.5 * (high - low);
      }
    } else {
      out.upper[k] = at[0].upper[k];
      out.lower[k] = at[0].lower[k];
      out.signs.positive |= at[0].signs.positive & rowBits;
      out.signs.negative |= at[0].signs.negative & rowBits;
      if (estimates) out.centreEstimate[k] = at[0].centreEstimate[k];
      if (search) out.searchUpper[k] = searchOf(0, k);
    }
    const ErrorBounds& s = at[source];
    if (s.componentSmear.rows() == n && s.componentSmear.cols() == vars) {
      out.componentSmear.row(k) = s.componentSmear.row(k);
    } else if (s.splitScore.size() == vars) {
      out.componentSmear.row(k) = s.splitScore.transpose();
    }
    if (s.geometrySmear.rows() == n && s.geometrySmear.cols() == freeCount) {
      for (int q = 0; q < freeCount; ++q) {
        out.geometrySmear(k, free[q]) = s.geometrySmear(k, q);
        out.geometrySensitivity(k, free[q]) = s.geometrySensitivity(k, q);
      }
    }
  }
  if (vars > 0) {
    DVec score = DVec::Zero(vars);
    for (int k = 0; k < n; ++k)
      if (box.wants(k))
        for (int i = 0; i < vars; ++i) score[i] = std::max(score[i], out.componentSmear(k, i));
    if (score.maxCoeff() > 0.0) out.splitScore = score;
  }
  return true;
}

void MeanValueEnclosure::encloseImpl(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out,
                                     bool onFace) const {
  const int n = model.dof();
  const int vars = box.variables;
  out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
  out.internals.valid = false;
  out.centreEstimate.resize(0);
  out.searchUpper.resize(0);
  out.componentSmear.resize(0, 0);
  out.geometrySmear.resize(0, 0);
  out.geometrySensitivity.resize(0, 0);
  out.lower = DVec::Zero(n);
  out.splitScore = DVec::Constant(vars, 1.0);
  out.faces = GeometryFaces();
  // What a failed encloseAffine() may have left (it sets splitScore only when it succeeds): the interval paths below
  // start from scratch.
  const auto discardAffine = [&out, n]() {
    out.upper = DVec::Constant(n, std::numeric_limits<double>::infinity());
    out.centreEstimate.resize(0);
    out.searchUpper.resize(0);
    out.lower = DVec::Zero(n);
    out.componentSmear.resize(0, 0);
    out.geometrySmear.resize(0, 0);
    out.geometrySensitivity.resize(0, 0);
    out.signs = SignPattern();
  };
  // Uncertain geometry: the geometry-aware second-order form; the interval-coefficient path below only if it fails.
  // Components with certified geometry directions (box.faces) are bounded on their faces instead.
  if (secondOrder_ && model.geometryParameterCount() > 0 && model.hasGeometryUncertainty() && box.hasGradient) {
    const int params = model.geometryParameterCount();
    const bool faces = box.useFaces && !onFace;
    unsigned faceRows = 0;
    for (int k = 0; k < n; ++k)
      if (faces && box.wants(k) && box.faces.any(k)) faceRows |= 1u << k;
    out.faces = box.faces;
    bool ok = true;
    if (box.rows & ~faceRows) {
      ok = encloseAffine(model, box, box.rows & ~faceRows, out);
    } else {
      out.signs = box.knownSigns;
      out.componentSmear = DMat::Zero(n, vars);
      out.geometrySmear = GMat::Zero(n, params);
      out.geometrySensitivity = GMat::Zero(n, params);
    }
    if (ok) {
      // Each row with certified directions (inherited, or found here while its bound misses the target) goes to its
      // face, and on to the smaller faces the face certifies in turn, while the bound misses its target.
      const bool targeted = box.targets.size() == n;
      bool faced = false;
      for (int k = 0; k < n && faces; ++k) {
        if (!box.wants(k)) continue;
        const bool inherited = (faceRows >> k) & 1u;
        if (inherited) out.lower[k] = 0.0;  // a bound on the face only: nothing about the other geometries
        for (int it = 0; it < kFaceIterations && out.faces.any(k); ++it) {
          if ((it > 0 || !inherited) && targeted && out.upper[k] <= box.targets[k]) break;
          faced = true;
          if (!encloseOnFace(model, box, k, out)) break;
        }
      }
      if (faced) {
        // The bisection hint from the rows' smears, as encloseAffine() makes it.
        DVec score = DVec::Zero(vars);
        for (int k = 0; k < n; ++k) {
          if (!box.wants(k)) continue;
          for (int i = 0; i < vars; ++i) score[i] = std::max(score[i], out.componentSmear(k, i));
        }
        if (vars > 0 && score.maxCoeff() > 0.0) out.splitScore = score;
      }
      return;
    }
    out.faces = box.faces;
    // Fallback to interval coefficients: no geometry hints (empty, not zero: zero would read "nothing to split").
    discardAffine();
  }

  // Exact geometry, boxes of 3 or more variables: the same affine second-order form without geometry terms, which
  // keeps far fewer boxes (paper workspace +5%: about 2.5x fewer, docs/enclosures.md). With one variable
  // (trajectories) the form below is as tight and cheaper (trajectory_bench, 1 thread, one run: 547 boxes in
  // 28-32 ms with the affine form, 561 in 16-18 ms without; two variables are not measured). The form below also
  // when the affine one cannot be built, and when the caller needs its internals (the derivative step).
  constexpr int kAffineFromVariables = 3;
  if (secondOrder_ && !model.hasGeometryUncertainty() && box.hasGradient && !box.keepInternals &&
      vars >= kAffineFromVariables) {
    if (encloseAffine(model, box, box.rows, out)) return;
    discardAffine();
  }

  MatrixWithGradient mg;
  model.inverseJacobian(box.dualPose, mg);
  const IMat centre = model.inverseJacobian(box.centrePose);
  DMat c;
  if (!approximateInverse(midpoint(centre), c)) return;

  // A = C J^-1(centre) + sum_i (C dJ^-1/dt_i) dev_i, intersected with the naive C J^-1(box).
  const IMat a0 = multiplyMidRad(c, centre);
  IMat a = a0;
  std::array<IMat, kMaxDof> cds;
  for (int i = 0; i < vars; ++i) {
    cds[i] = multiplyMidRad(c, mg.d[i]);
    const IMat& cd = cds[i];
    const Interval dev = box.deviation[i];
    double score = 0.0;
    for (int r = 0; r < n; ++r) {
      for (int s = 0; s < n; ++s) {
        a(r, s) += cd(r, s) * dev;
        score = std::max(score, cd(r, s).mag());
      }
    }
    out.splitScore[i] = score * dev.mag();
  }
  const IMat naive = multiplyMidRad(c, mg.value);
  for (int r = 0; r < n; ++r)
    for (int s = 0; s < n; ++s) {
      const Interval both = intersect(a(r, s), naive(r, s));
      // Both contain the true range, so the intersection cannot be empty except through a bug; keep `a` then.
      if (!both.isEmpty()) a(r, s) = both;
    }

  IMat inv;
  if (!gaussInverse(a, inv, false)) return;
  const IMat jac = multiplyMidRad(inv, c);
  const std::vector<double>& e = model.sensorError();
  const IVec f = errorFromJacobian(jac, e);
  for (int k = 0; k < n; ++k) {
    out.upper[k] = f[k].upper();
    out.lower[k] = f[k].lower();
  }
  if (box.keepInternals) {
    out.internals.valid = true;
    out.internals.variables = vars;
    out.internals.c = c;
    out.internals.inverse = inv;
    out.internals.d = cds;
    out.internals.jacobian = jac;
  }
  if (!secondOrder_) return;

  // Second-order form of f_k itself. With E(t) = C J^-1(t) - I, N = (I + E)^-1 = I - E + E^2 N, and the mean-value
  // form E(t) in E0 + sum_i D_i dev_i (D_i = C dJ^-1/dt_i over the box, E0 = C J^-1(centre) - I):
  //   N(t) in (I - E0 + R) - sum_i D_i dev_i,   R in E_box^2 N_box (second order in the box size).
  // Where J_kj keeps a sign s_kj on the box, |J_kj| = s_kj J_kj, so with w_k = s_k o e and v_k = C w_k:
  //   sum_{j signed} |J_kj| e_j = (N v_k)_k  in  (I - E0 + R)_k. v_k - sum_i (D_i v_k)_k dev_i,
  // where the first-order coefficients (D_i v_k)_k cancel across j instead of adding up entry by entry.
  // Entries whose sign may change are bounded by their magnitude. Both bounds are valid; the tighter one is kept.
  DMat magE(n, n), magN(n, n);
  for (int r = 0; r < n; ++r)
    for (int q = 0; q < n; ++q) {
      magE(r, q) = (a(r, q) - Interval(r == q ? 1.0 : 0.0)).mag();
      magN(r, q) = inv(r, q).mag();
    }
  // Products of non-negative matrices: the computed value times (1 + kProductMargin) bounds the exact one in any
  // rounding mode (relative error below gamma(6) per product, Rounding.hpp); 1e-300 covers underflow. An overflow
  // (+inf, or DBL_MAX under round-down) leaves the bound unused.
  constexpr double kProductMargin = 1e-13;
  static_assert(kProductMargin >= 4.0 * interval::rounding::gamma(6), "two products and the scaling");
  const DMat remainder = ((magE * magE) * magN) * (1.0 + kProductMargin) + DMat::Constant(n, n, 1e-300);
  if (!(remainder.array() < std::numeric_limits<double>::max()).all()) return;
  DVec smear = DVec::Zero(vars);
  out.componentSmear = DMat::Zero(n, vars);
  for (int k = 0; k < n; ++k) {
    if (!box.wants(k)) continue;  // not asked for: the first-order bound above stays
    Interval rest(0.0);
    IVec v = IVec::Constant(n, Interval(0.0));
    for (int j = 0; j < n; ++j) {
      const double sign = jac(k, j).lower() > 0.0 ? 1.0 : (jac(k, j).upper() < 0.0 ? -1.0 : 0.0);
      if (sign == 0.0) {
        rest += Interval(jac(k, j).mag()) * Interval(e[j]);
        continue;
      }
      const double w = sign * e[j];  // exact
      for (int l = 0; l < n; ++l) v[l] += Interval(c(l, j)) * Interval(w);
    }
    Interval value(0.0);
    for (int l = 0; l < n; ++l) {
      const Interval nkl = Interval(k == l ? 2.0 : 0.0) - a0(k, l) + Interval(-remainder(k, l), remainder(k, l));
      value += nkl * v[l];
    }
    Interval linear[kMaxDof];
    for (int i = 0; i < vars; ++i) {
      Interval g(0.0);
      for (int l = 0; l < n; ++l) g += cds[i](k, l) * v[l];
      linear[i] = g * box.deviation[i];
      value -= linear[i];
    }
    out.upper[k] = std::min(out.upper[k], (value + rest).upper());
    out.lower[k] = std::max(out.lower[k], value.lower());
    // Bisection hint: each variable's share of the width of this bound, relative to the bound.
    if (out.upper[k] > 0.0 && std::isfinite(out.upper[k])) {
      for (int i = 0; i < vars; ++i) {
        out.componentSmear(k, i) = linear[i].mag() / out.upper[k];
        smear[i] = std::max(smear[i], out.componentSmear(k, i));
      }
    }
  }
  if (smear.maxCoeff() > 0.0) out.splitScore = smear;
}

}  // namespace enclosure
}  // namespace pkm_accuracy
