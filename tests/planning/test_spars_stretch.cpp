// The sparse-vertex stretch rules (spars_spanner.cpp) and bridges by edge: short pairs of sparse
// vertices, where Alg. 1 read literally leaves long detours (an inspection guard with no edges,
// interfaces bounded only through rep(q)). Each property is checked on the default rule set and
// shown to fail on the literal one, so the check itself can fail.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/search/graph_search.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

SparsRules rules(SparsVariant variant) { return SparsRules::for_variant(variant, true); }

// W(q) by brute force: sparse vertices within Delta whose segment to q is valid, `self` excluded.
std::vector<VertexId> brute_reachable(const Scene& scene, const Roadmap& sparse, const Vec3& q, VertexId self) {
  std::vector<VertexId> out;
  for (VertexId s = 0; s < sparse.vertex_count(); ++s) {
    if (s == self || (sparse.position(s) - q).norm() > scene.config().sparse_delta) continue;
    if (scene.segment_valid(sparse.position(s), q)) out.push_back(s);
  }
  return out;
}

// Pairs w, w' of W(q) whose sparse route is longer than t (|w - q| + |q - w'|) + slack Delta.
std::size_t witness_violations(const Scene& scene, const Roadmap& sparse, const Vec3& q, VertexId self,
                               double slack = 0.0) {
  const std::vector<VertexId> w = brute_reachable(scene, sparse, q, self);
  const double t = scene.config().stretch;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const std::vector<double> d = shortest_distances(sparse, w[i]);
    for (std::size_t j = i + 1; j < w.size(); ++j) {
      const double witness = (sparse.position(w[i]) - q).norm() + (q - sparse.position(w[j])).norm();
      bad += d[w[j]] > (t * witness + slack * scene.config().sparse_delta) * (1.0 + 1e-12);
    }
  }
  return bad;
}

struct StepRun {
  std::size_t checked_steps = 0;
  std::size_t violating_steps = 0;
  std::size_t steps_past_zero_slack = 0;  // steps with a pair past t times its witness alone
  SparsAdmissions admissions;
};

// A build of `warmup` samples, then `steps` samples half near the surface, each followed by the
// witness check of its own W(q).
StepRun check_every_step(const Scene& scene, SparsVariant variant, std::size_t warmup, std::size_t steps,
                         double slack = 0.0) {
  BuildOptions options;
  options.stretch_slack = slack;
  SparsBuilder b(scene, options, rules(variant));
  b.extend(warmup);
  scene_files::Rng rng(7);
  StepRun run;
  for (const Vec3& q : test::mixed_query_points(scene, rng, steps)) {
    const std::size_t dense_before = b.dense()->vertex_count();
    b.step(q);
    if (b.dense()->vertex_count() == dense_before) continue;  // invalid sample
    const VertexId dense_q = static_cast<VertexId>(dense_before);
    const VertexId self =
        b.dense_ids().back() == dense_q ? static_cast<VertexId>(b.roadmap().vertex_count() - 1) : kNoVertex;
    ++run.checked_steps;
    run.violating_steps += witness_violations(scene, b.roadmap(), q, self, slack) > 0;
    if (slack > 0.0) run.steps_past_zero_slack += witness_violations(scene, b.roadmap(), q, self) > 0;
  }
  run.admissions = b.admissions();
  return run;
}

class StretchOnSharedScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(StretchOnSharedScenes, EveryStepBoundsTheRoutesBetweenTheMembersOfW) {
  // After step(q), any two sparse vertices that q sees within Delta are joined in G_s within t
  // times the route through q: the witnessed-pair rule when q stays out, the vertex join when it
  // is admitted. Alg. 1 read literally does not promise this, and breaks it.
  const Scene& scene = test::shared_scene(GetParam());
  // Not scaled down in the sanitizer pass: fewer steps may find nothing to catch on Alg. 1.
  const std::size_t steps = 300;
  const StepRun stretch = check_every_step(scene, SparsVariant::stretch, 2500, steps);
  const StepRun alg1 = check_every_step(scene, SparsVariant::alg1, 2500, steps);
  ASSERT_GT(stretch.checked_steps, steps / 3);
  EXPECT_EQ(stretch.violating_steps, 0u);
  EXPECT_GT(alg1.violating_steps, 0u) << "the check found nothing to catch on Alg. 1: it would prove nothing";
  EXPECT_GT(stretch.admissions.witness_edge, 0u);
  EXPECT_GT(stretch.admissions.join_edges, 0u);
}

