#pragma once
// SPARS (Dobson & Bekris 2014) and Inspection-SPARS (Alg. 1 of the paper): a sparse roadmap
// G_s grown beside its dense delta-PRM G_d, with sparse-vertex stretch rules. What they prove is
// local: a route within t |a - b| between sparse vertices within Delta in view, and within t times
// the path through q between two members of a sample's W(q). They bound no farther pair, which
// Theorem 1's proof would also need (docs/sparse-stretch.md; measured in docs/results/stretch.md).

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "ispars/planning/builders/delta_prm.hpp"
#include "ispars/planning/builders/known_routes.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/sample_batch.hpp"
#include "ispars/planning/search/dense_search.hpp"

namespace ispars::planning {

/// The rules that grow G_s, each on or off. `for_variant` gives the named sets; the lab's
/// ablation turns single rules on and off.
struct SparsRules {
  /// Alg. 1, lines 18-23: admit q when chi(q) reaches outside the union of chi(w), w in W(q).
  bool inspection_test = true;
  /// Alg. 1, lines 24-26: Dobson & Bekris' shortcut test, through the dense graph.
  bool dense_shortcut = true;
  /// Sparse-vertex join: a new sparse vertex s is joined to each w in W(s) (nearest first)
  /// whose sparse route exceeds t |s - w|.
  bool vertex_join = false;
  /// Witnessed pairs: for a sample q left out of G_s, every pair w, w' of W(q) whose sparse
  /// route exceeds t (|w - q| + |q - w'|) is repaired, by the edge w-w' when its segment is
  /// valid, otherwise through q (admitted, joined to both).
  bool witnessed_pairs = false;
  /// Witnessed pairs: only the pairs that include rep(q), the nearest member of W(q).
  bool witness_nearest_only = false;
  /// Bridge: join the components' members directly where their segment is valid (as the
  /// interface test does), admitting q only for the components it alone can join.
  bool bridge_by_edge = false;
  /// Keep the dense delta-PRM G_d (and the representatives and interface supports over it)
  /// beside G_s. Only the dense shortcut reads them: without it no rule does, and a builder
  /// without G_d (ispars2) grows exactly the same G_s in memory proportional to G_s alone.
  bool dense_graph = true;

  /// The named rule sets: `alg1` is the paper's Alg. 1 read literally (and SPARS without the
  /// inspection test); `stretch`, the default, adds the vertex join, the witnessed pairs over
  /// all of W(q) and bridges by edge, and drops the dense shortcut (with them it added edges for
  /// tours 0.5-2.9% shorter; docs/sparse-stretch.md has the ablation behind this choice).
  [[nodiscard]] static SparsRules for_variant(SparsVariant variant, bool inspection_test);
  /// ispars2: the `stretch` rules with the inspection test, and no dense graph.
  [[nodiscard]] static SparsRules dense_free();
};

/// How often each admission criterion changed G_s, and the edges each added.
struct SparsAdmissions {
  std::uint64_t guard = 0;             ///< W empty: q added alone.
  std::uint64_t bridge = 0;            ///< W spans components: q added, joined to each.
  std::uint64_t bridge_edge = 0;       ///< ... or two components joined directly.
  std::uint64_t interface_edge = 0;    ///< Two nearest sparse vertices joined directly.
  std::uint64_t interface_vertex = 0;  ///< ... or through q, when their segment is blocked.
  std::uint64_t inspection = 0;        ///< chi(q) not covered by W: q added as a guard.
  std::uint64_t shortcut_edge = 0;     ///< Stretch violated: v' and v'' joined directly.
  std::uint64_t shortcut_path = 0;     ///< ... or through the smoothed dense path.
  std::uint64_t witness_edge = 0;      ///< A witnessed pair joined directly.
  std::uint64_t witness_vertex = 0;    ///< ... or through q, admitted for it.

