#pragma once
// SPARS (Dobson & Bekris 2014) and Inspection-SPARS (Alg. 1 of the paper): a sparse roadmap
// G_s grown beside its dense delta-PRM G_d.

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "ispars/delta_prm.hpp"
#include "ispars/dense_search.hpp"
#include "ispars/roadmap_builder.hpp"
#include "ispars/sample_batch.hpp"

namespace ispars {

/// How often each admission criterion changed G_s.
struct SparsAdmissions {
  std::uint64_t guard = 0;             ///< W empty: q added alone.
  std::uint64_t bridge = 0;            ///< W spans components: q added, joined to each.
  std::uint64_t interface_edge = 0;    ///< Two nearest sparse vertices joined directly.
  std::uint64_t interface_vertex = 0;  ///< ... or through q, when their segment is blocked.
  std::uint64_t inspection = 0;        ///< chi(q) not covered by W: q added as a guard.
  std::uint64_t shortcut_edge = 0;     ///< Stretch violated: v' and v'' joined directly.
  std::uint64_t shortcut_path = 0;     ///< ... or through the smoothed dense path.
};

/// One application of the shortcut criterion, kept so that tests and reports can check it.
struct ShortcutRecord {
  VertexId v = kNoVertex;       ///< rep(q), the sparse vertex whose interfaces are compared.
  VertexId vp = kNoVertex;      ///< v': the interface q supports.
  VertexId vpp = kNoVertex;     ///< v'': the other interface of v.
  double sparse_length = 0.0;   ///< (|v - v'| + |v - v''|) / 2 for this very pair.
  double dense_length = 0.0;    ///< Shortest dense route from q to a support of v|v''.
  bool direct_edge = false;     ///< Fixed by the edge v'-v''; otherwise by `path`.
  std::vector<VertexId> path;   ///< Sparse vertices of the added smoothed route, in order.
  VertexId front_rep = kNoVertex;  ///< rep of the route's first dense vertex when it was added.
  VertexId back_rep = kNoVertex;   ///< rep of the route's last dense vertex when it was added.
};

/// SPARS, with the inspection test of Inspection-SPARS when `inspection_test` is set.
/// Every sparse vertex is a dense vertex (the same sample); dense_ids() maps one to the other.
class SparsBuilder final : public RoadmapBuilder {
 public:
  SparsBuilder(const Scene& scene, const BuildOptions& options, bool inspection_test);

  void extend(std::size_t samples) override;
  [[nodiscard]] const Roadmap& roadmap() const override { return sparse_; }
  [[nodiscard]] const Roadmap* dense() const override { return &dense_.graph(); }
  [[nodiscard]] std::span<const VertexId> dense_ids() const override { return dense_of_sparse_; }

  /// One iteration of Alg. 1's loop for a prepared sample (invalid samples are dropped).
  void step(const PreparedSample& sample);
  void step(const Vec3& sample) override;

  [[nodiscard]] const SparsAdmissions& admissions() const { return admissions_; }
  [[nodiscard]] const std::vector<ShortcutRecord>& shortcuts() const { return shortcuts_; }
  /// rep(x) of dense vertex x: its nearest sparse vertex within Delta by a valid segment.
  [[nodiscard]] VertexId representative(VertexId dense_vertex) const { return rep_[dense_vertex]; }
  /// Dense vertices with representative v that have a dense neighbour represented by v2: the
  /// supports of the interface v|v2, ascending.
  [[nodiscard]] std::vector<VertexId> interface_supports(VertexId v, VertexId v2) const;

 private:
  // Alg. 1, line by line.
  void reachable_guards(const Vec3& q);  // fills nearby_ (graph neighbourhood) and reachable_ (W)
  bool bridge_test(VertexId q);
  bool interface_test(VertexId q);
  bool inspection_test(VertexId q) const;
  void shortcut_test(VertexId q);

  /// AddGuard: q becomes a sparse vertex (no edges); representatives and supports follow.
  VertexId add_guard(VertexId dense_vertex);
  void update_supports(VertexId dense_vertex);
  /// Registers dense vertex x as a support of rep(x)|partner (a new neighbour brought it).
  void add_partner(VertexId x, VertexId partner);
  VertexId interface_neighbor(VertexId dense_vertex, VertexId rep) const;
  std::vector<VertexId> smooth(const std::vector<VertexId>& dense_path) const;

  const Scene* scene_;
  BuildOptions options_;
  bool inspection_test_;
  double sparse_delta_;
  double stretch_;
  Rng rng_;

  DeltaPrm dense_;
  Roadmap sparse_;
  PointGrid sparse_grid_;
  std::vector<VertexId> dense_of_sparse_;
  std::vector<VertexId> sparse_of_dense_;

  std::vector<VertexId> rep_;           // per dense vertex
  std::vector<double> rep_distance_;    // per dense vertex
  std::vector<VertexId> support_rep_;   // the rep under which partners_ are registered
  std::vector<std::vector<VertexId>> partners_;  // per dense vertex: v' of the interfaces it supports
  std::vector<std::map<VertexId, std::vector<VertexId>>> supports_;  // per sparse v: v' -> dense ids

  SparsAdmissions admissions_;
  std::vector<ShortcutRecord> shortcuts_;
  std::vector<std::pair<double, std::uint32_t>> nearby_;
  std::vector<VertexId> reachable_;
  std::vector<PreparedSample> batch_;
  DenseSearch search_;
};

}  // namespace ispars
