// What an operator does to a running daemon: signals, restarts after unloading.

#include <signal.h>

#include <chrono>
#include <thread>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

TEST_F(ServiceTest, SighupNeitherStopsTheDaemonNorDisturbsItsRequests) {
  auto daemon = start("d");
  Client c(client_options(domain_));
  c.load("s0");
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(::kill(daemon->pid(), SIGHUP), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_TRUE(daemon->alive());
    EXPECT_EQ(c.stats("s0").scene(), "s0");
  }
  EXPECT_NE(daemon->log().find("SIGHUP: still serving"), std::string::npos);
  EXPECT_EQ(daemon->terminate(), 0) << "SIGTERM still stops it cleanly";
}

// An unloaded scene stays unloaded after a restart (its stored roadmap kept), and a load brings
// the roadmap back; a scene never unloaded is reloaded at start as before.
TEST_F(ServiceTest, AnUnloadSurvivesARestartAndALoadBringsTheRoadmapBack) {
  std::uint64_t vertices = 0;
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    for (const char* s : {"s0", "s1"}) {
      c.load(s);
      c.build(s, ispars_build(1200));
      c.wait_idle(s, {}, kLong);
    }
    vertices = c.stats("s0").vertices();
    c.unload("s0");
    ASSERT_EQ(daemon->terminate(), 0);
  }
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    const auto list = c.list_scenes();
    for (const auto& e : list) {
      if (e.name() == "s0") {
        EXPECT_FALSE(e.loaded()) << "an unloaded scene was reloaded at start";
      }
      if (e.name() == "s1") {
        EXPECT_TRUE(e.loaded()) << "a loaded scene was not reloaded at start";
      }
    }
    c.load("s0");
    EXPECT_EQ(c.stats("s0").vertices(), vertices);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  auto daemon = start("d");
  Client c(client_options(domain_));
  EXPECT_EQ(c.stats("s0").vertices(), vertices) << "loaded again, it is reloaded at start again";
}

}  // namespace
}  // namespace ispars::test
