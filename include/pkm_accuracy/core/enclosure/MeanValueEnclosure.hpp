// Methods "mean_value" and "second_order" (the default): the mean-value form of the *preconditioned* matrix,
//   C = J^-1(centre)^-1 (double),
//   C J^-1(t) in C J^-1(centre) + sum_i [C dJ^-1/dt_i](box) (t_i - centre_i), intersected with C [J^-1](box);
//   N = (C J^-1)^-1 by interval Gauss elimination (A is close to I), J = N C, f_k = sum_j |J_kj| e_j.
// The derivative enclosures come from forward-mode differentiation over the box (Dual<Interval>). The per-variable
// terms |C dJ^-1/dt_i| rad(t_i) are returned as bisection hints (the "smear" of the preconditioned matrix).
//
// Contract: enclose() fills out.upper (certified upper bounds of f_k over the box and every admissible geometry, +inf
// where it cannot bound one), out.lower (certified lower bounds of min f_k, 0 where none) and the hints of
// ErrorBounds; never throws on singular boxes. Derivations: docs/enclosures.md, docs/uncertainty.md.
//
// With Bound::SecondOrderColumns ("second_order"), a second bound of f_k is computed from the identity
// N = I - E + E^2 N (E = C J^-1 - I): its first-order part keeps the cancellations between the terms of
// sum_j |J_kj| e_j, its remainder is quadratic in the box size (see the .cpp); the tighter bound is returned. With
// uncertain geometry parameters, and for an exact geometry on boxes of 3 or more variables (without
// BoxInput::keepInternals), the affine forms of N V of PreconditionedInverseEnclosure are used instead (with the
// geometry parameters as first-order terms, resp. without them; docs/enclosures.md). With BoxInput::decomposeGeometry
// (SearchTuning::decompose_geometry) on workspace boxes, the geometry enters instead as a separate bound of the
// error's increase over the nominal geometry (GeometryIncrement), added to each column of the nominal form. With
// uncertain geometry, a component whose monotonicity in some parameters was certified on a containing box
// (BoxInput::faces) is bounded on that face of the geometry box, with those parameters fixed at their raising ends
// (docs/uncertainty.md, "Faces").
// With an uncertain tool point (second_order, boxes of at least one variable), each component is bounded at the
// vertices of the tool point's box, where the rest of the geometry keeps its uncertainty: the rotation components do
// not depend on the tool point and the translation components are convex in it (RobotModel::toolPointCoordinate).
// The second-order forms work in a MeanValueWorkspace (one per thread).
#pragma once

#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace enclosure {

struct MeanValueWorkspace;

class MeanValueEnclosure final : public ErrorEnclosure {
 public:
  /// What f_k is bounded from (the registry names in quotes).
  enum class Bound {
    /// "mean_value": sum_j |J_kj| e_j from an interval enclosure of every entry of J (mean-value form of C J^-1,
    /// interval Gauss elimination).
    JacobianEntries,
    /// "second_order": also (and the tighter bound kept) f_k as a whole, from the second-order forms of its columns
    /// N C w (and the geometry's first-order terms), which keep the cancellations between the legs.
    SecondOrderColumns,
  };
  explicit MeanValueEnclosure(Bound bound) : secondOrder_(bound == Bound::SecondOrderColumns) {}
  std::string name() const override { return secondOrder_ ? "second_order" : "mean_value"; }
  bool needsGradient() const override { return true; }
  /// encloseWith() the calling thread's workspace (MeanValueWorkspace::ofThisThread()).
  void enclose(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out) const override;
  /// enclose() with the scratch of the second-order forms in `workspace` (one per thread, reused box after box).
  void encloseWith(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out,
                   MeanValueWorkspace& workspace) const;

 private:
  /// The geometry the model's box is: the whole geometry box, or a face of it (encloseOnFace(): a model with the
  /// certified parameters fixed, whose bound is not taken to faces again).
  enum class Geometry { WholeBox, Face };
  /// enclose() at one tool point (or without one among the parameters).
  void encloseImpl(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out, Geometry geometry,
                   MeanValueWorkspace& ws) const;
  /// Uncertain geometry: the second-order forms with geometry terms, then each row with certified directions on its
  /// faces. @return false if the forms cannot be built (out then holds what the interval path starts from).
  bool encloseWithGeometryForms(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out,
                                Geometry geometry, MeanValueWorkspace& ws) const;
  /// The rows with certified directions (faceRows: inherited from box.faces; and those found by the forms) bounded
  /// on their faces, on the smaller faces these certify in turn, while a row's bound misses its target.
  void encloseRowsOnFaces(const model::RobotModel& model, const BoxInput& box, unsigned faceRows, ErrorBounds& out,
                          MeanValueWorkspace& ws) const;
  /// Component k on the face out.faces gives it: out.upper[k] and its hints if tighter, and the directions and signs
  /// the face certifies added to out.faces. @return true if it certified more directions.
  bool encloseOnFace(const model::RobotModel& model, const BoxInput& box, int k, ErrorBounds& out,
                     MeanValueWorkspace& ws) const;
  /// With a tool point among the geometry parameters (model::RobotModel::toolPointCoordinate): the bounds at every
  /// vertex of the tool point's box, each with a model in which the tool point is exact, combined by convexity
  /// (docs/uncertainty.md, "The tool point"). @return false if the model has no tool-point parameter (nothing done).
  bool encloseAtToolVertices(const model::RobotModel& model, const BoxInput& box, ErrorBounds& out,
                             MeanValueWorkspace& ws) const;
  bool secondOrder_;
};

}  // namespace enclosure
}  // namespace pkm_accuracy