TEST_P(StretchOnSharedScenes, WithASlackEveryStepBoundsTheRoutesWithinTheSlackAndTheRoadmapIsSmaller) {
  // stretch_slack = 0.5: the same bound plus half of Delta, kept at every step; the slack is
  // used (some pair exceeds the bound without it), and buys a smaller roadmap.
  const Scene& scene = test::shared_scene(GetParam());
  const StepRun slack = check_every_step(scene, SparsVariant::stretch, 2500, 300, 0.5);
  ASSERT_GT(slack.checked_steps, 100u);
  EXPECT_EQ(slack.violating_steps, 0u);
  EXPECT_GT(slack.steps_past_zero_slack, 0u) << "no pair used the slack: the check would prove nothing";
  BuildOptions with, without;
  with.stretch_slack = 0.5;
  SparsBuilder a(scene, with, rules(SparsVariant::stretch));
  SparsBuilder b(scene, without, rules(SparsVariant::stretch));
  a.extend(3000);
  b.extend(3000);
  EXPECT_LT(a.roadmap().edge_count(), b.roadmap().edge_count()) << GetParam();
}

TEST(SparsRules, AStretchSlackOutsideZeroToOneIsRefused) {
  const Scene& scene = test::shared_scene("water_tower");
  for (const double bad : {-0.01, 1.01, std::nan("")}) {
    BuildOptions options;
    options.stretch_slack = bad;
    EXPECT_THROW(SparsBuilder(scene, options, rules(SparsVariant::stretch)), std::invalid_argument) << bad;
  }
}

