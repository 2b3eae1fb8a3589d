// The snapshot cache: one encoding per version, kept for the chunks that follow and leased while
// kept; a stale version, a chunk past the last and a stopped encoding refused by name.

#include "ispars/service/snapshot_cache.hpp"

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "server/service_waits.hpp"
#include "server/unit_service.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

class SnapshotCacheTest : public ::testing::Test {
 protected:
  void SetUp() override { service_ = test::service_with_s0(dir_.path(), 800); }
  static std::string error_of(const std::function<void()>& f) {
    try {
      f();
    } catch (const params::InputError& e) {
      return e.what();
    }
    return "no error";
  }
  test::TempDir dir_;
  std::unique_ptr<RoadmapService> service_;
  std::shared_ptr<MemoryBudget> budget_ = MemoryBudget::make(1e12);
  bool go_on_ = true;
  SnapshotCache cache_{budget_, [this] { return go_on_; }};
};

TEST_F(SnapshotCacheTest, AVersionIsEncodedOnceAndLeasedWhileKept) {
  const auto session = service_->session("s0");
  const SnapshotSlice latest = cache_.slice(*session, "s0", 0, 0, 0, 0);
  EXPECT_EQ(latest.version, session->published().roadmap->version());
  EXPECT_EQ(latest.chunk_count, 1u);
  EXPECT_EQ(latest.end, latest.encoded->size());
  EXPECT_EQ(cache_.kept(), 1u);
  EXPECT_DOUBLE_EQ(budget_->leased(), static_cast<double>(latest.encoded->size()));  // shrunk to its size
  // The same version again (a later chunk, another client): the same bytes, not a new encoding.
  const SnapshotSlice again = cache_.slice(*session, "s0", latest.version, latest.generation, 0, latest.poi_count);
  EXPECT_EQ(again.encoded.get(), latest.encoded.get());
  EXPECT_EQ(cache_.kept(), 1u);
  cache_.drop_all();  // the budget's reclaimer
  EXPECT_EQ(cache_.kept(), 0u);
}

TEST_F(SnapshotCacheTest, AStaleVersionAChunkPastTheLastAndAStoppedEncodingAreRefused) {
  const auto session = service_->session("s0");
  const SnapshotSlice latest = cache_.slice(*session, "s0", 0, 0, 0, 0);
  EXPECT_NE(error_of([&] {
              (void)cache_.slice(*session, "s0", latest.version, latest.generation + 1, 0, 0);
            }).find("request: snapshot_version: version"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              (void)cache_.slice(*session, "s0", latest.version, latest.generation, 1, 0);
            }).find("request: chunk_index: 1 is past the last chunk (0)"),
            std::string::npos);
  cache_.drop_all();
  go_on_ = false;  // the daemon is stopping: a new encoding stops at its next slice
  EXPECT_NE(error_of([&] { (void)cache_.slice(*session, "s0", 0, 0, 0, 0); }).find("was stopped"), std::string::npos);
  EXPECT_EQ(cache_.kept(), 0u);
}

TEST_F(SnapshotCacheTest, LeasesAreGivenBackWhenTheBytesGo) {
  const auto session = service_->session("s0");
  {
    const SnapshotSlice latest = cache_.slice(*session, "s0", 0, 0, 0, 0);
    EXPECT_GT(budget_->leased(), 0.0);
    cache_.drop_all();
    EXPECT_GT(budget_->leased(), 0.0);  // the slice still holds the bytes
  }
  EXPECT_DOUBLE_EQ(budget_->leased(), 0.0);
}

}  // namespace
}  // namespace ispars::service
