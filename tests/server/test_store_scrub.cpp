// StoreScrub, the background check of stored copies: a bit flipped in a record of a store no
// session holds is found and named (file and byte) without opening the store, the files are left
// as they are, a healthy copy has no problem, a held store is never judged, and a read that does
// not fit the memory budget waits.

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "ispars/service/roadmap_service.hpp"
#include "ispars/service/store_scrub.hpp"
#include "server/service_waits.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

using namespace std::chrono_literals;
using test::eventually;

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class StoreScrubTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_.path() / "scenes");
    std::ofstream(dir_.path() / "scenes" / "s0.yaml") << "procedural: {kind: tank_tower, seed: 1}\n";
    ServiceSettings s;  // a service that builds s0's store and stops
    s.server_id = "unit";
    s.scene_dir = dir_.path() / "scenes";
    s.data_dir = data();
    RoadmapService service(s, {});
    (void)service.load("s0");
    BuildRequest r;
    r.samples = 600;
    service.build("s0", r);
    ASSERT_EQ(test::wait_idle(service, "s0").samples_done, 600u);
  }
  [[nodiscard]] std::filesystem::path data() const { return dir_.path() / "data"; }
  // A scrub of data() over `budget` bytes; `held` are the scenes a session holds.
  std::unique_ptr<StoreScrub> scrub(std::vector<std::string> held = {}, double budget = 1e18) const {
    return std::make_unique<StoreScrub>(
        data(), [held] { return held; }, MemoryBudget::make(budget), 10ms);
  }
  // Waits for two more passes: one that started after now has ended.
  static void two_passes(const StoreScrub& s) {
    const auto from = s.passes();
    ASSERT_TRUE(eventually([&] { return s.passes() >= from + 2; }, 10s, "two passes", 1ms));
  }
  // Flips one bit in the middle of journal.log's records.
  void flip_journal() const {
    const auto file = data() / "s0" / "journal.log";
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    const auto at = static_cast<std::streamoff>(std::filesystem::file_size(file) / 2);
    char byte = 0;
    f.seekg(at);
    f.read(&byte, 1);
    byte = static_cast<char>(byte ^ 0x10);
    f.seekp(at);
    f.write(&byte, 1);
  }
  test::TempDir dir_;
};

TEST_F(StoreScrubTest, AFlippedBitInAStoredCopyIsNamedAndLeftAsItIs) {
  const auto s = scrub();
  two_passes(*s);
  EXPECT_EQ(s->problem("s0"), "") << "a healthy copy";
  flip_journal();
  const std::string flipped = bytes_of(data() / "s0" / "journal.log");
  ASSERT_TRUE(eventually([&] { return !s->problem("s0").empty(); }, 10s, "the scrub finds the flipped bit"));
  const std::string problem = s->problem("s0");
  EXPECT_NE(problem.find((data() / "s0" / "journal.log").string() + " is damaged at byte"), std::string::npos)
      << problem;
  EXPECT_EQ(bytes_of(data() / "s0" / "journal.log"), flipped) << "the scrub wrote to the store";
  // The listing names it, and offers no copy of it.
  const StoredListing listing =
      list_stored_roadmaps(data(), {}, nullptr, [&](const std::string& scene) { return s->problem(scene); });
  ASSERT_EQ(listing.unservable.size(), 1u);
  EXPECT_NE(listing.unservable[0].why.find("its stored roadmap is damaged: " + problem), std::string::npos);
  EXPECT_TRUE(listing.served.empty());
}

TEST_F(StoreScrubTest, AHeldStoreIsNeverJudgedAndAReadThatDoesNotFitWaits) {
  flip_journal();
  const auto held = scrub({"s0"});
  two_passes(*held);
  EXPECT_EQ(held->problem("s0"), "") << "a store a session holds is the session's";
  const auto tight = scrub({}, 1000.0);  // less than the journal
  two_passes(*tight);
  EXPECT_EQ(tight->problem("s0"), "") << "read beyond the memory budget";
  const auto roomy = scrub();
  ASSERT_TRUE(eventually([&] { return !roomy->problem("s0").empty(); }, 10s, "the scrub finds the flipped bit"));
}

TEST_F(StoreScrubTest, AServiceWithTheCheckOnNamesTheDamageOfAStoreItDoesNotHold) {
  flip_journal();
  ServiceSettings s;
  s.server_id = "unit";
  s.scene_dir = dir_.path() / "scenes";
  s.data_dir = data();
  s.scrub_period = 10ms;
  RoadmapService service(s, {});
  ASSERT_TRUE(eventually([&] { return !service.scrub_problem("s0").empty(); }, 10s, "the service's scrub finds it"));
  EXPECT_NE(service.scrub_problem("s0").find("journal.log is damaged at byte"), std::string::npos);
}

}  // namespace
}  // namespace ispars::service
