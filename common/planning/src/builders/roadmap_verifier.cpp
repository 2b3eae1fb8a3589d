#include "ispars/planning/builders/roadmap_verifier.hpp"

#include <algorithm>
#include <bit>
#include <optional>
#include <vector>

#include "ispars/planning/geometry/point_grid.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

// Invariant 1 at one point q seeing `seen`: how many of those POIs no sparse vertex within Delta
// with a valid segment to q sees.
class InvariantCheck {
 public:
  InvariantCheck(const Scene& scene, const Roadmap& sparse)
      : scene_(scene),
        sparse_(sparse),
        delta_(scene.config().sparse_delta),
        grid_(delta_),
        cover_(sparse.visibility_table().words()) {
    for (VertexId s = 0; s < sparse.vertex_count(); ++s) grid_.insert(s, sparse.position(s));
  }

  std::uint64_t missing(const Vec3& q, PoiBits seen) {
    if (count(seen) == 0) return 0;
    std::fill(cover_.begin(), cover_.end(), 0);
    grid_.within(q, delta_, sparse_.positions(), near_);
    for (const auto& [distance, s] : near_) {
      if (!has_outside(seen, cover_)) break;                   // already witnessed in full
      if (!has_outside(sparse_.visible(s), cover_)) continue;  // adds nothing: skip the segment
      if (distance == 0.0 || scene_.segment_valid(sparse_.position(s), q)) unite(cover_, sparse_.visible(s));
    }
    std::uint64_t out = 0;
    for (std::size_t w = 0; w < seen.size(); ++w)
      out += static_cast<std::uint64_t>(std::popcount(seen[w] & ~cover_[w]));
    return out;
  }

 private:
  const Scene& scene_;
  const Roadmap& sparse_;
  double delta_;
  PointGrid grid_;
  std::vector<std::uint64_t> cover_;
  std::vector<std::pair<double, std::uint32_t>> near_;
};

// Asks `keep_going` every 256 steps; throws VerificationStopped when it says stop.
void check_in(std::size_t step, const VerifyKeepGoing& keep_going) {
  if (keep_going && step % 256 == 0 && !keep_going()) throw VerificationStopped();
}

}  // namespace

VerificationReport verify_roadmap(const Scene& scene, const Roadmap& roadmap, const VerifyKeepGoing& keep_going) {
  VerificationReport report;
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    check_in(v, keep_going);
    report.invalid_vertices += !scene.point_valid(roadmap.position(v));
  }
  std::size_t step = 0;
  for (const RoadmapEdge& e : roadmap.edges()) {
    check_in(step++, keep_going);
    const Vec3& a = roadmap.position(e.u);
    const Vec3& b = roadmap.position(e.v);
    report.invalid_edges += !scene.segment_valid(a, b);
    report.wrong_costs += e.cost != (a - b).norm();
  }
  return report;
}

VerificationReport verify_sparse_pair(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                      std::span<const VertexId> dense_ids, const VerifyKeepGoing& keep_going) {
  VerificationReport report = verify_roadmap(scene, sparse, keep_going);
  const VerificationReport dense_report = verify_roadmap(scene, dense, keep_going);
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
  InvariantCheck check(scene, sparse);
  for (VertexId q = 0; q < dense.vertex_count(); ++q) {
    check_in(q, keep_going);
    const std::uint64_t missing = check.missing(dense.position(q), dense.visible(q));
    report.invariant_violations += missing;
    report.invariant_vertices += missing > 0;
  }
  return report;
}

namespace {

// Invariant 1 at `samples` samples, each from next() (nothing: an invalid one, skipped), into
// report's invariant counts.
template <class Next>
void check_samples(const Scene& scene, const Roadmap& sparse, std::size_t samples, const VerifyKeepGoing& keep_going,
                   Next next, VerificationReport& report) {
  InvariantCheck check(scene, sparse);
  std::vector<PoiId> visible;
  std::vector<std::uint64_t> seen(poi_words(scene.pois().size()));
  for (std::size_t i = 0; i < samples; ++i) {
    check_in(i, keep_going);
    const std::optional<Vec3> q = next();
    if (!q) continue;
    scene.visible_pois(*q, visible);
    std::fill(seen.begin(), seen.end(), 0);
    for (const PoiId p : visible) seen[p / 64] |= std::uint64_t{1} << (p % 64);
    const std::uint64_t missing = check.missing(*q, seen);
    report.invariant_violations += missing;
    report.invariant_vertices += missing > 0;
  }
}

}  // namespace

VerificationReport verify_fresh_samples(const Scene& scene, const Roadmap& sparse, std::size_t samples,
                                        std::uint64_t seed, const VerifyKeepGoing& keep_going) {
  VerificationReport report;
  scene_files::Rng rng(seed);
  check_samples(
      scene, sparse, samples, keep_going,
      [&]() -> std::optional<Vec3> { return scene.sample_valid_configuration(rng); }, report);
  report.invariant_samples = samples;
  return report;
}

VerificationReport verify_drawn_samples(const Scene& scene, const Roadmap& sparse, std::uint64_t seed,
                                        std::size_t samples, const VerifyKeepGoing& keep_going) {
  VerificationReport report;
  scene_files::Rng stream(seed);
  check_samples(
      scene, sparse, samples, keep_going,
      [&]() -> std::optional<Vec3> {
        const Vec3 q = stream.uniform_in(scene.config().bounds);
        if (!scene.point_valid(q)) return std::nullopt;
        return q;
      },
      report);
  report.invariant_drawn = samples;
  return report;
}

}  // namespace ispars::planning
