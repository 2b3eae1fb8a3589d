#pragma once
// Exact checks of a built roadmap: what SPARS and the paper promise, counted, never assumed.

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// Violation counts; all zero is a clean roadmap.
struct VerificationReport {
  std::uint64_t invalid_vertices = 0;  ///< Vertices failing the point check.
  std::uint64_t invalid_edges = 0;     ///< Edges whose swept segment is not valid.
  std::uint64_t wrong_costs = 0;       ///< Edges whose cost is not |u - v| (0: costs come from positions).
  std::uint64_t sparse_not_dense = 0;  ///< Sparse vertices that are not their dense vertex.
  /// Invariant 1: pairs (dense q, POI p in chi(q)) with no sparse q' seeing p, |q - q'| <= Delta
  /// and a valid segment q-q'.
  std::uint64_t invariant_violations = 0;
  std::uint64_t invariant_vertices = 0;  ///< Dense vertices with at least one such POI.
  /// Fresh samples Invariant 1 was checked on instead of dense vertices (a roadmap without a
  /// dense graph: verify_fresh_samples); 0 when it was checked on the dense graph.
  std::uint64_t invariant_samples = 0;
  /// Samples of the build's own stream Invariant 1 was checked on, drawn again (a roadmap without
  /// a dense graph: verify_drawn_samples); 0 otherwise.
  std::uint64_t invariant_drawn = 0;

  [[nodiscard]] bool geometry_ok() const {
    return invalid_vertices == 0 && invalid_edges == 0 && wrong_costs == 0 && sparse_not_dense == 0;
  }
};

/// Asked between small steps of a verification (every 256 vertices, edges or samples, a few
/// milliseconds at most); false stops it with VerificationStopped.
using VerifyKeepGoing = std::function<bool()>;

/// Thrown when a verification's keep_going said stop.
struct VerificationStopped : std::runtime_error {
  VerificationStopped() : std::runtime_error("verification stopped") {}
};

/// Every vertex valid, every edge valid with cost = length.
[[nodiscard]] VerificationReport verify_roadmap(const Scene& scene, const Roadmap& roadmap,
                                                const VerifyKeepGoing& keep_going = {});

/// verify_roadmap on both graphs, plus: sparse vertex i is dense vertex dense_ids[i], and the
/// local inspection-coverage invariant over every dense vertex.
[[nodiscard]] VerificationReport verify_sparse_pair(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                                    std::span<const VertexId> dense_ids,
                                                    const VerifyKeepGoing& keep_going = {});

/// Invariant 1 on `samples` fresh valid samples q drawn from `seed` (independent of the build's
/// stream): the pairs (q, POI p in chi(q)) with no sparse vertex within Delta in view of q that
/// sees p, in invariant_violations, and the samples with one in invariant_vertices. The build
/// admits every sample it draws that would violate it; a fresh sample may, with a probability
/// these counts estimate.
[[nodiscard]] VerificationReport verify_fresh_samples(const Scene& scene, const Roadmap& sparse, std::size_t samples,
                                                      std::uint64_t seed, const VerifyKeepGoing& keep_going = {});

/// Invariant 1, exactly, on the samples a build from `seed` drew: its stream's first `samples`
/// draws again (three uniforms each, as the builders draw them), the valid ones checked as
/// verify_sparse_pair checks dense vertices (they are the dense vertices ispars would hold).
/// What Claim 1 promises for ispars2, also after an inspection task.
[[nodiscard]] VerificationReport verify_drawn_samples(const Scene& scene, const Roadmap& sparse, std::uint64_t seed,
                                                      std::size_t samples, const VerifyKeepGoing& keep_going = {});

}  // namespace ispars::planning
