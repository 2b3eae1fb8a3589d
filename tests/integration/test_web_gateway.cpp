// Who may use the live viewer's gateway (client/web/README.md): a page of another origin cannot
// open its WebSocket (in headless Chromium and as a raw upgrade), a DNS-rebinding Host is refused,
// with a token every peer needs it (off loopback in a network namespace, and on loopback, as
// behind a TLS proxy), idle connections cannot lock users out, tours are bounded per gateway,
// and a scene no browser watches stops being followed.

#include <nlohmann/json.hpp>

#include <csignal>
#include <fstream>
#include <set>
#include <thread>

#include "integration/service_fixture.hpp"
#include "integration/test_web_support.hpp"
#include "support/netns_lab.hpp"

namespace ispars::test {
namespace {

using WebGatewayTest = ServiceTest;

std::string origin_header(const std::string& origin) { return "Origin: " + origin + "\r\n"; }

// Raw requests, as a page of another origin, a rebinding name, curl and the page itself send them.
TEST_F(WebGatewayTest, AForeignOriginAndARebindingHostAreRefusedTheGatewaysOwnLetIn) {
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log", {"--allow-origin", "https://viewer.example:8443"});
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const int port = gateway.port();
  const std::string own = "http://127.0.0.1:" + std::to_string(port);
  {
    RawWebSocket foreign(port, "/ws?scene=s0", origin_header("http://evil.example"));
    EXPECT_EQ(foreign.status(), "HTTP/1.1 403 Forbidden");
    EXPECT_EQ(foreign.body(), "origin http://evil.example is not allowed (see --allow-origin)\n");
  }
  for (const std::string& origin :
       {own, "http://localhost:" + std::to_string(port), std::string("https://viewer.example:8443")}) {
    RawWebSocket allowed(port, "/ws?scene=s0", origin_header(origin));
    EXPECT_EQ(allowed.status(), "HTTP/1.1 101 Switching Protocols") << origin << ": " << allowed.body();
  }
  // The same origin on another port, or another scheme, is another origin.
  for (const std::string& origin :
       {std::string("http://127.0.0.1:1"), "https://127.0.0.1:" + std::to_string(port), std::string("null")}) {
    RawWebSocket other(port, "/ws?scene=s0", origin_header(origin));
    EXPECT_EQ(other.status(), "HTTP/1.1 403 Forbidden") << origin;
  }
  const auto api = http_get(port, "/api/scenes", origin_header("http://evil.example"));
  EXPECT_EQ(api.first, "HTTP/1.1 403 Forbidden");
  EXPECT_NE(api.second.find("origin http://evil.example is not allowed"), std::string::npos) << api.second;
  // DNS rebinding: a name the attacker controls, pointed at 127.0.0.1.
  for (const char* path : {"/api/scenes", "/api/mesh/s0", "/"}) {
    const auto rebound = http_get(port, path, "", "rebind.example:" + std::to_string(port));
    EXPECT_EQ(rebound.first, "HTTP/1.1 421 Misdirected Request") << path;
    EXPECT_NE(rebound.second.find("host rebind.example:" + std::to_string(port) + " is not this gateway"),
              std::string::npos)
        << rebound.second;
  }
  EXPECT_EQ(http_get(port, "/", "", "localhost").first, "HTTP/1.1 421 Misdirected Request") << "another port (80)";
  // No Origin (curl, the page's own files) with the gateway's Host: served.
  EXPECT_EQ(http_get(port, "/").first, "HTTP/1.1 200 OK");
  EXPECT_EQ(http_get(port, "/app.js", "", "localhost:" + std::to_string(port)).first, "HTTP/1.1 200 OK");
  EXPECT_EQ(http_get(port, "/app.js", origin_header(own)).first, "HTTP/1.1 200 OK");
  EXPECT_EQ(gateway.stop(), 0);
  EXPECT_NE(gateway.log().find("9 requests refused by Host, Origin or token"), std::string::npos) << gateway.log();
}

// A real page of another origin, in headless Chromium, opens ws://127.0.0.1:PORT/ws: refused;
// the same page is let in once its origin is named by --allow-origin.
TEST_F(WebGatewayTest, APageOfAnotherOriginCannotOpenTheWebSocket) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium")) << "Debian's chromium (deploy/install-deps.sh installs it)";
  const int page_port = free_port();
  const std::string page_origin = "http://127.0.0.1:" + std::to_string(page_port);
  const auto try_page = [&](int gateway_port) {
    const auto out = dir_.path() / "origin.txt";
    const std::string command = "ISPARS_WEB_NODE_MODULES='" + std::string(ISPARS_WEB_NODE_MODULES) +
                                "' timeout -k 5 300 node '" + ISPARS_SOURCE_DIR + "/tests/web/origin_check.mjs' " +
                                std::to_string(gateway_port) + " " + std::to_string(page_port) + " s0 60 > '" +
                                out.string() + "' 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << read_text(out);
    const auto json = nlohmann::json::parse(read_text(out), nullptr, false);
    return json.is_discarded() ? nlohmann::json{{"failure", read_text(out)}} : json;
  };
  {
    Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log");
    ASSERT_GT(gateway.port(), 0) << gateway.log();
    const auto refused = try_page(gateway.port());
    EXPECT_EQ(refused.value("ws", ""), "refused") << refused;
    EXPECT_EQ(refused.value("origin", ""), page_origin) << refused;
    EXPECT_EQ(gateway.stop(), 0);
    EXPECT_NE(gateway.log().find(" 1 requests refused by Host, Origin or token"), std::string::npos) << gateway.log();
  }
  Gateway allowing(domain_, scene_dir_, dir_.path() / "web-allowing.log", {"--allow-origin", page_origin});
  ASSERT_GT(allowing.port(), 0) << allowing.log();
  const auto opened = try_page(allowing.port());
  EXPECT_EQ(opened.value("ws", ""), "open") << opened;
  EXPECT_EQ(allowing.stop(), 0);
  EXPECT_NE(allowing.log().find(" 0 requests refused by Host, Origin or token"), std::string::npos) << allowing.log();
}

// Off loopback, in network namespaces made by the test (nothing reaches the machine's own): a
// gateway refuses to listen without a token; with one, every peer must present it (header, query
// then cookie, or cookie), a peer on loopback too (behind a proxy on the same host every user is).
TEST_F(WebGatewayTest, AGatewayWithATokenNeedsItFromEveryPeer) {
  NetnsLab lab(dir_.path() / "netns", {"gw", "cl"}, std::chrono::seconds(3));
  const std::string address = lab.address("gw");
  const std::string web = std::string(ISPARS_WEB) + " --domain " + std::to_string(domain_) + " --profile-file " +
                          lab.profile("gw").string();
  for (const std::string& listen : {std::string("0.0.0.0:0"), address + ":0"}) {
    const auto refused = lab.run("gw", "timeout 10 " + web + " --listen " + listen);  // 124: it served
    EXPECT_EQ(refused.status, 2) << refused.output;
    EXPECT_NE(refused.output.find("--listen " + listen + " is not a loopback address"), std::string::npos)
        << refused.output;
  }
  const std::string token = "tok-0123456789abcdef-XYZ";
  const auto token_file = dir_.path() / "token";
  std::ofstream(token_file) << token << "\n";
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log",
                  {"--token-file", token_file.string(), "--profile-file", lab.profile("gw").string()}, lab.prefix("gw"),
                  "0.0.0.0:0");
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  EXPECT_EQ(gateway.log().find(token), std::string::npos) << "the token is not printed";
  const std::string url = "http://" + address + ":" + std::to_string(gateway.port());
  const auto code = [&](const std::string& host, const std::string& args) {
    return lab.run(host, "curl -s -o /dev/null -w \"%{http_code}\" " + args).output;
  };
  EXPECT_EQ(code("cl", url + "/"), "401");
  EXPECT_NE(lab.run("cl", "curl -s " + url + "/app.js").output.find("a token is required from " + lab.address("cl")),
            std::string::npos);
  EXPECT_EQ(code("cl", "-H \"Authorization: Bearer tok-0123456789abcdef-XYy\" " + url + "/"), "401");
  EXPECT_EQ(code("cl", "-H \"Cookie: ispars_token=" + token + "x\" " + url + "/"), "401");
  EXPECT_EQ(code("cl", "-H \"Authorization: Bearer " + token + "\" " + url + "/"), "200");
  EXPECT_EQ(code("cl", "-H \"Cookie: a=b; ispars_token=" + token + "\" " + url + "/app.js"), "200");
  // The page opened once as /?token=: the response keeps the token in a cookie for the page's
  // requests and its WebSocket (which a browser cannot give an Authorization header).
  const auto headers = lab.run("cl", "curl -s -D - -o /dev/null \"" + url + "/?token=" + token + "\"").output;
  EXPECT_NE(headers.find("HTTP/1.1 200 OK"), std::string::npos) << headers;
  EXPECT_NE(headers.find("Set-Cookie: ispars_token=" + token + "; Path=/; HttpOnly; SameSite=Strict"),
            std::string::npos)
      << headers;
  const std::string upgrade =
      "curl -s -i --max-time 2 -H \"Origin: " + url +
      "\" -H \"Connection: Upgrade\" -H \"Upgrade: websocket\" -H \"Sec-WebSocket-Version: 13\" "
      "-H \"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\" ";
  EXPECT_EQ(lab.run("cl", upgrade + url + "/ws?scene=s0 | head -1").output, "HTTP/1.1 401 Unauthorized\r\n");
  EXPECT_EQ(
      lab.run("cl", upgrade + "-H \"Cookie: ispars_token=" + token + "\" " + url + "/ws?scene=s0 | head -1").output,
      "HTTP/1.1 101 Switching Protocols\r\n");
  // On the gateway's host: by its own address and by 127.0.0.1 alike.
  const std::string local = "http://127.0.0.1:" + std::to_string(gateway.port()) + "/";
  EXPECT_EQ(code("gw", url + "/"), "401");
  EXPECT_EQ(code("gw", local), "401");
  EXPECT_EQ(code("gw", "-H \"Authorization: Bearer " + token + "\" " + local), "200");
  EXPECT_EQ(gateway.stop(), 0) << gateway.log();
}

