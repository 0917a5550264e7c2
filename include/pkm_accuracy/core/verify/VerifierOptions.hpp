// Options of a verification or max-error run. Units: thresholds, min widths and alpha in the units of the
// component / variable they refer to (m or rad; trajectory parameters are unitless).
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/verify/SearchTuning.hpp"

namespace pkm_accuracy {
namespace enclosure {
class ErrorEnclosure;
}
namespace verify {

enum class Mode {
  Verify,    ///< SAFE / UNSAFE / UNDECIDED against per-component thresholds
  MaxError,  ///< certified [lower, upper] of the maximal error of every component
};

/// How bounded geometric uncertainty (the model's geometry parameters) enters the search. In every mode the
/// enclosures carry it as interval coefficients plus exact first-order terms per parameter (strategy (a) of the
/// seed paper, tightened); the geometry parameters may also be bisected (strategy (b)).
enum class GeometrySplitting {
  Auto,    ///< a box whose bound stops improving under bisection switches to bisecting the geometry; default
  Never,   ///< never bisect the geometry (strategy (a) only)
  Always,  ///< the geometry parameters compete with the box variables for every split from the start
};

struct Progress;

struct VerifierOptions {
  Mode mode = Mode::Verify;
  /// Per-component thresholds (size = dof; m for positions, rad for rotations). Required (> 0) in Verify mode;
  /// optional in MaxError mode (then the verdict compares the bounds with them).
  DVec thresholds;
  /// MaxError tolerance: upper - lower <= alpha (relative: alpha * lower) for every component.
  double alpha = 0.01;
  bool alpha_relative = true;
  /// Enclosure method (enclosure::enclosureNames()).
  std::string method = "second_order";
  /// Boxes narrower than this in every variable are not split (per variable; empty: 1e-5 of the initial width).
  DVec min_width;
  /// Stop after this many boxes (0: no limit).
  std::size_t max_boxes = 0;
  /// Stop after this many seconds of wall time (0: no limit).
  double time_limit_s = 0.0;
  /// Set to true from any thread to stop promptly (the result is UNDECIDED, reason Cancelled, partial).
  const std::atomic<bool>* cancel = nullptr;
  /// Called at most every progress_period_s while the run goes on (from a worker thread; keep it short).
  std::function<void(const Progress&)> progress;
  double progress_period_s = 0.5;
  /// Worker threads (0: all hardware threads). The verdict does not depend on it.
  int threads = 0;
  /// In Verify mode: stop at the first certified witness (true) or keep classifying every box (false).
  bool stop_at_first_witness = true;
  /// At most this many undecided boxes are kept in the result (the rest are counted).
  std::size_t max_recorded_boxes = 1000;
  /// In Verify mode, at most this many of the boxes proven within every threshold for every admissible geometry are
  /// kept in the result (VerifierResult::safe_boxes, in the order they were settled; the rest are counted), e.g. to
  /// draw the proof. 0 (the default): none.
  std::size_t max_recorded_safe_boxes = 0;
  /// Points per variable of the initial sampling grid (witness search / first lower bounds); 0 disables it.
  int presample_points = 3;
  /// Derivatives of the error functions (seed paper section 4.2, monotonicity, plus the mean-value form of f_k):
  /// for boxes inside the domain that their enclosure does not decide, bound max f_k by a certified evaluation at
  /// the point where the monotone variables are at their maximising ends, plus |d f_k / d t_i| x reach for the
  /// others.
  bool monotonicity = false;
  /// Geometric uncertainty: see GeometrySplitting.
  GeometrySplitting geometry_splitting = GeometrySplitting::Auto;
  /// How the search works inside (not part of the user interfaces: benches and tests set it).
  SearchTuning tuning;
  /// Self-check of the enclosures while the search runs: for every box enclosed, a few points of the box (its centre,
  /// a vertex, random interior points; deterministic, seeded by the box), each with a point of the box's geometry
  /// ranges when the geometry is uncertain (vertices, and one interior point), are evaluated in plain double (the
  /// worst error sum_j |J_kj| e_j with J the inverse of J^-1 at that pose and geometry). A value above a component's
  /// certified upper bound, or below its certified lower bound, by more than round-off (relative 1e-9, plus 1e-14
  /// times the condition number of J^-1 there) stops the run: Verifier::run throws InternalError naming the enclosure
  /// method, the box, the point, the geometry and the values. Statistics::self_check_points counts the points. Off by
  /// default (it adds about four point evaluations per box).
  bool self_check = false;
  /// The enclosure to use instead of the registry's `method` (null: `method`), e.g. a method under test. It must be
  /// safe for concurrent const use.
  std::shared_ptr<const enclosure::ErrorEnclosure> enclosure;
};

}  // namespace verify
}  // namespace pkm_accuracy
