// Roadmap batches: ranges of the change log, digests, encodings, and replicas that take a batch
// whole or not at all.

#include <gtest/gtest.h>

#include <limits>
#include <memory>

#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

// Builds Inspection-SPARS in `batches` steps, keeping each step's batch.
std::vector<RoadmapBatch> build_batches(planning::SparsBuilder& builder, int batches) {
  std::vector<RoadmapBatch> out;
  std::uint64_t version = builder.roadmap().version();
  out.push_back(batch_since(builder.roadmap(), 0));  // the root
  for (int i = 0; i < batches; ++i) {
    builder.extend(300);
    out.push_back(batch_since(builder.roadmap(), version));
    version = builder.roadmap().version();
  }
  return out;
}

// An Inspection-SPARS build cut into batches.
class RoadmapBatchTest : public ::testing::Test {
 protected:
  void build(const std::string& scene_name, int batches) {
    scene_ = &test::shared_scene(scene_name);
    builder_ = std::make_unique<planning::SparsBuilder>(*scene_, planning::BuildOptions{},
                                                        planning::SparsRules::for_variant(SparsVariant::stretch, true));
    batches_ = build_batches(*builder_, batches);
  }

  const planning::Scene* scene_ = nullptr;
  std::unique_ptr<planning::SparsBuilder> builder_;
  std::vector<RoadmapBatch> batches_;
};

TEST_F(RoadmapBatchTest, BatchRangeIsAPrefixOfTheLogAndTheDigestFollowsIt) {
  build("truss_bridge", 3);
  const Roadmap& g = builder_->roadmap();
  const std::uint64_t mid = g.version() / 2;
  Roadmap prefix(scene_->pois().size());
  apply_batch(prefix, batch_range(g, 0, mid));
  EXPECT_EQ(prefix.version(), mid);
  apply_batch(prefix, batch_range(g, mid, g.version()));
  EXPECT_EQ(roadmap_digest(prefix), roadmap_digest(g));
  EXPECT_EQ(test::fingerprint(prefix), test::fingerprint(g));
  Roadmap shorter(scene_->pois().size());
  apply_batch(shorter, batch_range(g, 0, mid));
  EXPECT_NE(roadmap_digest(shorter), roadmap_digest(g));
  EXPECT_EQ(batch_range(g, 0, g.version() + 100).to_version, g.version());  // clamped
}

// The digest is streamed from the roadmap; it must stay the FNV-1a of the encoded whole batch
// (what the digests printed and compared so far were), and same_changes_as must agree with it.
TEST_F(RoadmapBatchTest, TheStreamedDigestIsTheDigestOfTheEncodedLogAndSameChangesAgrees) {
  build("truss_bridge", 3);
  const Roadmap& g = builder_->roadmap();
  const std::string bytes = encode_batch(batch_since(g, 0));
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  EXPECT_EQ(roadmap_digest(g), hash);
  Roadmap copy(scene_->pois().size());
  apply_batch(copy, batch_since(g, 0));
  EXPECT_TRUE(copy.same_changes_as(g));
  Roadmap shorter(scene_->pois().size());
  apply_batch(shorter, batch_range(g, 0, g.version() - 1));
  EXPECT_FALSE(shorter.same_changes_as(g));
  // The same vertices and edges in another order are another log.
  Roadmap reordered(scene_->pois().size());
  for (VertexId v = 0; v < g.vertex_count(); ++v) reordered.add_vertex(g.position(v), g.visibility_table().ids(v));
  for (const RoadmapEdge& e : g.edges()) reordered.add_edge(e.u, e.v);
  EXPECT_EQ(reordered.edge_count(), g.edge_count());
  EXPECT_FALSE(reordered.same_changes_as(g));
  EXPECT_NE(roadmap_digest(reordered), roadmap_digest(g));
}

