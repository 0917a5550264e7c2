// Outcome of a verification or max-error run, and the progress snapshots sent while it runs.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"

namespace pkm_accuracy {
namespace verify {

enum class Verdict { Safe, Unsafe, Undecided };
/// UncertaintySensitive: a certified pose where some admissible geometry exceeds a threshold and none was found that
/// exceeds it for every geometry (so SAFE is impossible, UNSAFE not proven): see VerifierResult::sensitive.
enum class UndecidedReason {
  None,
  PrecisionLimit,
  BoxBudget,
  TimeBudget,
  Cancelled,
  NoThresholds,
  UncertaintySensitive
};

std::string toString(Verdict v);          ///< "SAFE", "UNSAFE", "UNDECIDED"
std::string toString(UndecidedReason r);  ///< "none", "precision_limit", "box_budget", "time_budget", ...

struct Statistics {
  std::size_t boxes = 0;  ///< boxes processed (enclosures computed)
  int max_depth = 0;      ///< deepest bisection level reached
  double seconds = 0.0;   ///< wall time
  /// Fractions of the initial box volume (over variables of non-zero width) proven safe, proven unsafe (every
  /// point exceeds a threshold), left undecided, and outside the region.
  double safe_fraction = 0.0;
  double unsafe_fraction = 0.0;
  double undecided_fraction = 0.0;
  double outside_fraction = 0.0;
  int threads = 1;
  std::size_t monotonicity_hits = 0;  ///< component bounds tightened by the derivative (monotonicity) step
  /// Geometric uncertainty: boxes that switched from interval coefficients to bisecting the geometry (strategy (a)
  /// to (b); one per search path), and all bisections of a geometry parameter.
  std::size_t geometry_switches = 0;
  std::size_t geometry_splits = 0;
  /// Geometric uncertainty: search paths that switched to bounding their components on the faces of the geometry
  /// box where monotonicity is certified (a stalled path, or a box at the precision limit; before any geometry
  /// bisection), and the boxes enclosed that way.
  std::size_t face_switches = 0;
  std::size_t face_boxes = 0;
  /// Boxes split without being enclosed, because the enclosure of the box they came from predicted that they could
  /// not be decided (SearchTuning::skip_hopeless; not counted in `boxes`).
  std::size_t unenclosed_boxes = 0;
  /// Points evaluated by the self-check (VerifierOptions::self_check; 0 without it), every one within its box's bounds.
  std::size_t self_check_points = 0;
};

struct Progress {
  Statistics stats;
  DVec lower;  ///< MaxError: current certified lower bounds
  DVec upper;  ///< MaxError: current upper bound over the boxes closed so far
};

/// A box of the search that could not be decided, with the upper bounds the enclosure gave on it.
struct BoxRecord {
  IVec box;    ///< in the domain's variables
  DVec upper;  ///< per component (+inf if unbounded)
  /// Ranges of the geometry parameters the box was searched with (after bisecting the geometry, strategy (b));
  /// empty: every admissible geometry.
  std::vector<Interval> geometry;
};

/// A certified pose where the answer depends on the geometric uncertainty: component `component` exceeds its
/// threshold for the admissible geometry `failing_geometry` (certified: error >= failing_lower), while no certified
/// bound shows it exceeding for every geometry. If `passing_geometry` is not empty, that admissible geometry keeps
/// the component below its threshold there (certified: error <= passing_upper); `passes_all` says whether it keeps
/// every component below its threshold.
struct SensitivePose {
  DVec point;   ///< in the domain's variables
  IVec pose;    ///< enclosure of the pose (x, y, z, roll, pitch, yaw)
  IVec region;  ///< the search box it was found in (the pose region concerned)
  int component = -1;
  std::vector<double> failing_geometry;  ///< one value per geometry parameter (model::geometryParameterName)
  double failing_lower = 0.0;
  std::vector<double> passing_geometry;
  double passing_upper = 0.0;
  bool passes_all = false;
};

struct VerifierResult {
  Verdict verdict = Verdict::Undecided;
  UndecidedReason reason = UndecidedReason::None;
  std::string message;  ///< one human sentence

