// A search domain: an m-dimensional box of variables t (m <= kMaxDof) with a map t -> pose and a membership test.
// The poses have poseDimension() coordinates, those of the robot model the domain is verified for (its dof, in the
// order of its description). Workspaces use the identity map on the pose coordinates (possibly restricted to a
// position region); trajectories and motion varieties map t in [0,1]^m to poses.
#pragma once

#include <string>

#include "pkm_accuracy/core/Types.hpp"
#include "pkm_accuracy/core/enclosure/ErrorEnclosure.hpp"

namespace pkm_accuracy {
namespace domain {

/// Result of testing a box of the domain against the region of interest (seed paper section 2.2).
enum class Containment { Inside, Outside, Partial };

class Domain {
 public:
  virtual ~Domain() = default;
  /// Number of box variables m.
  virtual int variables() const = 0;
  /// Number of pose coordinates n of the poses the domain maps to (the model's dof; 1 .. kMaxDof).
  virtual int poseDimension() const = 0;
  /// Name and unit of variable i (for reports).
  virtual std::string variableName(int i) const = 0;
  /// The initial box of variables.
  virtual const IVec& initialBox() const = 0;
  /// Fills the pose view of a box of variables (enclosures of the poses, their gradient when `gradient` is set,
  /// the pose at the box centre and the deviations from the centre): pose and centrePose have poseDimension()
  /// entries, the entries of dualPose beyond them are 0.
  virtual void poseView(const IVec& box, bool gradient, enclosure::BoxInput& out) const = 0;
  /// Whether every / no / some point of the box belongs to the domain (certified; Partial when unsure).
  virtual Containment classify(const IVec& box) const = 0;
  /// Enclosure of the pose at a point of the variables (poseDimension() entries).
  virtual IVec poseAt(const DVec& t) const = 0;
};

/// The centre of a box (exactly representable: the midpoint of each interval).
DVec centreOf(const IVec& box);

/// The pose view of a box for domains whose variables are the pose coordinates themselves (identity map):
/// the poses are the box, the centre pose its (exact) centre, the gradient the identity.
void identityPoseView(const IVec& box, bool gradient, enclosure::BoxInput& out);

}  // namespace domain
}  // namespace pkm_accuracy