  /// Edges of G_s by the rule that added them.
  std::uint64_t bridge_edges = 0;
  std::uint64_t interface_edges = 0;  ///< Direct, and the two through q.
  std::uint64_t shortcut_edges = 0;   ///< Direct, and along (and at the ends of) added paths.
  std::uint64_t join_edges = 0;       ///< Sparse-vertex join.
  std::uint64_t witness_edges = 0;    ///< Witnessed pairs, direct and through q.
  /// Vertices added along shortcut paths (not counted in shortcut_path, which counts paths).
  std::uint64_t shortcut_path_vertices = 0;
};

/// One application of the shortcut criterion, kept so that tests and reports can check it.
struct ShortcutRecord {
  VertexId v = kNoVertex;          ///< rep(q), the sparse vertex whose interfaces are compared.
  VertexId vp = kNoVertex;         ///< v': the interface q supports.
  VertexId vpp = kNoVertex;        ///< v'': the other interface of v.
  double sparse_length = 0.0;      ///< (|v - v'| + |v - v''|) / 2 for this very pair.
  double dense_length = 0.0;       ///< Shortest dense route from q to a support of v|v''.
  bool direct_edge = false;        ///< Fixed by the edge v'-v''; otherwise by `path`.
  std::vector<VertexId> path;      ///< Sparse vertices of the added smoothed route, in order.
  VertexId front_rep = kNoVertex;  ///< rep of the route's first dense vertex when it was added.
  VertexId back_rep = kNoVertex;   ///< rep of the route's last dense vertex when it was added.
};

/// SPARS, with the inspection test of Inspection-SPARS when rules.inspection_test is set.
/// With rules.dense_graph every sparse vertex is a dense vertex (the same sample), and
/// dense_ids() maps one to the other; without it there is no dense graph (dense() is null).
class SparsBuilder final : public RoadmapBuilder {
 public:
  /// Throws std::invalid_argument for rules that need G_d without it (the dense shortcut).
  SparsBuilder(const Scene& scene, const BuildOptions& options, const SparsRules& rules);
  /// Goes on from `built`, grown by these rules from built.samples samples of options.seed's
  /// stream, as if it had never stopped (the admission counts and shortcut records start again
  /// empty). Without G_d, G_s and the place in the stream are the whole state. With it, G_d and
  /// dense_ids are given too, and the representatives and interface supports are restored from
  /// them (restore_representatives): they are functions of G_s and G_d. Throws
  /// std::invalid_argument when `built` has a dense roadmap and the rules none, or the reverse;
  /// resume_roadmap_builder checks the roots and the pair.
  SparsBuilder(const Scene& scene, const BuildOptions& options, const SparsRules& rules, BuiltRoadmaps built);

  void extend(std::size_t samples) override;
  /// An inspection task (spars_task.cpp): every vertex learns the new POIs it sees; then, with
  /// the inspection test, Alg. 1's lines 18-23 run again for the new POIs over every sample drawn
  /// so far, in the build's order (the dense vertices with G_d; the seed's stream drawn again
  /// without): a sample seeing a new POI that no sparse vertex within Delta in view sees becomes a
  /// guard, joined by the stretch rules (vertex join; Alg. 1: the bridge test's edges), and then
  /// the witness rule runs again for the samples near the new guards (replay_witnesses).
  /// Invariant 1 then holds for the new POIs as for the old. Samples given to step(Vec3) are not
  /// in the stream and are not replayed. Returns the vertices added.
  std::size_t add_pois(const Scene& widened, const std::function<bool()>& keep_going = {}) override;
  [[nodiscard]] const Roadmap& roadmap() const override { return sparse_; }
  [[nodiscard]] const Roadmap* dense() const override { return rules_.dense_graph ? &dense_.graph() : nullptr; }
  [[nodiscard]] std::span<const VertexId> dense_ids() const override {
    return rules_.dense_graph ? std::span<const VertexId>(dense_of_sparse_) : std::span<const VertexId>();
  }

  /// One iteration of Alg. 1's loop for a prepared sample (invalid samples are dropped).
  void step(const PreparedSample& sample);
  void step(const Vec3& sample) override;

