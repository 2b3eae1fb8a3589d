// The service's scene registry (SceneRegistry): a name is reserved once, whatever the threads;
// a load that fails frees its name; a session added is found, listed and erased by name.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "ispars/params/input_error.hpp"
#include "ispars/service/scene_registry.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

class SceneRegistryTest : public ::testing::Test {
 protected:
  std::shared_ptr<RoadmapSession> session(const std::string& name) {
    return std::make_shared<RoadmapSession>(name, test::shared_scene("demo_tank_tower"), dir_.path() / name,
                                            SessionLimits{}, SessionCallbacks{});
  }
  test::TempDir dir_;
  SceneRegistry registry_;
};

TEST_F(SceneRegistryTest, ANameIsReservedByOneLoadAmongManyThreads) {
  std::atomic<int> reserved{0}, refused{0};
  std::vector<std::unique_ptr<SceneRegistry::Reservation>> held(8);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < held.size(); ++i) {
    threads.emplace_back([&, i] {
      try {
        held[i] = registry_.reserve("tower");
        ++reserved;
      } catch (const params::InputError& e) {
        EXPECT_EQ(e.field(), "scene");
        ++refused;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(reserved.load(), 1);
  EXPECT_EQ(refused.load(), 7);
  EXPECT_EQ(registry_.held_or_loading(), std::vector<std::string>{"tower"}) << "a reserved name is left to scrub";
  EXPECT_TRUE(registry_.names().empty()) << "a reserved name is listed as loaded";
  EXPECT_EQ(registry_.find("tower"), nullptr);
}

TEST_F(SceneRegistryTest, AFailedLoadFreesItsNameAndAnAddedSessionKeepsIt) {
  { auto failed = registry_.reserve("tower"); }  // the load threw before it added a session
  auto r = registry_.reserve("tower");
  const auto s = session("tower");
  r->add(s);
  r.reset();
  EXPECT_EQ(registry_.find("tower"), s) << "the reservation's end took the added session's name away";
  EXPECT_THROW((void)registry_.reserve("tower"), params::InputError) << "a loaded scene was reserved again";
  EXPECT_EQ(registry_.names(), std::vector<std::string>{"tower"});
  ASSERT_EQ(registry_.sessions().size(), 1u);
  registry_.erase("tower");
  registry_.erase("tower");  // twice: nothing to forget
  EXPECT_EQ(registry_.find("tower"), nullptr);
  EXPECT_TRUE(registry_.held_or_loading().empty());
  EXPECT_NO_THROW((void)registry_.reserve("tower"));
  EXPECT_EQ(s.use_count(), 1) << "the registry kept an erased session";
}

TEST_F(SceneRegistryTest, NamesAreListedInOrderWithTheLoadsUnderWay) {
  for (const char* name : {"silo", "bridge", "tower"}) {
    auto r = registry_.reserve(name);
    r->add(session(name));
  }
  const auto loading = registry_.reserve("dam");
  EXPECT_EQ(registry_.names(), (std::vector<std::string>{"bridge", "silo", "tower"}));
  std::vector<std::string> held = registry_.held_or_loading();
  std::sort(held.begin(), held.end());
  EXPECT_EQ(held, (std::vector<std::string>{"bridge", "dam", "silo", "tower"}));
}

}  // namespace
}  // namespace ispars::service
