// A client of another DDS vendor: ispars-cyclone (tests/vendor/), written with Eclipse Cyclone DDS's C
// API on types that Cyclone's strict idlc made from the unmodified idl/ispars.idl, against a real
// isparsd on Fast DDS. It reads a scene's status as a late joiner, the roadmap's updates, STATS
// and a tour with its progress, all equal to what the C++ client sees; and 100 new clients in a
// row each get the reply to their first request, sent once (no resend), within 2 s.

#include <nlohmann/json.hpp>

#include <string>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

using nlohmann::json;

class VendorTest : public ServiceTest {
 protected:
  // Runs `ispars-cyclone DOMAIN ARGS` (killed after `limit_s`): its JSON, or a failure naming its
  // exit status and standard error.
  json cyclone(const std::string& args, int limit_s = 120) {
    const auto err = dir_.path() / "cyclone.err";
    const std::string command = "timeout -k 5 " + std::to_string(limit_s) + " '" + std::string(ISPARS_CYCLONE) + "' " +
                                std::to_string(domain_) + " " + args + " 2>'" + err.string() + "'";
    const auto [code, out] = run_command(command);
    const std::string errors = read_text(err);
    if (!errors.empty()) std::printf("ispars-cyclone %s (stderr):\n%s", args.c_str(), errors.c_str());
    if (code != 0) {
      ADD_FAILURE() << "ispars-cyclone " << args << " exited with " << code << ": " << errors;
      return json();
    }
    try {
      return json::parse(out);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "ispars-cyclone " << args << " printed no JSON (" << e.what() << "): " << out;
      return json();
    }
  }

  // Daemon "d" holding scene s0 with a small roadmap built by the C++ client: its status.
  SceneStatus built_scene(Client& client) {
    client.load("s0");
    client.build("s0", ispars_build(2000));
    return client.wait_idle("s0", {}, kLong);
  }
};

void expect_status_equal(const json& seen, const SceneStatus& stats) {
  ASSERT_TRUE(seen.is_object());
  EXPECT_EQ(seen["scene"], "s0");
  EXPECT_EQ(seen["status_server_id"], stats.server_id);
  // The Cyclone client prints the wire's enum value.
  EXPECT_EQ(client::from_message(static_cast<msg::SceneState>(seen["state"].get<int>())), stats.state);
  EXPECT_EQ(seen["generation"], stats.generation);
  EXPECT_EQ(seen["samples_done"], stats.samples_done);
  EXPECT_EQ(seen["version"], stats.version);
  EXPECT_EQ(seen["vertices"], stats.vertices);
  EXPECT_EQ(seen["edges"], stats.edges);
  EXPECT_EQ(seen["components"], stats.components);
}

TEST_F(VendorTest, ACycloneClientReadsStatusUpdatesStatsAndATourWithProgress) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  const SceneStatus built = built_scene(client);
  ASSERT_EQ(built.state, SceneState::idle);
  const SceneStatus stats = client.stats("s0");
  ASSERT_GT(stats.vertices, 0u);

  const json status = cyclone("status s0");
  expect_status_equal(status, stats);

  const json updates = cyclone("updates s0");
  ASSERT_TRUE(updates.is_object());
  EXPECT_EQ(updates["version"], stats.version);
  EXPECT_EQ(updates["vertices"], stats.vertices);
  EXPECT_EQ(updates["edges"], stats.edges);

  const json answered = cyclone("stats d s0");
  expect_status_equal(answered, stats);
  if (answered.is_object()) {
    EXPECT_EQ(answered["server_id"], "d");
    std::printf("cyclone STATS: %.3f ms, %d send(s)\n", answered["latency_ms"].get<double>(),
                answered["sends"].get<int>());
  }

  // A new client whose first request is the tour: its progress from that request on.
  const json tour = cyclone("tour d s0 2");
  ASSERT_TRUE(tour.is_object());
  std::printf("cyclone tour: %s\n", tour.dump().c_str());
  EXPECT_GE(tour["progress"].get<int>(), 1) << "no tour progress reached the client of another vendor";
  EXPECT_TRUE(tour["valid"].get<bool>());
  EXPECT_GT(tour["covered"].get<unsigned>(), 0u);
  EXPECT_GT(tour["cost"].get<double>(), 0.0);
  EXPECT_EQ(tour["version"], stats.version);
}

TEST_F(VendorTest, AHundredFreshCycloneClientsLoseNoFirstReply) {
  constexpr int kClients = 100;
  auto daemon = start("d");
  Client client(client_options(domain_));
  ASSERT_EQ(built_scene(client).state, SceneState::idle);
  const json fresh = cyclone("fresh " + std::to_string(kClients) + " d s0", 540);
  ASSERT_TRUE(fresh.is_object());
  std::printf("cyclone fresh clients: %s\n", fresh.dump().c_str());
  EXPECT_EQ(fresh["clients"], kClients);
  EXPECT_EQ(fresh["lost"], 0) << "first replies lost (one STATS each, sent once, 2 s wait)";
  EXPECT_EQ(fresh["answered"], kClients);
  if (fresh.contains("latency_ms")) {
    const json& l = fresh["latency_ms"];
    std::printf("first reply latency over %d answered of %d: min %.2f ms, median %.2f ms, p95 %.2f ms, max %.2f ms\n",
                fresh["answered"].get<int>(), kClients, l["min"].get<double>(), l["median"].get<double>(),
                l["p95"].get<double>(), l["max"].get<double>());
  }
}

}  // namespace
}  // namespace ispars::test