  [[nodiscard]] const SparsRules& rules() const { return rules_; }
  [[nodiscard]] const SparsAdmissions& admissions() const { return admissions_; }
  [[nodiscard]] const std::vector<ShortcutRecord>& shortcuts() const { return shortcuts_; }
  /// rep(x) of dense vertex x: its nearest sparse vertex within Delta by a valid segment.
  [[nodiscard]] VertexId representative(VertexId dense_vertex) const { return rep_[dense_vertex]; }
  /// Dense vertices with representative v that have a dense neighbour represented by v2: the
  /// supports of the interface v|v2, ascending.
  [[nodiscard]] std::vector<VertexId> interface_supports(VertexId v, VertexId v2) const;

 private:
  // Alg. 1, line by line (spars_builder.cpp), for the current sample q (current_).
  void reachable_guards(const Vec3& q);  // fills nearby_ (graph neighbourhood) and reachable_ (W)
  bool bridge_test();
  bool interface_test();
  bool inspection_test() const;
  /// The current sample q as a sparse vertex: added (AddGuard) on the first call.
  VertexId admit();
  // The dense shortcut (spars_spanner.cpp).
  void shortcut_test(VertexId q);
  /// A pair shortcut_test weighs: q supports the interface v|vp; vpp is a sparse neighbour of v,
  /// not vp and not adjacent to it, with a known interface v|vpp. The sparse route between the
  /// interfaces through v is estimated with midpoints; the dense one is the shortest from q to a
  /// support of v|vpp.
  struct ShortcutCandidate {
    VertexId vp;
    VertexId vpp;
    double sparse_length;
    double dense_length = std::numeric_limits<double>::infinity();
    VertexId support = kNoVertex;
  };
  [[nodiscard]] std::vector<ShortcutCandidate> shortcut_candidates(VertexId q, VertexId v) const;
  void find_dense_supports(VertexId q, VertexId v, std::vector<ShortcutCandidate>& candidates);
  void add_shortcut(VertexId q, VertexId v, const ShortcutCandidate& c);
  std::vector<VertexId> smooth(const std::vector<VertexId>& dense_path) const;
  VertexId interface_neighbor(VertexId dense_vertex, VertexId rep) const;
  // The sparse-vertex stretch rules (spars_spanner.cpp).
  /// Joins sparse vertex s to the members of `reachable` (W(s), nearest first) whose sparse
  /// route from s exceeds t |s - w|.
  void vertex_join(VertexId s, const std::vector<VertexId>& reachable);
  /// Repairs every pair of W(q) whose sparse route exceeds t times the route through q; returns
  /// whether q was admitted.
  /// `through`: only pairs with a member from this id on (a task's guards); 0 for every pair.
  bool witnessed_pairs(VertexId through = 0);
  /// The first k whose sparse route from `from` exceeds bounds[k] (targets.size() when none does).
  std::size_t first_long_route(VertexId from, std::span<const VertexId> targets, std::span<const double> bounds);
  /// The shortest route between sparse vertices a and b known so far (an edge, or a route a
  /// search found), an upper bound on d_s(a, b) forever since routes only get shorter;
  /// infinity when none is known. Lets the stretch rules skip searches they already answered.
  [[nodiscard]] double known_route(VertexId a, VertexId b) const { return known_routes_.get(a, b); }
  /// W(x) for sparse vertex s at dense vertex x: sparse vertices within Delta in view, s excluded.
  std::vector<VertexId> reachable_from(VertexId s) const;

  /// After a resume: rep(x) of every dense vertex x, and the interface supports over them, as the
  /// uninterrupted build holds them. rep(x) is the nearest sparse vertex within Delta in view,
  /// the lower id on a tie (as add_guard keeps it); a vertex's partners are its neighbours' reps.
  void restore_representatives();

