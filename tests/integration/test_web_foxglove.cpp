// ispars-web speaking the Foxglove WebSocket protocol (client/web/src/foxglove_session.cpp), as
// @foxglove/ws-protocol's own client speaks it: the subprotocol negotiated, the server's info
// and the roadmap channel advertised, every message a valid foxglove.SceneUpdate (ajv with
// @foxglove/schemas), and the replayed updates the roadmap `stats` reports. A bad request is
// answered with a status; a page of another origin is refused as the viewer's is.

#include <nlohmann/json.hpp>

#include "integration/service_fixture.hpp"
#include "integration/test_web_support.hpp"

namespace ispars::test {
namespace {

using WebFoxgloveTest = ServiceTest;

TEST_F(WebFoxgloveTest, AFoxgloveClientReplaysTheRoadmapStatsReports) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  const SceneStatus built = load_and_build(client, "s0", ispars_build(3000));
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log", {});
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const std::string url = "ws://127.0.0.1:" + std::to_string(gateway.port()) + "/ws?scene=s0";
  const auto [status, output] =
      run_command("NODE_PATH='" + std::string(ISPARS_READERS_NODE_MODULES) + "' timeout -k 5 120 node '" +
                  ISPARS_READERS_DIR + "/foxglove_client.cjs' '" + url + "' " + std::to_string(built.vertices) + " " +
                  std::to_string(built.edges) + " 60 2>&1");
  ASSERT_EQ(status, 0) << output << gateway.log();
  const nlohmann::json seen = nlohmann::json::parse(output);
  EXPECT_EQ(seen["server"], "ispars-web");
  ASSERT_EQ(seen["channels"].size(), 1u) << output;
  EXPECT_EQ(seen["channels"][0]["topic"], "/ispars/s0/roadmap");
  EXPECT_EQ(seen["channels"][0]["schemaName"], "foxglove.SceneUpdate");
  EXPECT_EQ(seen["channels"][0]["schemaEncoding"], "jsonschema");
  EXPECT_EQ(seen["invalid"], 0) << "every message a valid foxglove.SceneUpdate";
  EXPECT_EQ(seen["spheres"], built.vertices);
  EXPECT_EQ(seen["edges"], built.edges);
  ASSERT_GE(seen["statuses"].size(), 1u);
  EXPECT_NE(seen["statuses"][0].get<std::string>().find("'publish' is not supported"), std::string::npos) << output;
  {
    RawWebSocket foreign(gateway.port(), "/ws?scene=s0",
                         "Origin: http://evil.example\r\nSec-WebSocket-Protocol: foxglove.websocket.v1\r\n");
    EXPECT_EQ(foreign.status(), "HTTP/1.1 403 Forbidden");
  }
  EXPECT_EQ(gateway.stop(), 0);
}

}  // namespace
}  // namespace ispars::test
