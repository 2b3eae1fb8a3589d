// ispars2 through the daemon: no dense graph is built, stored or reported; verify checks
// Invariant 1 on the samples the build drew, drawn again, and says so; a variant is refused by
// name; and after a restart (SIGTERM or kill -9) an extend goes on from the stored roadmap
// without replaying it, to the roadmap an uninterrupted build gives, byte for byte (as it does
// for the Dense method).

#include <gtest/gtest.h>

#include <string>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

BuildArgs ispars2_build(std::uint64_t samples, std::uint64_t seed = 1) {
  BuildArgs a;
  a.method = BuildMethod::ispars2;
  a.samples = samples;
  a.seed = seed;
  return a;
}

TEST_F(ServiceTest, Ispars2KeepsNoDenseGraphAndGoesOnAfterARestartWithoutReplay) {
  auto daemon = start("d");
  {
    Client client(client_options(domain_));
    client.load("s0");
    BuildArgs with_variant = ispars2_build(100);
    with_variant.variant = SparsVariant::alg1;
    try {
      client.build("s0", with_variant);
      ADD_FAILURE() << "a variant for ispars2 was accepted";
    } catch (const ClientError& e) {
      EXPECT_NE(std::string(e.what()).find("'alg1' given, but ispars2 has no rule-set variants"), std::string::npos)
          << e.what();
    }
    EXPECT_TRUE(client.stats("s0").method.empty()) << "the refused build changed the scene";
    client.build("s0", ispars2_build(3000));
    const SceneStatus built = client.wait_idle("s0", {}, kLong);
    ASSERT_EQ(built.state, SceneState::idle) << built.last_error;
    EXPECT_EQ(built.method, "ispars2");
    EXPECT_EQ(built.dense_vertices, 0u);
    EXPECT_EQ(built.dense_edges, 0u);
    EXPECT_GT(built.vertices, 10u);
    // The same sparse roadmap as ispars's, which keeps the dense graph it never reads.
    EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 3000, 1));
    const auto verified = client.verify("s0");
    EXPECT_EQ(verified.verify.violations, 0u) << verified.message;
    EXPECT_NE(verified.message.find("0 of the 3000 samples the build drew (drawn again) have one"), std::string::npos)
        << verified.message;
  }
  ASSERT_EQ(daemon->terminate(), 0);
  daemon = start("d");
  {
    Client client(client_options(domain_));
    client.load("s0");
    client.extend("s0", 2000);
    const SceneStatus extended = client.wait_idle("s0", {}, kLong);
    ASSERT_EQ(extended.samples_done, 5000u) << extended.last_error;
    EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap),
              reference_digest(scene_dir_ / "s0.yaml", 5000, 1, BuildMethod::ispars2));
  }
  const std::string log = daemon->log();
  EXPECT_NE(log.find("the ispars2 builder resumed from its stored roadmaps at 3000 samples"), std::string::npos) << log;
  // kill -9 in the middle of an extend: the restart recovers the last commit, and goes on from it.
  {
    Client client(client_options(domain_));
    client.extend("s0", 400000);
    (void)eventually([&] { return client.stats("s0").samples_done >= 6000; }, std::chrono::seconds(4),
                     "the extend passes 6,000 samples");
  }
  daemon->kill9();
  daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  (void)client.cancel("s0");  // the resumed extend: what is checked is what the kill left
  const SceneStatus recovered = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(recovered.state, SceneState::idle) << recovered.last_error;
  ASSERT_GE(recovered.samples_done, 5000u);
  const std::uint64_t target = recovered.samples_done + 1000;
  client.extend("s0", 1000);
  const SceneStatus done = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(done.samples_done, target) << done.last_error;
  EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap),
            reference_digest(scene_dir_ / "s0.yaml", target, 1, BuildMethod::ispars2));
}

}  // namespace
}  // namespace ispars::test