  // Verify mode, UNSAFE: a certified witness.
  DVec witness;       ///< the witness in the domain's variables (for a workspace: the pose)
  IVec witness_pose;  ///< enclosure of the witness pose (x, y, z, roll, pitch, yaw)
  int witness_component = -1;
  double witness_lower_bound = 0.0;  ///< certified: worst error of that component at the witness >= this
  DVec witness_error_lower;          ///< certified lower bounds of every component at the witness

  /// A certified singularity (either mode): det J^-1 has certified opposite signs, for every admissible geometry, at
  /// the two points singular_from and singular_to of the domain (in its variables), and the domain contains the
  /// segment between them (a box of the search inside the domain). So for every admissible geometry J^-1 is singular
  /// at some pose of the domain on that path, and the worst error is unbounded near it: ||J|| grows without bound
  /// there and every sensor bound e_j is > 0, so some component exceeds any threshold at poses of the domain. Verify
  /// mode: UNSAFE (with a certified witness pose too when one was found near the singularity; for very large thresholds
  /// none may be representable); max-error mode: max_upper is +inf and the run stops. In max-error mode with uncertain
  /// geometry, where the signs hold for the nominal geometry only, singular_geometry holds it (one value per parameter;
  /// the maximum over the geometries is unbounded all the same); empty: every admissible geometry.
  bool singular = false;
  DVec singular_from, singular_to;            ///< in the domain's variables
  IVec singular_pose_from, singular_pose_to;  ///< enclosures of their poses (x, y, z, roll, pitch, yaw)
  std::vector<double> singular_geometry;

  // MaxError mode (also filled where known in Verify mode): certified bounds of max f_k over the domain.
  DVec max_lower;                ///< attained: f_k(max_argmax[k]) >= max_lower[k]
  DVec max_upper;                ///< max over the domain of f_k <= max_upper[k] (+inf if unbounded)
  std::vector<DVec> max_argmax;  ///< per component: the variables of a point attaining max_lower
  /// Per component: enclosure of the pose at max_argmax (x, y, z, roll, pitch, yaw, as the model sees it: in the base
  /// frame for a domain given in another frame, like witness_pose); empty where max_argmax is.
  std::vector<IVec> max_argmax_pose;
  /// With uncertain geometry, per component: the geometry (one value per parameter) attaining max_lower at
  /// max_argmax (empty when the bound holds for every geometry). Its values, like every geometry a result reports,
  /// are admissible as the geometry was given (model::RobotModel::geometryParameterAdmissible: nominal +- half-width,
  /// not the model's outward-rounded ranges).
  std::vector<std::vector<double>> max_argmax_geometry;
  bool converged = false;  ///< MaxError: upper - lower <= alpha for every component

  /// Verify mode with uncertain geometry: the first certified uncertainty-sensitive poses (at most
  /// options.max_recorded_boxes) and how many were found.
  std::vector<SensitivePose> sensitive;
  std::size_t sensitive_count = 0;

  std::vector<BoxRecord> undecided_boxes;  ///< at most options.max_recorded_boxes
  std::size_t undecided_box_count = 0;     ///< all of them
  /// Verify mode: boxes proven within every threshold for every admissible geometry (their `geometry` empty), at
  /// most options.max_recorded_safe_boxes, and how many there were (counted only when some are recorded). `upper`
  /// holds the bounds computed on the box itself; a component already proven on a box containing it is not enclosed
  /// again and has a valid but possibly looser bound there (even above its threshold; +inf where none was computed).
  std::vector<BoxRecord> safe_boxes;
  std::size_t safe_box_count = 0;
  Statistics stats;
};

}  // namespace verify
}  // namespace pkm_accuracy
