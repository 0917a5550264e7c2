// Per-box enclosure of the worst positioning error ("algorithm A" of the seed paper).
//
// For pose component k, f_k(X) = sum_j |J_kj(X)| e_j is the worst error at pose X when every leg sensor error is
// bounded by e_j (J = (J^-1)^-1). A method returns, for a box of poses, a certified upper bound of max f_k over the
// box and every admissible geometry (+inf when it cannot bound it, e.g. a singular pose may lie in the box).
// Certified lower bounds come from errorAtPose() at single poses. The methods and their derivations:
// docs/enclosures.md.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/model/RobotModel.hpp"

namespace pkm_accuracy {
namespace enclosure {

/// Entries of J = (J^-1)^-1 (n x n, row-major bit k * n + j) whose sign is certified over a box (and every admissible
/// geometry). A sub-box inherits them, so a search can hand its boxes' signs down to their children.
struct SignPattern {
  std::uint64_t positive = 0, negative = 0;
  bool known(int bit) const { return ((positive | negative) >> bit) & 1u; }
  double sign(int bit) const { return (positive >> bit) & 1u ? 1.0 : ((negative >> bit) & 1u ? -1.0 : 0.0); }
};

/// Monotonicity of each f_k in the geometry parameters, certified over a box and (the face of) the geometry box:
/// bit p of up[k] (down[k]) says that f_k is non-decreasing (non-increasing) in g_p over the box and over the face of
/// the geometry box given by the other bits of row k. So max over the geometry box of f_k (on the box, and on every
/// sub-box) is its max over the face with each such g_p at its raising end: a sub-box may bound f_k on that face
/// only, with a model whose uncertainty is the face's (fewer parameters, re-centred: tighter and cheaper). The
/// face signs are the signs of J_kj certified over the box and that face (row k's entries for row k), which hold on
/// the face only. Bits refer to the parameter numbering of the model the box is enclosed with; a search that
/// bisects the geometry must drop them (a raising end of the whole range is not one of the half range).
struct GeometryFaces {
  std::array<std::uint64_t, kMaxDof> up{}, down{};
  SignPattern signs;
  bool any(int k) const { return (up[k] | down[k]) != 0; }
};

/// A box of the search, seen as poses. Built by the domain (workspace: the identity map; trajectory: the pose
/// map of the parameters).
struct BoxInput {
  int variables = 0;           ///< number of box variables (<= kMaxDof)
  IVec pose;                   ///< enclosure of every pose of the box
  DualPose dualPose;           ///< the pose over the box with its gradient with respect to the box variables
  IVec centrePose;             ///< enclosure of the pose at the box centre (degenerate for workspace boxes)
  IVec deviation;              ///< per box variable i: t_i - centre_i over the box
  bool hasGradient = false;    ///< dualPose is filled
  bool keepInternals = false;  ///< ask the method to fill ErrorBounds::internals (for errorGradient)
  /// Signs of J already certified on a box containing this one (e.g. its parent); methods may skip recomputing them.
  SignPattern knownSigns;
  /// Monotonicity in the geometry certified on a box containing this one (GeometryFaces). Empty by default.
  GeometryFaces faces;
  /// Bound the components on their faces (those in `faces` and those certified on this box, in turn on the smaller
  /// faces these give), and certify directions with the mean-value form in the pose too: tighter (to the nominal
  /// enclosure at one geometry vertex once every direction is certified) but several enclosures per component, so
  /// for the boxes where the plain bound stalls. Off: `faces` is only passed on (the directions found added).
  bool useFaces = false;
  /// With uncertain geometry on workspace boxes: bound the nominal error and its increase over the geometry
  /// separately (GeometryIncrement, the "decomposed" form) instead of expanding around the pose and the geometry at
  /// once (the "combined" form of PreconditionedInverseEnclosure with the geometry). Both are rigorous.
  bool decomposeGeometry = false;
  /// The components the caller needs (bit k: component k). Methods may skip the others: their upper bounds are then
  /// +inf or looser than they could be (still valid), their lower bounds 0, their hints 0.
  unsigned rows = ~0u;
  /// Component k is in `rows`.
  bool wants(int k) const { return ((rows >> k) & 1u) != 0; }
  /// The box variables are the n pose coordinates themselves (pose_i = t_i, as for workspace boxes; dualPose filled).
  bool variablesArePose(int n) const;
  /// Optional (empty: none), per component: a bound at or below targets[k] is good enough for the caller, so
  /// methods may skip refinements that could only lower it further.
  DVec targets;
};

/// Intermediate enclosures of the preconditioned methods, kept so that derivative information (monotonicity) can
/// be computed on demand for the boxes that need it.
struct EnclosureInternals {
  bool valid = false;
  int variables = 0;
  DMat c;                       ///< the preconditioner (point)
  IMat inverse;                 ///< N = (C J^-1)^-1 over the box
  std::array<IMat, kMaxDof> d;  ///< C dJ^-1/dt_i over the box
  IMat jacobian;                ///< J = N C over the box
};

struct ErrorBounds {
  DVec upper;       ///< per component: certified upper bound of f_k over the box (+inf if unbounded)
  DVec lower;       ///< per component: certified lower bound of min f_k over the box (0 if not computed)
  DVec splitScore;  ///< per box variable: estimated share of the overestimation (bisection hint); may be empty
  /// Per component k and box variable i: share of the width of component k's bound due to variable i (relative
  /// to the bound), so that a search can split for the components it still needs; may be empty.
  DMat componentSmear;
  /// Geometry parameters (model::RobotModel::geometryParameterCount() > 0; second-order method only, else empty):
  /// per component k and parameter p, the share of the width of component k's bound due to p (relative to the
  /// bound), and the estimated derivative d f_k / d g_p at the box (its sign says which end of the range of p
  /// raises the error).
  GMat geometrySmear;
  GMat geometrySensitivity;
  /// Per component: an estimate, NOT certified, of the largest f_k over every admissible geometry at the box centre
  /// (the affine form's value there plus its first-order geometry terms G, plus G^2 / value for the second-order
  /// ones; second-order method, affine form only, else empty; +inf for components without one). For search
  /// heuristics only: the verifier skips the certified centre evaluation of a box whose estimates are clearly below
  /// the thresholds.
  DVec centreEstimate;
  /// Per component: NOT certified, the bound the search's heuristics use (Verifier: hopeless halves, split weights,
  /// progress) where it differs from `upper`: for a component some of whose columns had their geometry increase bounded
  /// only coarsely (the box is split whatever it is, MeanValueEnclosure), the bound without that increase. Empty:
  /// `upper`.
  DVec searchUpper;
  /// Every upper bound finite (of the components in `rows`, bit k: component k; see BoxInput::rows).
  bool bounded(unsigned rows = ~0u) const {
    if (upper.size() == 0) return false;
    for (int k = 0; k < upper.size(); ++k)
      if (((rows >> k) & 1u) && !std::isfinite(upper[k])) return false;
    return true;
  }
  EnclosureInternals internals;  ///< filled by the mean-value methods when BoxInput::keepInternals is set
  SignPattern signs;             ///< signs of J certified over the box (second-order method with geometry; else 0)
  /// The input's faces with what this box certified added (second-order method with geometry; else empty). Lower
  /// bounds of components bounded on a face are 0 (a face bound says nothing about the other geometries).
  GeometryFaces faces;
};

/// Enclosure of the gradient of f_k with respect to the box variables over the box, from the internals of a
/// mean-value enclosure: d f_k / d t_i = -(row k of N) (C dJ^-1/dt_i) (N C w_k), w_kj = sign(J_kj) e_j.
/// @return false if the internals are missing or some J_kj may change sign on the box (f_k not differentiable).
bool errorGradient(const ErrorBounds& bounds, const std::vector<double>& sensorError, int k, IVec& gradient);

class ErrorEnclosure {
 public:
  virtual ~ErrorEnclosure() = default;
  /// Registry name ("second_order", "mean_value", "precond", "paper_baseline").
  virtual std::string name() const = 0;
  /// True if enclose() reads BoxInput::dualPose.
  virtual bool needsGradient() const = 0;
  /// Fills out.upper (size model.dof()) and possibly out.splitScore. Never throws on singular boxes.
  virtual void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const = 0;
};

/// Names accepted by makeEnclosure(), the default first.
std::vector<std::string> enclosureNames();
/// @throws InvalidArgument naming the accepted methods if `name` is unknown.
std::unique_ptr<ErrorEnclosure> makeEnclosure(const std::string& name);

/// f = sum_j |J_kj| e_j as intervals, from an enclosure of J.
IVec errorFromJacobian(const IMat& jacobian, const std::vector<double>& sensorError);

/// Certified enclosure of f_k at the poses of a (thin) pose box, by preconditioned interval Gauss elimination.
/// lower() of each entry is a certified lower bound of the worst error at that pose (for every admissible
/// geometry). With uncertain geometry parameters the second-order form tightens both ends, and `sensitivity` (if
/// given) receives its estimate of d f_k / d g_p there (empty otherwise). `rows` (bit k: component k) asks for
/// some components only (see BoxInput::rows): the others may come back as [0, +inf]. @return false if J^-1 could
/// not be inverted there (singular or nearly so).
bool errorAtPose(const model::RobotModel& model, const IVec& pose, IVec& f, GMat* sensitivity = nullptr,
                 unsigned rows = ~0u);

/// The same in double at a nominal pose (not certified; +inf if singular).
DVec errorAtPoseDouble(const model::RobotModel& model, const DVec& pose);

}  // namespace enclosure
}  // namespace pkm_accuracy