namespace ispars::test {
namespace {

// The roadmap an uninterrupted in-process ispars2 build with `slack` from sample 1000 on gives.
std::uint64_t slack_reference(const std::filesystem::path& scene_file, std::uint64_t samples, double slack) {
  return reference_digest(scene_file, samples, 1, BuildMethod::ispars2, slack, slack > 0.0 ? 1000 : 0);
}

// stretch_slack and the sample it starts from travel with the recipe: the daemon builds with them,
// reports them, stores them, and after a restart goes on with them (resumed, not replayed) to the
// uninterrupted build's roadmap.
TEST_F(ServiceTest, AStretchSlackIsBuiltReportedStoredAndKeptAfterARestart) {
  auto daemon = start("d");
  {
    Client client(client_options(domain_));
    client.load("s0");
    BuildArgs args = ispars2_build(3000);
    args.overrides.stretch_slack = 0.5;
    args.overrides.stretch_slack_after = 1000;
    client.build("s0", args);
    const SceneStatus built = client.wait_idle("s0", {}, kLong);
    ASSERT_EQ(built.state, SceneState::idle) << built.last_error;
    EXPECT_EQ(built.stretch_slack, 0.5);
    EXPECT_EQ(built.stretch_slack_after, 1000u);
    EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), slack_reference(scene_dir_ / "s0.yaml", 3000, 0.5));
    EXPECT_NE(roadmap_digest(client.snapshot("s0").roadmap), slack_reference(scene_dir_ / "s0.yaml", 3000, 0.0))
        << "the slack changed nothing on this scene: the test would prove nothing";
  }
  ASSERT_EQ(daemon->terminate(), 0);
  daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  EXPECT_EQ(client.stats("s0").stretch_slack, 0.5);
  EXPECT_EQ(client.stats("s0").stretch_slack_after, 1000u);
  client.extend("s0", 2000);
  const SceneStatus extended = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(extended.samples_done, 5000u) << extended.last_error;
  EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), slack_reference(scene_dir_ / "s0.yaml", 5000, 0.5));
}

}  // namespace
}  // namespace ispars::test

namespace ispars::test {
namespace {

// The Dense method's roadmap is its whole state too, and the dense pair's are its sparse and
// dense roadmaps: after a restart (SIGTERM for one, kill -9 for the other) an extend resumes from
// the stored roadmaps, nothing replayed, to the uninterrupted build's roadmap byte for byte.
TEST_F(ServiceTest, ADenseOrDensePairRoadmapGoesOnAfterARestartWithoutReplay) {
  for (const BuildMethod method : {BuildMethod::dense, BuildMethod::ispars}) {
    const std::string name(to_string(method));
    SCOPED_TRACE(name);
    auto daemon = start("d");
    {
      Client client(client_options(domain_));
      client.load("s0");
      BuildArgs args;
      args.method = method;
      args.samples = 2000;
      args.replace = method != BuildMethod::dense;
      client.build("s0", args);
      ASSERT_EQ(client.wait_idle("s0", {}, kLong).state, SceneState::idle);
    }
    if (method == BuildMethod::dense) {
      ASSERT_EQ(daemon->terminate(), 0);
    } else {
      daemon->kill9();
    }
    daemon = start("d");
    Client client(client_options(domain_));
    client.load("s0");
    client.extend("s0", 1000);
    const SceneStatus extended = client.wait_idle("s0", {}, kLong);
    ASSERT_EQ(extended.samples_done, 3000u) << extended.last_error;
    EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 3000, 1, method));
    const std::string log = daemon->log();
    EXPECT_NE(log.find("the " + name + " builder resumed from its stored roadmaps at 2000 samples"), std::string::npos)
        << log;
    if (method == BuildMethod::ispars) {
      EXPECT_EQ(client.verify("s0").verify.violations, 0u) << "Invariant 1 on the resumed dense pair";
    }
    ASSERT_EQ(daemon->terminate(), 0);
  }
}

}  // namespace
}  // namespace ispars::test
