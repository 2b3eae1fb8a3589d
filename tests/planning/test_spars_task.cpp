// Inspection tasks on a built roadmap (spars_task.cpp): the new POIs' visibility is exactly a
// rebuild's, Invariant 1 holds for them, the same addition gives the same roadmap, and a task the
// builder cannot take changes nothing.

#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>
#include <vector>

#include "ispars/planning/builders/poi_visibility.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/scene_files/poi_sampling.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

constexpr std::size_t kSamples = 3000;

BuildOptions options_with(unsigned threads) {
  BuildOptions options;
  options.seed = 3;
  options.threads = threads;
  return options;
}

// `count` new POIs on the scene's surface, from a seed of their own.
std::vector<Vec3> task_pois(const Scene& scene, std::size_t count) {
  return scene_files::sample_pois_on_surface(scene.mesh(), count, 77, true);
}

// The sparse and dense roadmaps' digests.
std::pair<std::uint64_t, std::uint64_t> digests(const RoadmapBuilder& b) {
  return {roadmap_digest(b.roadmap()), b.dense() != nullptr ? roadmap_digest(*b.dense()) : 0};
}

VerificationReport verify(const Scene& scene, const RoadmapBuilder& b) {
  return verify_sparse_pair(scene, b.roadmap(), *b.dense(), b.dense_ids());
}

TEST(SparsTask, EveryDenseVertexSeesTheNewPoisARebuildWithThemWouldSee) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 60));
  auto built = make_roadmap_builder(BuildMethod::ispars, scene, options_with(1));
  built->extend(kSamples);
  const std::uint64_t dense_version = built->dense()->version();
  built->add_pois(widened);
  auto rebuilt = make_roadmap_builder(BuildMethod::ispars, widened, options_with(1));
  rebuilt->extend(kSamples);
  // G_d does not depend on the POIs: the same graph, and now the same chi of every vertex.
  EXPECT_EQ(built->dense()->version(), dense_version);
  EXPECT_TRUE(built->dense()->same_changes_as(*rebuilt->dense()));
  EXPECT_EQ(built->roadmap().poi_count(), widened.pois().size());
}

TEST(SparsTask, InvariantOneHoldsForTheNewPoisAndAfterLaterSamples) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 60));
  auto builder = make_roadmap_builder(BuildMethod::ispars, scene, options_with(2));
  builder->extend(kSamples);
  const std::size_t before = builder->roadmap().vertex_count();
  const std::size_t added = builder->add_pois(widened);
  EXPECT_GT(added, 0u) << "no sample needed a guard for 60 new POIs";
  EXPECT_EQ(builder->roadmap().vertex_count(), before + added);
  const VerificationReport report = verify(widened, *builder);
  EXPECT_TRUE(report.geometry_ok());
  EXPECT_EQ(report.invariant_violations, 0u);
  // The positive control: the same roadmaps told the new POIs they see, without the replay's
  // guards, break Invariant 1.
  auto control = make_roadmap_builder(BuildMethod::ispars, scene, options_with(2));
  control->extend(kSamples);
  Roadmap sparse = control->roadmap();
  Roadmap dense = *control->dense();
  sparse.widen_pois(widened.pois().size());
  dense.widen_pois(widened.pois().size());
  for (VertexId x = 0; x < dense.vertex_count(); ++x) {
    dense.add_visible(x, widened.visibility().visible_pois(dense.position(x)));
  }
  for (VertexId s = 0; s < sparse.vertex_count(); ++s) {
    sparse.add_visible(s, widened.visibility().visible_pois(sparse.position(s)));
  }
  EXPECT_GT(verify_sparse_pair(widened, sparse, dense, control->dense_ids()).invariant_violations, 0u);
  // spars keeps no Invariant 1: its vertices learn what they see, and nothing is added.
  auto chi_only = make_roadmap_builder(BuildMethod::spars, scene, options_with(2));
  chi_only->extend(kSamples);
  EXPECT_EQ(chi_only->add_pois(widened), 0u);
  EXPECT_EQ(chi_only->roadmap().poi_count(), widened.pois().size());
  // Later samples treat every POI alike.
  builder->extend(1000);
  EXPECT_EQ(verify(widened, *builder).invariant_violations, 0u);
}

TEST(SparsTask, TheSameAdditionGivesTheSameRoadmapWithAnyThreadCount) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 40));
  const Scene wider = widened.with_more_pois(scene_files::sample_pois_on_surface(scene.mesh(), 30, 78, true));
  std::vector<std::pair<std::uint64_t, std::uint64_t>> seen;
  for (const unsigned threads : {1u, 2u}) {
    auto b = make_roadmap_builder(BuildMethod::ispars, scene, options_with(threads));
    b->extend(kSamples);
    b->add_pois(widened);
    b->extend(500);
    b->add_pois(wider);
    seen.push_back(digests(*b));
  }
  EXPECT_EQ(seen[0], seen[1]);
}