TEST_F(RoadmapBatchTest, AMalformedBatchIsRefusedWholeAndLeavesTheReplicaUntouched) {
  build("truss_bridge", 2);
  Roadmap replica(scene_->pois().size());
  apply_batch(replica, batches_[0]);
  const std::string before = test::fingerprint(replica);
  const auto expect_refused = [&](RoadmapBatch bad, const std::string& needle) {
    try {
      apply_batch(replica, bad);
      ADD_FAILURE() << "accepted: " << needle;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::fingerprint(replica), before) << needle;
  };
  RoadmapBatch b = batches_[1];
  ASSERT_FALSE(b.visible.empty());
  b.visible.back().push_back(static_cast<PoiId>(scene_->pois().size()));
  expect_refused(b, "sees POI");
  b = batches_[1];
  b.positions.back().x() = std::numeric_limits<double>::quiet_NaN();
  expect_refused(b, "not finite");
  b = batches_[1];
  ASSERT_FALSE(b.edges.empty());
  b.edges.back().cost += 1e-9;
  expect_refused(b, "cost is not its length");
  b = batches_[1];
  b.edges.back() = b.edges.front();
  expect_refused(b, "duplicate");
  b = batches_[1];
  b.edges.back().v = 1u << 30;
  expect_refused(b, "does not fit");
  apply_batch(replica, batches_[1]);  // the good one still applies
  EXPECT_EQ(replica.version(), batches_[1].to_version);
}

TEST_F(RoadmapBatchTest, BatchesRoundTripThroughTheirEncoding) {
  build("truss_bridge", 5);
  Roadmap replica(scene_->pois().size());
  for (const auto& b : batches_) apply_batch(replica, decode_batch(encode_batch(b)));
  EXPECT_EQ(test::fingerprint(replica), test::fingerprint(builder_->roadmap()));
  EXPECT_EQ(replica.version(), builder_->roadmap().version());
  EXPECT_EQ(replica.component_count(), builder_->roadmap().component_count());
}

TEST_F(RoadmapBatchTest, AnEncodingIsItsPredictedSizeAppendsInPlaceAndDecodesFromAView) {
  build("truss_bridge", 3);
  std::string appended = "prefix";
  for (const RoadmapBatch& b : batches_) {
    const std::string alone = encode_batch(b);
    EXPECT_EQ(alone.size(), encoded_batch_size(b));
    const std::size_t before = appended.size();
    append_encoded_batch(appended, b);
    EXPECT_EQ(std::string_view(appended).substr(before), alone) << "the same bytes, appended";
    // A view into a larger buffer decodes to the same batch, encoded again byte for byte.
    EXPECT_EQ(encode_batch(decode_batch(std::string_view(appended).substr(before))), alone);
  }
  // A count that cannot fit in what is left is refused before anything is reserved for it.
  std::string huge = encode_batch(batches_[1]);
  const std::size_t changes_at = 2 * sizeof(std::uint64_t);
  const std::uint32_t impossible = 0x7fffffff;
  huge.replace(changes_at, sizeof impossible, reinterpret_cast<const char*>(&impossible), sizeof impossible);
  EXPECT_THROW((void)decode_batch(huge), std::runtime_error);
}

// A snapshot's encoding, gathered a slice at a time: the same bytes as in one piece, across
// several slices, and nothing once keep_going says stop (a stopping daemon does not wait it out).
TEST(RoadmapBatch, AnEncodingGatheredBySlicesIsTheWholeOneAndStopsWhenAsked) {
  Roadmap roadmap(4);
  const std::vector<PoiId> seen{1, 3};
  for (int i = 0; i < 70'000; ++i) {
    const VertexId v = roadmap.add_vertex(Vec3(i, 0.5 * i, 0), seen);
    if (v > 0) roadmap.add_edge(v - 1, v);
  }
  ASSERT_GT(roadmap.version(), 2u * 65536u) << "more than two slices";
  for (const std::uint64_t to : {roadmap.version(), std::uint64_t{70'000}, std::uint64_t{1}}) {
    const auto sliced = encode_prefix(roadmap, to, [] { return true; });
    ASSERT_TRUE(sliced.has_value());
    EXPECT_EQ(*sliced, encode_batch(batch_range(roadmap, 0, to))) << to;
  }
  int asked = 0;
  EXPECT_EQ(encode_prefix(roadmap, roadmap.version(), [&] { return ++asked < 2; }), std::nullopt);
  EXPECT_EQ(asked, 2) << "it stopped at the first slice after being told";
}

}  // namespace
}  // namespace ispars
