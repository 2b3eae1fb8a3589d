// Storage that fails loudly, with real daemons: damage beyond a torn tail is reported with the
// file and the offset, left untouched, and does not stop the daemon serving other scenes.

#include <fstream>
#include <sstream>

#include "integration/service_fixture.hpp"
#include "ispars/roadmap/record_file.hpp"

namespace ispars::test {
namespace {

std::string bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(ServiceTest, ACorruptJournalMiddleFailsItsSceneLoudlyAndTheOthersServe) {
  const std::vector<std::string> no_compaction = {"--compact-every", "100000"};
  std::uint64_t s1_vertices = 0;
  {
    auto daemon = start("d", no_compaction);
    Client c(client_options(domain_));
    for (const char* s : {"s0", "s1"}) {
      c.load(s);
      c.build(s, ispars_build(3000));
      c.wait_idle(s, {}, kLong);
    }
    s1_vertices = c.stats("s1").vertices();
    ASSERT_EQ(daemon->terminate(), 0);
  }
  const auto journal = dir_.path() / "data-d" / "s0" / "journal.log";
  const RecordReplay intact = read_record_file(journal, "ISPJRN01", [](const std::string&) { return std::string(); });
  ASSERT_GE(intact.payloads.size(), 3u) << "the build committed too few chunks for a middle";
  std::string damaged = bytes_of(journal);
  const std::size_t second = 8 + 8 + intact.payloads[0].size();  // the second commit's header
  damaged[second + 8 + intact.payloads[1].size() / 2] ^= 0x01;
  std::ofstream(journal, std::ios::binary | std::ios::trunc) << damaged;

  auto daemon = start("d", no_compaction);
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state(), msg::SCENE_FAILED);
  EXPECT_NE(s0.last_error().find("journal.log is damaged at byte " + std::to_string(second) + " (commit 2)"),
            std::string::npos)
      << s0.last_error();
  EXPECT_EQ(c.stats("s1").vertices(), s1_vertices) << "another scene stopped serving";
  try {
    c.build("s0", ispars_build(1000));
    FAIL() << "a build without replace went over a damaged store";
  } catch (const ClientError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
  }
  EXPECT_EQ(bytes_of(journal), damaged) << "the damaged journal was changed";
  EXPECT_TRUE(daemon->alive());
}

}  // namespace
}  // namespace ispars::test