// ispars2 draws its samples again from the seed: the same guards as ispars finds on its dense
// vertices, so the two sparse roadmaps stay byte for byte the same through tasks and extends.
TEST(SparsTask, Ispars2DrawsItsSamplesAgainAndStaysTheRoadmapIsparsGrows) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 60));
  auto ispars = make_roadmap_builder(BuildMethod::ispars, scene, options_with(2));
  auto ispars2 = make_roadmap_builder(BuildMethod::ispars2, scene, options_with(2));
  for (RoadmapBuilder* b : {ispars.get(), ispars2.get()}) b->extend(kSamples);
  const std::size_t added = ispars->add_pois(widened);
  EXPECT_GT(added, 0u);
  EXPECT_EQ(ispars2->add_pois(widened), added);
  EXPECT_TRUE(ispars2->roadmap().same_changes_as(ispars->roadmap()));
  for (RoadmapBuilder* b : {ispars.get(), ispars2.get()}) b->extend(700);
  EXPECT_TRUE(ispars2->roadmap().same_changes_as(ispars->roadmap()));
  EXPECT_EQ(verify(widened, *ispars).invariant_violations, 0u);
}

// A task's guards take part in the stretch rules as a rebuild's would: the samples near them
// witness their routes again (the default rules), and under Alg. 1, which has no vertex join,
// each guard is bridged to the components in view of it instead of standing alone.
TEST(SparsTask, TheWitnessRuleRunsThroughTheTasksGuardsAndAlg1GuardsAreJoined) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 60));
  auto builder = make_roadmap_builder(BuildMethod::ispars, scene, options_with(2));
  builder->extend(kSamples);
  const auto& spars = dynamic_cast<const SparsBuilder&>(*builder);
  const SparsAdmissions before = spars.admissions();
  const std::size_t first_guard = builder->roadmap().vertex_count();
  ASSERT_GT(builder->add_pois(widened), 0u);
  const SparsAdmissions after = spars.admissions();
  EXPECT_GT(after.witness_edges, before.witness_edges) << "no witnessed route through the task's guards";
  EXPECT_EQ(builder->roadmap().vertex_count(),
            first_guard + (after.inspection - before.inspection) + (after.witness_vertex - before.witness_vertex));
  EXPECT_EQ(verify(widened, *builder).invariant_violations, 0u);

  BuildOptions alg1 = options_with(2);
  alg1.variant = SparsVariant::alg1;
  auto literal = make_roadmap_builder(BuildMethod::ispars, scene, alg1);
  literal->extend(kSamples);
  const std::size_t first = literal->roadmap().vertex_count();
  ASSERT_GT(literal->add_pois(widened), 0u);
  const Roadmap& g = literal->roadmap();
  std::size_t joined = 0;
  for (VertexId s = static_cast<VertexId>(first); s < g.vertex_count(); ++s) {
    joined += g.neighbor_ids(s).empty() ? 0 : 1;
    if (!g.neighbor_ids(s).empty()) {
      EXPECT_EQ(g.component(s), g.component(g.neighbor_ids(s).front()));
    }
  }
  EXPECT_GT(joined, 0u) << "every Alg. 1 task guard stands alone";
  EXPECT_EQ(verify(widened, *literal).invariant_violations, 0u);
}

TEST(SparsTask, ATaskTheBuilderCannotTakeChangesNothing) {
  const Scene& scene = test::shared_scene("truss_bridge");
  auto builder = make_roadmap_builder(BuildMethod::ispars, scene, options_with(1));
  builder->extend(1000);
  const auto digest = digests(*builder);
  // A scene whose POIs do not begin with the roadmap's own.
  const Scene& other = test::shared_scene("water_tower");
  EXPECT_THROW(builder->add_pois(other.with_more_pois(task_pois(other, 5))), std::invalid_argument);
  EXPECT_EQ(digests(*builder), digest);
  EXPECT_EQ(builder->roadmap().poi_count(), scene.pois().size());
  // A builder that promises nothing per POI.
  const Scene widened = scene.with_more_pois(task_pois(scene, 5));
  auto dense = make_roadmap_builder(BuildMethod::dense, scene, options_with(1));
  dense->extend(200);
  EXPECT_THROW(dense->add_pois(widened), std::invalid_argument);
}