  /// Whether a sparse vertex within Delta of `q`, in view, sees each POI of `seen` (bits over the
  /// new POIs; `fresh` holds each sparse vertex's): the inspection test for new POIs, checking
  /// segments only for vertices that would add to the cover.
  bool new_pois_covered(const Vec3& q, PoiBits seen, const PoiSetTable& fresh);
  /// The task's replay over the dense vertices (`dense_fresh`: their new POIs), or over the
  /// seed's stream; each guard's new POIs join `sparse_fresh`. Return the guards added.
  std::size_t replay_dense(const PoiSetTable& dense_fresh, PoiSetTable& sparse_fresh,
                           const std::function<bool()>& keep_going);
  std::size_t replay_stream(PoiSetTable& sparse_fresh, PoiId first, const std::function<bool()>& keep_going);
  /// A task guard's edges, for W = reachable_ (its reachable guards before it): the vertex join
  /// with the stretch rules; without them (Alg. 1, whose later samples would have bridged it),
  /// the bridge test's edge to the nearest member of each component W touches.
  void join_task_guard(VertexId s);
  /// The witness rule replayed through the task's guards (ids from `first_guard`): every build
  /// sample that is not a sparse vertex and has one of them within Delta witnesses its reachable
  /// guards' routes again, in the build's order. Returns the vertices it admitted.
  std::size_t replay_witnesses(VertexId first_guard, const std::function<bool()>& keep_going);
  /// One sample of that replay: `dense` is its dense vertex, or kNoVertex without G_d.
  bool witness_again(const Vec3& q, VertexId dense, VertexId first_guard);

  /// AddGuard: dense vertex x becomes a sparse vertex (no edges); representatives and supports
  /// follow.
  VertexId add_guard(VertexId dense_vertex);
  /// Adds the sparse edge u-v (when new), counted under `cause`.
  void connect(VertexId u, VertexId v, std::uint64_t& cause);
  void update_supports(VertexId dense_vertex);
  /// Registers dense vertex x as a support of rep(x)|partner (a new neighbour brought it).
  void add_partner(VertexId x, VertexId partner);

  const Scene* scene_;
  BuildOptions options_;
  SparsRules rules_;
  double sparse_delta_;
  double stretch_;
  double stretch_slack_;    // metres: options_.stretch_slack times Delta
  double slack_now_ = 0.0;  // slack_at(the sample being stepped)
  // The stretch bounds' slack for sample `index` of the stream: stretch_slack_ from
  // options_.stretch_slack_after on, else 0.
  [[nodiscard]] double slack_at(std::uint64_t index) const {
    return index >= options_.stretch_slack_after ? stretch_slack_ : 0.0;
  }
  scene_files::Rng rng_;

  DeltaPrm dense_;
  Roadmap sparse_;
  PointGrid sparse_grid_;
  std::vector<VertexId> dense_of_sparse_;
  std::vector<VertexId> sparse_of_dense_;

  std::vector<VertexId> rep_;                    // per dense vertex
  std::vector<double> rep_distance_;             // per dense vertex
  std::vector<VertexId> support_rep_;            // the rep under which partners_ are registered
  std::vector<std::vector<VertexId>> partners_;  // per dense vertex: v' of the interfaces it supports
  std::vector<std::map<VertexId, std::vector<VertexId>>> supports_;  // per sparse v: v' -> dense ids

  // The sample being processed: its position and chi, its dense vertex (with G_d), and its
  // sparse vertex once admitted.
  struct CurrentSample {
    const PreparedSample* sample = nullptr;
    std::vector<std::uint64_t> seen;  // chi(q) as bits
    VertexId dense = kNoVertex;
    VertexId sparse = kNoVertex;
  } current_;

  SparsAdmissions admissions_;
  std::vector<ShortcutRecord> shortcuts_;
  std::vector<std::pair<double, std::uint32_t>> nearby_;
  std::vector<VertexId> reachable_;
  std::vector<PreparedSample> batch_;
  DenseSearch search_;         // over G_d (shortcut test)
  DenseSearch sparse_search_;  // over G_s (stretch rules)
  struct OpenTarget {
    Vec3 position;
    double bound;
    std::size_t index;
  };
  std::vector<OpenTarget> open_targets_;  // first_long_route's scratch
  enum class TargetState : std::uint8_t { open, short_route, long_route };
  std::vector<TargetState> target_state_;  // first_long_route's scratch, by target index
  std::vector<double> among_w_;            // witnessed_pairs' scratch: known routes between members of W
  KnownRoutes known_routes_;               // edges and routes found: searches the stretch rules can skip
};

}  // namespace ispars::planning
