// Internal knobs of the branch-and-bound search: the bisection rule, when a stalled search path changes strategy,
// the search-order shortcut for hopeless halves, the geometry form and the centre checks. They change how fast the
// search decides, never what it may certify; the user interfaces (pkm_verify, the node's services) do not expose
// them. Benches and tests set them through VerifierOptions::tuning.
#pragma once

namespace pkm_accuracy {
namespace verify {

/// How the branch-and-bound chooses the variable to bisect.
enum class Bisection {
  Smear,               ///< largest contribution to the enclosure's width (|C dJ^-1/dt_i| rad(t_i)); default
  LargestScaledWidth,  ///< largest width relative to the initial width
  RoundRobin,          ///< cycle through the variables by depth (the seed paper's baseline)
};

struct SearchTuning {
  /// The variable to bisect.
  Bisection bisection = Bisection::Smear;
  /// Auto: a box "keeps splitting without progress" after this many bisection levels without halving its bound's
  /// excess over the target (0: half the number of box variables, at least 2). (A 10% reduction is not counted as
  /// progress: the decomposed geometry form's bound creeps down by that much per few levels towards its floor at
  /// single poses, so its paths would reach the faces too late and too small; docs/design-notes.md.)
  int stall_levels = 0;
  /// Geometric uncertainty: a stalled search path (or a box at the precision limit) first bounds each component on
  /// the face of the geometry box where it is certified monotone (enclosure::BoxInput::useFaces), before any
  /// geometry bisection; false skips that step (strategy (a), then (b)).
  bool faces = true;
  /// Split a box's two halves again at once, without enclosing them, when the box's own enclosure predicts that
  /// neither can be decided: some component's bound, minus the whole share of the split variable in it (the smear
  /// hints), is still above 1.1 times its target (threshold; in max-error mode the lower bound plus the tolerance).
  /// Only the search order changes (Statistics::unenclosed_boxes counts them); paper workspace, 1.05 x the maxima:
  /// 10-15% fewer boxes (bench/RESULTS.md). Only on domains of at least 3 variables (not on trajectories or
  /// 2-parameter varieties). False encloses every box.
  bool skip_hopeless = true;
  /// Geometric uncertainty, second_order method, workspace boxes: bound the nominal error and its increase over the
  /// geometry separately (enclosure::GeometryIncrement, the "decomposed" form, the default) on every search path,
  /// geometry halves included (about their own centre), and use one expansion around the pose and the geometry
  /// together (the "combined" form) on the paths that work on their faces; false: the combined form everywhere. Both
  /// are rigorous. The decomposed form gives no monotone geometry directions (the combined one certifies them where the
  /// faces need them) and needs the model's affine geometry derivatives (anchors, not the tool point: else the combined
  /// form runs). Paper workspace, 5% margins: fewer boxes and faster than the combined form (docs/uncertainty.md);
  /// margins below the first-order floor at single poses still get the faces.
  bool decompose_geometry = true;
  /// Certified evaluation at the centre of every box being split at depth multiple of this (>= 1).
  int centre_check_period = 2;
};

}  // namespace verify
}  // namespace pkm_accuracy
