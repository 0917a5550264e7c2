// Grid sampling before the search (VerifierOptions::presample_points per varying variable, at most 1e5 points):
// double-precision screening of every grid point, then certified evaluations (PointEvaluator) of the promising ones:
// quick witnesses (e.g. singular corners) and first lower bounds. Runs before the workers start. Internal to the core.
#pragma once

#include <vector>

#include "PointEvaluator.hpp"
#include "SearchContext.hpp"
#include "SearchState.hpp"

namespace pkm_accuracy {
namespace verify {

class Presampler {
 public:
  Presampler(const SearchContext& context, SearchState& state, const PointEvaluator& points)
      : c_(context), state_(state), points_(points) {}

  /// Samples the grid; may record a witness, sensitive poses and lower bounds, and request a stop.
  void presample() const;

 private:
  /// Grid point `index` over the varying variables `vars` (g points each; the others at the centre).
  DVec gridPoint(std::size_t index, const std::vector<int>& vars, int g) const;
  /// Screens the `total` grid points in double: verify mode certifies each point where some component exceeds its
  /// threshold; the others give each component's largest value (`best`, at `bestPoint`; -1: none). Returns false if
  /// a witness ends the search.
  bool screen(std::size_t total, const std::vector<int>& vars, int g, std::vector<double>& best,
              std::vector<DVec>& bestPoint) const;
  /// Certifies each component's best grid point (each point once). Returns false if a witness ends the search.
  bool certifyBest(const std::vector<double>& best, const std::vector<DVec>& bestPoint) const;

  const SearchContext& c_;
  SearchState& state_;
  const PointEvaluator& points_;
};

}  // namespace verify
}  // namespace pkm_accuracy
