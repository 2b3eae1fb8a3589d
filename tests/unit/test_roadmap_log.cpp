// The batch log: round trips, and a crash at any byte leaves exactly the committed batches.

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <memory>

#include "ispars/roadmap/roadmap_log.hpp"
#include "ispars/builders/spars_builder.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

// Builds Inspection-SPARS on the truss bridge in `batches` steps, logging each step's batch.
std::vector<RoadmapBatch> build_batches(SparsBuilder& builder, int batches) {
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

// An Inspection-SPARS build cut into logged batches, and a temporary directory for log files.
class RoadmapLogTest : public ::testing::Test {
 protected:
  void build(const std::string& scene_name, int batches) {
    scene_ = &test::shared_scene(scene_name);
    builder_ = std::make_unique<SparsBuilder>(*scene_, BuildOptions{}, SparsRules::for_variant(SparsVariant::stretch, true));
    batches_ = build_batches(*builder_, batches);
  }
  [[nodiscard]] std::filesystem::path log_path() const { return dir_.path() / "roadmap.log"; }
  [[nodiscard]] Roadmap replay_into_replica(const LogReplay& replay) const {
    Roadmap replica(scene_->pois().size());
    for (const auto& b : replay.batches) apply_batch(replica, b);
    return replica;
  }

  const Scene* scene_ = nullptr;
  std::unique_ptr<SparsBuilder> builder_;
  std::vector<RoadmapBatch> batches_;
  test::TempDir dir_;
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(RoadmapLogTest, BatchRangeIsAPrefixOfTheLogAndTheDigestFollowsIt) {
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
TEST_F(RoadmapLogTest, TheStreamedDigestIsTheDigestOfTheEncodedLogAndSameChangesAgrees) {
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

TEST_F(RoadmapLogTest, AMalformedBatchIsRefusedWholeAndLeavesTheReplicaUntouched) {
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

TEST_F(RoadmapLogTest, BatchesRoundTripThroughEncodingAndTheFile) {
  build("truss_bridge", 5);
  {
    RoadmapLogWriter writer(log_path());
    for (const auto& b : batches_) writer.append(b);
    EXPECT_EQ(writer.version(), builder_->roadmap().version());
  }
  const LogReplay replay = read_roadmap_log(log_path());
  EXPECT_FALSE(replay.torn_tail);
  ASSERT_EQ(replay.batches.size(), batches_.size());
  const Roadmap replica = replay_into_replica(replay);
  EXPECT_EQ(test::fingerprint(replica), test::fingerprint(builder_->roadmap()));
  EXPECT_EQ(replica.version(), builder_->roadmap().version());
  EXPECT_EQ(replica.component_count(), builder_->roadmap().component_count());
}

TEST_F(RoadmapLogTest, AnEncodingIsItsPredictedSizeAppendsInPlaceAndDecodesFromAView) {
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

TEST_F(RoadmapLogTest, ACrashAtAnyByteRecoversExactlyTheCommittedBatches) {
  build("water_tower", 3);
  const auto& batches = batches_;
  const auto full = log_path();
  std::vector<std::uint64_t> committed_sizes;  // file size after each append
  {
    RoadmapLogWriter writer(full);
    committed_sizes.push_back(std::filesystem::file_size(full));
    for (const auto& b : batches) {
      writer.append(b);
      committed_sizes.push_back(std::filesystem::file_size(full));
    }
  }
  const std::string bytes = slurp(full);
  const auto cut = dir_.path() / "cut.log";
  // Every cut within 16 bytes of a record boundary and inside the last record; every 61st
  // byte elsewhere.
  const auto step_after = [&](std::size_t size) -> std::size_t {
    if (size >= committed_sizes[committed_sizes.size() - 2]) return 1;
    for (const std::uint64_t boundary : committed_sizes) {
      if (size + 16 >= boundary && size <= boundary + 16) return 1;
    }
    return 61;
  };
  for (std::size_t size = 0; size <= bytes.size(); size += step_after(size)) {
    std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(size));
    const LogReplay replay = read_roadmap_log(cut);
    std::size_t expected = 0;
    while (expected + 1 < committed_sizes.size() && committed_sizes[expected + 1] <= size) ++expected;
    ASSERT_EQ(replay.batches.size(), expected) << "cut at " << size;
    ASSERT_EQ(replay.torn_tail, size != 0 && size != committed_sizes[expected]) << "cut at " << size;
    // Never half-applied: the replica is exactly the first `expected` batches.
    ASSERT_EQ(replay_into_replica(replay).version(), expected == 0 ? 0 : batches[expected - 1].to_version);
  }
}

TEST_F(RoadmapLogTest, ReopeningCutsATornTailAndAppendsAfterIt) {
  build("water_tower", 2);
  const auto& batches = batches_;
  const auto path = log_path();
  {
    RoadmapLogWriter writer(path);
    writer.append(batches[0]);
    writer.append(batches[1]);
  }
  const auto committed = std::filesystem::file_size(path);
  std::ofstream(path, std::ios::binary | std::ios::app) << "half a rec";  // a crash mid-append
  {
    RoadmapLogWriter writer(path);
    EXPECT_TRUE(writer.recovered_torn_tail());
    EXPECT_EQ(std::filesystem::file_size(path), committed);
    EXPECT_EQ(writer.version(), batches[1].to_version);
    EXPECT_THROW(writer.append(batches[1]), std::invalid_argument);  // would duplicate
    writer.append(batches[2]);
  }
  const LogReplay replay = read_roadmap_log(path);
  EXPECT_FALSE(replay.torn_tail);
  EXPECT_EQ(replay.batches.size(), 3u);
}

TEST_F(RoadmapLogTest, CorruptionInTheMiddleStopsTheReplayThere) {
  build("water_tower", 3);
  const auto& batches = batches_;
  const auto path = log_path();
  std::uint64_t second_record_at = 0;
  {
    RoadmapLogWriter writer(path);
    writer.append(batches[0]);
    second_record_at = std::filesystem::file_size(path);
    for (std::size_t i = 1; i < batches.size(); ++i) writer.append(batches[i]);
  }
  std::string bytes = slurp(path);
  bytes[second_record_at + 20] ^= 0x40;  // one flipped bit inside record 2's payload
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  const LogReplay replay = read_roadmap_log(path);
  EXPECT_EQ(replay.batches.size(), 1u);
  EXPECT_TRUE(replay.torn_tail);
  EXPECT_EQ(replay.tail_problem, "record checksum mismatch");
}

TEST_F(RoadmapLogTest, NotALogAndGapsAreRefused) {
  const auto path = dir_.write("other.txt", "hello, this is not a roadmap log");
  EXPECT_THROW((void)read_roadmap_log(path), std::runtime_error);
  EXPECT_TRUE(read_roadmap_log(dir_.path() / "missing.log").batches.empty());
  build("water_tower", 2);
  const auto& batches = batches_;
  Roadmap replica(scene_->pois().size());
  EXPECT_THROW(apply_batch(replica, batches[1]), std::runtime_error);  // skips batch 0
  apply_batch(replica, batches[0]);
  EXPECT_THROW(apply_batch(replica, batches[0]), std::runtime_error);  // a duplicate
  EXPECT_THROW((void)decode_batch(encode_batch(batches[1]) + "x"), std::runtime_error);
  EXPECT_THROW((void)decode_batch(encode_batch(batches[1]).substr(0, 30)), std::runtime_error);
}

}  // namespace
}  // namespace ispars
