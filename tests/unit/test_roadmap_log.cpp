// The batch log: round trips, and a crash at any byte leaves exactly the committed batches.

#include <gtest/gtest.h>

#include <fstream>

#include "ispars/roadmap_log.hpp"
#include "ispars/spars_builder.hpp"
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

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(RoadmapLog, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(crc32("", 0), 0u);
}

TEST(RoadmapLog, BatchesRoundTripThroughEncodingAndTheFile) {
  const Scene& scene = test::shared_scene("truss_bridge");
  SparsBuilder builder(scene, BuildOptions{}, true);
  const auto batches = build_batches(builder, 5);
  const test::TempDir dir;
  const auto path = dir.path() / "roadmap.log";
  {
    RoadmapLogWriter writer(path);
    for (const auto& b : batches) writer.append(b);
    EXPECT_EQ(writer.version(), builder.roadmap().version());
  }
  const LogReplay replay = read_roadmap_log(path);
  EXPECT_FALSE(replay.torn_tail);
  ASSERT_EQ(replay.batches.size(), batches.size());
  Roadmap replica(scene.pois().size());
  for (const auto& b : replay.batches) apply_batch(replica, b);
  EXPECT_EQ(test::fingerprint(replica), test::fingerprint(builder.roadmap()));
  EXPECT_EQ(replica.version(), builder.roadmap().version());
  EXPECT_EQ(replica.component_count(), builder.roadmap().component_count());
}

TEST(RoadmapLog, ACrashAtAnyByteRecoversExactlyTheCommittedBatches) {
  const Scene& scene = test::shared_scene("water_tower");
  SparsBuilder builder(scene, BuildOptions{}, true);
  const auto batches = build_batches(builder, 3);
  const test::TempDir dir;
  const auto full = dir.path() / "full.log";
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
  const auto cut = dir.path() / "cut.log";
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
    Roadmap replica(scene.pois().size());
    for (const auto& b : replay.batches) apply_batch(replica, b);
    ASSERT_EQ(replica.version(), expected == 0 ? 0 : batches[expected - 1].to_version);
  }
}

TEST(RoadmapLog, ReopeningCutsATornTailAndAppendsAfterIt) {
  const Scene& scene = test::shared_scene("water_tower");
  SparsBuilder builder(scene, BuildOptions{}, true);
  const auto batches = build_batches(builder, 2);
  const test::TempDir dir;
  const auto path = dir.path() / "roadmap.log";
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

TEST(RoadmapLog, CorruptionInTheMiddleStopsTheReplayThere) {
  const Scene& scene = test::shared_scene("water_tower");
  SparsBuilder builder(scene, BuildOptions{}, true);
  const auto batches = build_batches(builder, 3);
  const test::TempDir dir;
  const auto path = dir.path() / "roadmap.log";
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

TEST(RoadmapLog, NotALogAndGapsAreRefused) {
  const test::TempDir dir;
  const auto path = dir.write("other.txt", "hello, this is not a roadmap log");
  EXPECT_THROW((void)read_roadmap_log(path), std::runtime_error);
  EXPECT_TRUE(read_roadmap_log(dir.path() / "missing.log").batches.empty());
  const Scene& scene = test::shared_scene("water_tower");
  SparsBuilder builder(scene, BuildOptions{}, true);
  const auto batches = build_batches(builder, 2);
  Roadmap replica(scene.pois().size());
  EXPECT_THROW(apply_batch(replica, batches[1]), std::runtime_error);  // skips batch 0
  apply_batch(replica, batches[0]);
  EXPECT_THROW(apply_batch(replica, batches[0]), std::runtime_error);  // a duplicate
  EXPECT_THROW((void)decode_batch(encode_batch(batches[1]) + "x"), std::runtime_error);
  EXPECT_THROW((void)decode_batch(encode_batch(batches[1]).substr(0, 30)), std::runtime_error);
}

}  // namespace
}  // namespace ispars