TEST_P(StretchOnSharedScenes, SparseVerticesWithinDeltaHaveRoutesWithinTTimesTheirDistance) {
  // The vertex join's invariant: two sparse vertices within Delta of each other with a valid
  // segment are never more than t |a - b| apart in G_s (whichever came second joined the first).
  const Scene& scene = test::shared_scene(GetParam());
  const double t = scene.config().stretch;
  for (const SparsVariant variant : {SparsVariant::stretch, SparsVariant::alg1}) {
    SparsBuilder b(scene, BuildOptions{}, rules(variant));
    b.extend(3000);
    const Roadmap& g = b.roadmap();
    std::size_t pairs = 0, violations = 0;
    for (VertexId a = 0; a < g.vertex_count(); ++a) {
      const std::vector<double> d = shortest_distances(g, a);
      for (VertexId c = a + 1; c < g.vertex_count(); ++c) {
        const double length = (g.position(a) - g.position(c)).norm();
        if (length > scene.config().sparse_delta || !scene.segment_valid(g.position(a), g.position(c))) continue;
        ++pairs;
        violations += d[c] > t * length * (1.0 + 1e-12);
      }
    }
    ASSERT_GT(pairs, 100u);
    if (variant == SparsVariant::stretch) {
      EXPECT_EQ(violations, 0u) << GetParam();
    } else {
      EXPECT_GT(violations, 0u) << "Alg. 1 kept every short pair: the check would prove nothing";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, StretchOnSharedScenes,
                         ::testing::Values("truss_bridge", "water_tower", "caric_city", "radio_tower"));

TEST(BridgeByEdge, JoinsTwoComponentsDirectlyWhenTheySeeEachOther) {
  const Scene scene = test::open_scene(2.0, 3.0);
  SparsBuilder b(scene, BuildOptions{}, rules(SparsVariant::stretch));
  b.step(Vec3(5, 0, 0));  // beyond Delta of the root: a guard, alone
  ASSERT_EQ(b.roadmap().vertex_count(), 2u);
  b.step(Vec3(2.5, 1.5, 0));  // sees both components; they see each other
  EXPECT_EQ(b.admissions().bridge_edge, 1u);
  EXPECT_EQ(b.admissions().bridge, 0u);
  EXPECT_EQ(b.roadmap().vertex_count(), 2u) << "q is not needed to join them";
  EXPECT_TRUE(b.roadmap().has_edge(0, 1));
  EXPECT_TRUE(verify_roadmap(scene, b.roadmap()).geometry_ok());
}

TEST(BridgeByEdge, AdmitsTheSampleWhenOnlyItJoinsTheComponents) {
  const Scene scene = test::open_scene(2.0, 3.0, /*wall=*/true);
  ASSERT_FALSE(scene.segment_valid(Vec3(0, 0, 0), Vec3(5, 0, 0)));
  SparsBuilder b(scene, BuildOptions{}, rules(SparsVariant::stretch));
  b.step(Vec3(5, 0, 0));
  ASSERT_EQ(b.roadmap().vertex_count(), 2u);
  b.step(Vec3(2.5, 1.5, 0));  // the wall blocks root - guard: the bridge goes through q
  EXPECT_EQ(b.admissions().bridge, 1u);
  EXPECT_EQ(b.admissions().bridge_edge, 0u);
  ASSERT_EQ(b.roadmap().vertex_count(), 3u);
  EXPECT_TRUE(b.roadmap().has_edge(2, 0));
  EXPECT_TRUE(b.roadmap().has_edge(2, 1));
  EXPECT_TRUE(verify_roadmap(scene, b.roadmap()).geometry_ok());
}

TEST(SparsRules, VariantsNameTheirRuleSets) {
  const SparsRules paper = SparsRules::for_variant(SparsVariant::alg1, true);
  EXPECT_TRUE(paper.inspection_test && paper.dense_shortcut);
  EXPECT_FALSE(paper.vertex_join || paper.witnessed_pairs || paper.bridge_by_edge || paper.witness_nearest_only);
  const SparsRules ours = SparsRules::for_variant(SparsVariant::stretch, false);
  EXPECT_FALSE(ours.inspection_test || ours.dense_shortcut || ours.witness_nearest_only);
  EXPECT_TRUE(ours.vertex_join && ours.witnessed_pairs && ours.bridge_by_edge);
  EXPECT_EQ(parse_spars_variant("alg1"), SparsVariant::alg1);
  EXPECT_EQ(parse_spars_variant("stretch"), SparsVariant::stretch);
  EXPECT_FALSE(parse_spars_variant("Alg1").has_value());
  EXPECT_FALSE(parse_spars_variant("").has_value());
  EXPECT_EQ(BuildOptions{}.variant, SparsVariant::stretch) << "the default rule set";
}

TEST(SparsRules, EachVariantIsDeterministicAndThreadIndependent) {
  const Scene& scene = test::shared_scene("truss_bridge");
  for (const SparsVariant variant : {SparsVariant::stretch, SparsVariant::alg1}) {
    BuildOptions one;
    one.variant = variant;
    BuildOptions two = one;
    two.threads = 2;
    const auto a = make_roadmap_builder(BuildMethod::ispars, scene, one);
    const auto b = make_roadmap_builder(BuildMethod::ispars, scene, two);
    a->extend(test::scaled(2000));
    b->extend(test::scaled(1000));
    b->extend(test::scaled(2000) - test::scaled(1000));
    EXPECT_EQ(test::fingerprint(a->roadmap()), test::fingerprint(b->roadmap())) << to_string(variant);
    EXPECT_EQ(test::fingerprint(*a->dense()), test::fingerprint(*b->dense()));
  }
}

}  // namespace
}  // namespace ispars::planning
