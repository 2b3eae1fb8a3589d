#include "ispars/builders/roadmap_verifier.hpp"

#include <algorithm>
#include <bit>
#include <vector>

#include "ispars/geometry/point_grid.hpp"

namespace ispars {

VerificationReport verify_roadmap(const Scene& scene, const Roadmap& roadmap) {
  VerificationReport report;
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    report.invalid_vertices += !scene.point_valid(roadmap.position(v));
  }
  for (const RoadmapEdge& e : roadmap.edges()) {
    const Vec3& a = roadmap.position(e.u);
    const Vec3& b = roadmap.position(e.v);
    report.invalid_edges += !scene.segment_valid(a, b);
    report.wrong_costs += e.cost != (a - b).norm();
  }
  return report;
}

VerificationReport verify_sparse_pair(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                      std::span<const VertexId> dense_ids) {
  VerificationReport report = verify_roadmap(scene, sparse);
  const VerificationReport dense_report = verify_roadmap(scene, dense);
  report.invalid_vertices += dense_report.invalid_vertices;
  report.invalid_edges += dense_report.invalid_edges;
  report.wrong_costs += dense_report.wrong_costs;

  for (VertexId s = 0; s < sparse.vertex_count(); ++s) {
    const bool same = s < dense_ids.size() && dense_ids[s] < dense.vertex_count() &&
                      dense.position(dense_ids[s]) == sparse.position(s) &&
                      std::ranges::equal(dense.visible(dense_ids[s]), sparse.visible(s));
    report.sparse_not_dense += !same;
  }

  // Invariant 1, exactly: for each dense q, the POIs of chi(q) that no sparse vertex within
  // Delta with a valid segment to q sees.
  const double delta = scene.config().sparse_delta;
  PointGrid grid(delta);
  for (VertexId s = 0; s < sparse.vertex_count(); ++s) grid.insert(s, sparse.position(s));
  std::vector<std::pair<double, std::uint32_t>> near;
  std::vector<std::uint64_t> cover(dense.visibility_table().words());
  for (VertexId q = 0; q < dense.vertex_count(); ++q) {
    const PoiBits seen = dense.visible(q);
    if (count(seen) == 0) continue;
    std::fill(cover.begin(), cover.end(), 0);
    grid.within(dense.position(q), delta, sparse.positions(), near);
    for (const auto& [distance, s] : near) {
      if (!has_outside(seen, cover)) break;  // already witnessed in full
      if (!has_outside(sparse.visible(s), cover)) continue;  // adds nothing: skip the segment
      if (distance == 0.0 || scene.segment_valid(sparse.position(s), dense.position(q))) {
        unite(cover, sparse.visible(s));
      }
    }
    std::uint64_t missing = 0;
    for (std::size_t w = 0; w < seen.size(); ++w) {
      missing += static_cast<std::uint64_t>(std::popcount(seen[w] & ~cover[w]));
    }
    report.invariant_violations += missing;
    report.invariant_vertices += missing > 0;
  }
  return report;
}

}  // namespace ispars