TEST(SparsTask, SeeingNewPoisOnARoadmapGivesTheRowsTheBuilderGaveIt) {
  // What a store's recovery does for the vertices built before a task: the builder's own rows.
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 60));
  auto built = make_roadmap_builder(BuildMethod::ispars, scene, options_with(1));
  built->extend(kSamples);
  Roadmap sparse = built->roadmap();
  Roadmap dense = *built->dense();
  built->add_pois(widened);
  const std::uint64_t dense_with_task = roadmap_digest(*built->dense());
  built->extend(500);  // vertices built seeing every POI: seeing them again changes nothing
  Roadmap sparse_after = built->roadmap();
  see_new_pois(sparse, widened, static_cast<PoiId>(scene.pois().size()));
  see_new_pois(dense, widened, static_cast<PoiId>(scene.pois().size()));
  EXPECT_EQ(roadmap_digest(dense), dense_with_task);
  const std::uint64_t before = roadmap_digest(sparse_after);
  see_new_pois(sparse_after, widened, static_cast<PoiId>(scene.pois().size()));
  EXPECT_EQ(roadmap_digest(sparse_after), before);
  // The sparse roadmap before the task, told what its vertices see, is the task's roadmap less
  // its guards: every vertex it has, it has with the same POIs.
  for (VertexId v = 0; v < sparse.vertex_count(); ++v) {
    ASSERT_TRUE(std::equal(sparse.visible(v).begin(), sparse.visible(v).end(), sparse_after.visible(v).begin()))
        << "vertex " << v;
  }
}

TEST(SparsTask, AnAdditionStopsWhenAskedAndSaysSo) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 20));
  for (const BuildMethod method : {BuildMethod::ispars, BuildMethod::ispars2}) {
    auto built = make_roadmap_builder(method, scene, options_with(1));
    built->extend(kSamples);
    int asked = 0;
    EXPECT_THROW(built->add_pois(widened, [&] { return ++asked < 3; }), AdditionStopped) << to_string(method);
    EXPECT_EQ(asked, 3) << "it stops at the first no";
  }
}

// takes_pois says which builders add_pois: the others refuse, changing nothing.
TEST(SparsTask, TakesPoisNamesTheBuildersThatAddThem) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 5));
  for (const BuildMethod method :
       {BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars, BuildMethod::irisc, BuildMethod::ispars2}) {
    auto built = make_roadmap_builder(method, scene, options_with(1));
    built->extend(300);
    const std::uint64_t before = roadmap_digest(built->roadmap());
    bool took = true;
    try {
      (void)built->add_pois(widened);
    } catch (const std::exception&) {
      took = false;
      EXPECT_EQ(roadmap_digest(built->roadmap()), before) << to_string(method);
    }
    EXPECT_EQ(took, takes_pois(method)) << to_string(method);
  }
}

// Stopped while it still finds what the vertices see (most of an addition's time on a dense
// pair), the builder is unchanged: the session keeps it and reopens nothing, so a stop is quick.
// Stopped once the inspection test has begun, it says the builder changed.
TEST(SparsTask, AnAdditionStoppedBeforeTheInspectionTestLeavesTheBuilderAsItWas) {
  const Scene& scene = test::shared_scene("truss_bridge");
  const Scene widened = scene.with_more_pois(task_pois(scene, 20));
  for (const BuildMethod method : {BuildMethod::ispars, BuildMethod::ispars2}) {
    auto reference = make_roadmap_builder(method, scene, options_with(1));
    reference->extend(kSamples);
    const std::uint64_t before = roadmap_digest(reference->roadmap());
    (void)reference->add_pois(widened);
    // The rows do not depend on the threads that find them.
    const Roadmap& rows_of = reference->dense() ? *reference->dense() : reference->roadmap();
    const auto first = static_cast<PoiId>(scene.pois().size());
    EXPECT_TRUE(new_poi_visibility(widened, rows_of, first, {}, 1) ==
                new_poi_visibility(widened, rows_of, first, {}, 3))
        << to_string(method);
    // The visibility pass asks once per 256 rows: the dense pair's, or the roadmap's.
    const std::size_t rows =
        reference->dense() ? reference->dense()->vertex_count() : reference->roadmap().vertex_count();
    const auto visibility_asks = static_cast<int>((rows + 255) / 256);
    for (const int stop_at : {visibility_asks, visibility_asks + 1}) {
      auto built = make_roadmap_builder(method, scene, options_with(1));
      built->extend(kSamples);
      int asked = 0;
      try {
        (void)built->add_pois(widened, [&] { return ++asked < stop_at; });
        ADD_FAILURE() << "not stopped";
      } catch (const AdditionStopped& e) {
        EXPECT_EQ(e.builder_changed, stop_at > visibility_asks) << to_string(method) << " stopped at ask " << stop_at;
      }
      if (stop_at > visibility_asks) continue;
      EXPECT_EQ(roadmap_digest(built->roadmap()), before) << to_string(method);
      (void)built->add_pois(widened);  // the same builder, asked again: the reference's roadmap
      EXPECT_EQ(roadmap_digest(built->roadmap()), roadmap_digest(reference->roadmap())) << to_string(method);
    }
  }
}

}  // namespace
}  // namespace ispars::planning