// Behind a TLS proxy on the same host (as docs/service.md recommends): every user is a loopback
// peer, the proxy keeps the public Host (no port under https), and the page is https. The token
// is still required, the public Host is the gateway's, the token's cookie is Secure, and idle
// connections cannot lock users out.
TEST_F(WebGatewayTest, BehindATlsProxyTheTokenHoldsAndIdleConnectionsCannotLockUsersOut) {
  const std::string token = "tok-0123456789abcdef-XYZ";
  const auto token_file = dir_.path() / "token";
  std::ofstream(token_file) << token << "\n";
  Gateway gateway(
      domain_, scene_dir_, dir_.path() / "web.log",
      {"--token-file", token_file.string(), "--allow-origin", "https://viewer.example", "--max-browsers", "8"});
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const int port = gateway.port();
  const std::string bearer = "Authorization: Bearer " + token + "\r\n";
  const std::string from_proxy = origin_header("https://viewer.example") + "X-Forwarded-Proto: https\r\n";
  EXPECT_EQ(http_get(port, "/", from_proxy, "viewer.example").first, "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(http_get(port, "/", from_proxy + bearer, "viewer.example").first, "HTTP/1.1 200 OK");
  EXPECT_EQ(http_get(port, "/", from_proxy + bearer, "viewer.example:443").first, "HTTP/1.1 200 OK");
  EXPECT_EQ(http_get(port, "/", bearer, "other.example").first, "HTTP/1.1 421 Misdirected Request");
  // The cookie that keeps the token is Secure when the page came by https, and only then.
  const std::string cookie = "Set-Cookie: ispars_token=" + token + "; Path=/; HttpOnly; SameSite=Strict";
  const std::string by_https = http_response(port, "/?token=" + token, "", "viewer.example");
  EXPECT_NE(by_https.find(cookie + "; Secure\r\n"), std::string::npos) << by_https;
  const std::string forwarded = http_response(port, "/?token=" + token, "X-Forwarded-Proto: https\r\n");
  EXPECT_NE(forwarded.find(cookie + "; Secure\r\n"), std::string::npos) << forwarded;
  const std::string plain = http_response(port, "/?token=" + token);
  EXPECT_NE(plain.find(cookie + "\r\n"), std::string::npos) << plain;
  // 8 connections that never send a request fill the gateway; users are still served (the
  // oldest idle one makes room each time; the gateway accepts in order, so it is full each time).
  std::vector<int> idle;
  for (int i = 0; i < 7; ++i) idle.push_back(connect_local(port));
  for (int i = 0; i < 3; ++i) {
    idle.push_back(connect_local(port));
    EXPECT_EQ(http_get(port, "/app.js", bearer).first, "HTTP/1.1 200 OK") << i;
  }
  for (const int fd : idle) ::close(fd);
  EXPECT_EQ(gateway.stop(), 0);
  EXPECT_NE(gateway.log().find(" 3 idle connections closed to make room"), std::string::npos) << gateway.log();
}

// A page that sends and never reads: each request of about 60 kB draws an error reply that
// echoes it. The gateway closes it once its replies pass twice the queue's bound (64 MB), and its
// memory stays bounded; a page that reads is served throughout.
TEST_F(WebGatewayTest, APageThatSendsAndNeverReadsIsClosedAndMemoryStaysBounded) {
  std::signal(SIGPIPE, SIG_IGN);  // writes to the closed socket fail instead
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log");
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const double before = resident_mb(gateway.pid());
  RawWebSocket flood(gateway.port(), "/ws?scene=s0", "");
  ASSERT_EQ(flood.status(), "HTTP/1.1 101 Switching Protocols");
  const std::string request = R"({"type":")" + std::string(60000, 'x') + R"("})";
  for (int i = 0; i < 3000; ++i) flood.send_text(request);  // 180 MB of replies, were they all kept
  const double after = resident_mb(gateway.pid());
  RawWebSocket reader(gateway.port(), "/ws?scene=s0", "");
  ASSERT_EQ(reader.status(), "HTTP/1.1 101 Switching Protocols");
  reader.send_text(R"({"type":"nonsense"})");
  bool answered = false;
  for (auto m = reader.next(std::chrono::seconds(10)); m && !answered; m = reader.next(std::chrono::seconds(10))) {
    answered = m->find("is not tour or tasks") != std::string::npos;
  }
  EXPECT_TRUE(answered);
  std::printf("a page that never reads: ispars-web's resident memory %.0f MB before, %.0f MB after 180 MB of replies\n",
              before, after);
  EXPECT_LT(after - before, 120.0);
  EXPECT_EQ(gateway.stop(), 0);
  EXPECT_NE(gateway.log().find(" 1 browsers closed for not reading"), std::string::npos) << gateway.log();
}

// Two pages ask for a tour at once through a gateway of --max-tours 1: the second is refused by
// name and served once the first ends. Then, with every page gone, the scene's feed is dropped.
TEST_F(WebGatewayTest, ToursAreBoundedPerGatewayAndAnUnwatchedSceneIsDropped) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", ispars_build(scaled(3000)));
  (void)client.wait_idle("s0", {}, kLong);
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log", {"--max-tours", "1", "--feed-linger", "1"});
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const std::string own = origin_header("http://127.0.0.1:" + std::to_string(gateway.port()));
  // The next message of `type` on `ws` (others, the roadmap's batches and statuses, are skipped).
  const auto next_of = [](RawWebSocket& ws, const std::set<std::string>& types) {
    while (const auto text = ws.next(std::chrono::seconds(30))) {
      const auto m = nlohmann::json::parse(*text, nullptr, false);
      if (!m.is_discarded() && types.count(m.value("type", "")) != 0) return m;
    }
    return nlohmann::json{{"type", "nothing within 30 s"}};
  };
  {
    RawWebSocket a(gateway.port(), "/ws?scene=s0", own);
    RawWebSocket b(gateway.port(), "/ws?scene=s0", own);
    ASSERT_EQ(a.status(), "HTTP/1.1 101 Switching Protocols") << a.body();
    ASSERT_EQ(b.status(), "HTTP/1.1 101 Switching Protocols") << b.body();
    // Followed: each page has had the scene's status (a tour needs the feed).
    EXPECT_EQ(next_of(a, {"status", "error"})["type"], "status");
    EXPECT_EQ(next_of(b, {"status", "error"})["type"], "status");
    a.send_text(R"({"type":"tour","budget":3})");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a's tour runs first (it runs 3 s)
    b.send_text(R"({"type":"tour","budget":0.5})");
    const auto refused = next_of(b, {"tour", "error"});
    EXPECT_EQ(refused.value("message", ""),
              "tour: the gateway runs 1 tours at once already (its limit, --max-tours); ask again when one ends")
        << refused;
    const auto first = next_of(a, {"tour", "error"});
    EXPECT_EQ(first["type"], "tour") << first;
    // What the page draws and names first is the shortcut tour; the roadmap walk's length comes with it.
    EXPECT_LE(first["cost"].get<double>(), first["roadmap_cost"].get<double>() * (1 + 1e-12)) << first;
    b.send_text(R"({"type":"tour","budget":0.5})");
    const auto second = next_of(b, {"tour", "error"});
    EXPECT_EQ(second["type"], "tour") << second;
    // A task's tour: a bad name is refused by the gateway, an unknown one by the daemon; the scene
    // has no tasks to list.
    b.send_text(R"({"type":"tour","budget":0.5,"task":7})");
    EXPECT_EQ(next_of(b, {"tour", "error"}).value("message", ""), "tour: task: not a task name (1-64 of A-Za-z0-9_-.)");
    b.send_text(R"({"type":"tour","budget":0.5,"task":"nope"})");
    EXPECT_NE(next_of(b, {"tour", "error"}).value("message", "").find("the roadmap has no task 'nope'"),
              std::string::npos);
    b.send_text(R"({"type":"tasks"})");
    EXPECT_EQ(next_of(b, {"tasks", "error"}), (nlohmann::json{{"type", "tasks"}, {"tasks", nlohmann::json::array()}}));
  }
  // Both pages gone: the feed goes after --feed-linger (1 s), checked each second.
  const std::string dropped = "stopped following scene s0: no browser watched it for 1 s";
  EXPECT_TRUE(eventually([&] { return gateway.log().find(dropped) != std::string::npos; }, std::chrono::seconds(10),
                         "the gateway drops the feed", std::chrono::milliseconds(100)))
      << gateway.log();
  // A page coming back follows it again.
  RawWebSocket again(gateway.port(), "/ws?scene=s0", own);
  EXPECT_EQ(next_of(again, {"status", "error"})["type"], "status");
  EXPECT_EQ(gateway.stop(), 0);
  EXPECT_NE(gateway.log().find(" 1 tours refused over --max-tours"), std::string::npos) << gateway.log();
}

}  // namespace
}  // namespace ispars::test
