// The gateway behind the TLS proxy client/web/README.md recommends: Debian's nginx terminating TLS
// on loopback with a self-signed certificate, configured as the README says. Headless Chromium
// follows a build over https and wss; a request without the token is refused through the proxy;
// a WebSocket that sends and never reads, and 64 TLS connections that send nothing, leave another
// user served and the gateway's memory bounded (the figures are printed).

#include <nlohmann/json.hpp>

#include <atomic>
#include <fstream>
#include <thread>

#include "integration/service_fixture.hpp"
#include "integration/test_web_support.hpp"

namespace ispars::test {
namespace {

// nginx on 127.0.0.1:`port`, TLS with a fresh self-signed certificate for localhost, proxying to
// the gateway on `upstream` with the README's location block. Stopped (SIGTERM) when destroyed.
class TlsProxy {
 public:
  TlsProxy(const std::filesystem::path& dir, int port, int upstream) : dir_(dir) {
    std::filesystem::create_directories(dir / "tmp");
    std::filesystem::permissions(dir / "tmp", std::filesystem::perms::all);  // nginx's workers are nobody
    const std::string cert = "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost -keyout '" +
                             (dir / "key.pem").string() + "' -out '" + (dir / "cert.pem").string() + "' 2>'" +
                             (dir / "openssl.log").string() + "'";
    if (std::system(cert.c_str()) != 0) throw std::runtime_error("openssl: " + read_text(dir / "openssl.log"));
    std::ofstream(dir / "nginx.conf") << config(port, upstream);
    const std::string run = "nginx -p '" + dir.string() + "' -c '" + (dir / "nginx.conf").string() + "' -e '" +
                            (dir / "error.log").string() + "' > '" + (dir / "nginx.out").string() + "' 2>&1 & echo $!";
    FILE* pipe = ::popen(run.c_str(), "r");
    if (pipe == nullptr || std::fscanf(pipe, "%d", &pid_) != 1) pid_ = -1;
    if (pipe != nullptr) ::pclose(pipe);
    (void)eventually([&] { return listening(port); }, std::chrono::seconds(10), "nginx listens",
                     std::chrono::milliseconds(100));  // a test that needs it checks it
  }
  ~TlsProxy() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);  // nginx's fast stop; its workers go with the master
      (void)eventually([&] { return ::kill(pid_, 0) != 0; }, std::chrono::seconds(5), "nginx stops",
                       std::chrono::milliseconds(50));
    }
  }
  TlsProxy(const TlsProxy&) = delete;
  TlsProxy& operator=(const TlsProxy&) = delete;
  [[nodiscard]] std::string log() const { return read_text(dir_ / "nginx.out") + read_text(dir_ / "error.log"); }

 private:
  static bool listening(int port) {
    const int fd = connect_local(port);
    if (fd >= 0) ::close(fd);
    return fd >= 0;
  }
  std::string config(int port, int upstream) const {
    const std::string d = dir_.string();
    return "daemon off;\nworker_processes 1;\npid " + d +
           "/nginx.pid;\nevents { worker_connections 1024; }\n"
           "http {\n  access_log " +
           d + "/access.log;\n" + "  client_body_temp_path " + d + "/tmp/body;\n  proxy_temp_path " + d +
           "/tmp/proxy;\n" + "  fastcgi_temp_path " + d + "/tmp/fastcgi;\n  uwsgi_temp_path " + d + "/tmp/uwsgi;\n" +
           "  scgi_temp_path " + d + "/tmp/scgi;\n" +
           "  map $http_upgrade $connection_upgrade { default upgrade; '' close; }\n"
           "  server {\n    listen 127.0.0.1:" +
           std::to_string(port) + " ssl;\n" + "    ssl_certificate " + d + "/cert.pem;\n    ssl_certificate_key " + d +
           "/key.pem;\n" +
           // client/web/README.md's location block, word for word.
           "    location / {\n"
           "      proxy_pass http://127.0.0.1:" +
           std::to_string(upstream) + ";\n" +
           "      proxy_http_version 1.1;\n"
           "      proxy_set_header Upgrade $http_upgrade;\n"
           "      proxy_set_header Connection $connection_upgrade;\n"
           "      proxy_set_header Host $http_host;\n"
           "      proxy_set_header X-Forwarded-Proto $scheme;\n"
           "      proxy_read_timeout 1h;\n"
           "    }\n  }\n}\n";
  }
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

class WebProxyTest : public ServiceTest {
 protected:
  // proxy_check.mjs MODE BASE TOKEN ARGS: the JSON it printed (a "failure" key when it printed none).
  nlohmann::json check(const std::string& mode, const std::string& args) {
    const auto out = dir_.path() / (mode + ".txt");
    const std::string command = "ISPARS_WEB_NODE_MODULES='" + std::string(ISPARS_WEB_NODE_MODULES) +
                                "' timeout -k 5 300 node '" + ISPARS_SOURCE_DIR + "/tests/web/proxy_check.mjs' " +
                                mode + " " + base_ + " " + token_ + " " + args + " > '" + out.string() + "' 2>&1";
    (void)std::system(command.c_str());
    const std::string text = read_text(out);
    const auto json = nlohmann::json::parse(
        text.substr(text.rfind("\n{") == std::string::npos ? 0 : text.rfind("\n{") + 1), nullptr, false);
    return json.is_discarded() ? nlohmann::json{{"failure", text}} : json;
  }
  std::string base_;
  const std::string token_ = "proxy-token-0123456789abcdef";
};

TEST_F(WebProxyTest, ChromiumFollowsABuildOverHttpsAndWssAndTheBoundsHoldThroughTheProxy) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium")) << "Debian's chromium (deploy/install-deps.sh installs it)";
  ASSERT_EQ(std::system("command -v nginx > /dev/null"), 0) << "Debian's nginx (deploy/install-deps.sh installs it)";
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  std::ofstream(dir_.path() / "token") << token_ << "\n";
  const int port = free_port();
  base_ = "https://localhost:" + std::to_string(port);
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log",
                  {"--token-file", (dir_.path() / "token").string(), "--allow-origin", base_});
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  TlsProxy proxy(dir_.path() / "nginx", port, gateway.port());

  // Through the proxy the token is still needed: every user of the proxy is a loopback peer.
  const nlohmann::json ask = check("ask", "");
  EXPECT_EQ(ask["without_token"], 401) << ask << proxy.log();
  EXPECT_EQ(ask["wrong_token"], 401) << ask;
  EXPECT_EQ(ask["with_token"], 200) << ask;
  EXPECT_NE(ask["ws_without_token"].get<std::string>().find(" 401 "), std::string::npos) << ask;
  EXPECT_FALSE(ask["answered_ms"].is_null()) << ask;

  // Chromium follows a build from its first batch, over https and wss.
  const auto ready = dir_.path() / "page-open";
  nlohmann::json follow;
  std::atomic<bool> ended{false};
  std::thread follower([&] {
    follow = check("follow", "s0 240 '" + ready.string() + "'");
    ended = true;
  });
  (void)eventually([&] { return std::filesystem::exists(ready) || ended; }, std::chrono::seconds(120),
                   "the page is ready", std::chrono::milliseconds(100));  // checked below
  const bool opened = std::filesystem::exists(ready);
  if (opened) client.build("s0", ispars_build(scaled(20'000), 1));
  follower.join();
  ASSERT_TRUE(opened) << follow << gateway.log() << proxy.log();
  ASSERT_FALSE(follow.contains("failure")) << follow << gateway.log() << proxy.log();
  const SceneStatus stats = client.stats("s0");
  std::printf("behind nginx: Chromium followed the build in %d batches over %s to %d vertices and %d edges\n",
              follow["batches"].get<int>(), follow["sockets"].dump().c_str(), follow["vertices"].get<int>(),
              follow["edges"].get<int>());
  EXPECT_GT(follow["batches"].get<int>(), 1) << follow;  // open before the build: it drew the roadmap as it grew
  EXPECT_EQ(follow["with_token"], 200) << follow;
  EXPECT_EQ(follow["vertices"], stats.vertices) << follow;
  EXPECT_EQ(follow["edges"], stats.edges) << follow;
  EXPECT_EQ(follow["samples"], scaled(20'000)) << follow;
  EXPECT_TRUE(follow["errors"].empty() && follow["console_errors"].empty()) << follow;
  ASSERT_FALSE(follow["sockets"].empty()) << follow;
  for (const auto& url : follow["sockets"])
    EXPECT_EQ(url.get<std::string>().rfind("wss://localhost:" + std::to_string(port) + "/ws", 0), 0u) << url;
  ASSERT_EQ(follow["cookies"].size(), 1u) << follow;
  EXPECT_TRUE(follow["cookies"][0]["secure"].get<bool>() && follow["cookies"][0]["httpOnly"].get<bool>()) << follow;

  // A page that sends and never reads, and 64 connections that send nothing, at once: another
  // user is served, and the gateway closes the flood with its memory bounded.
  const double before = resident_mb(gateway.pid());
  nlohmann::json flood;
  std::thread flooder([&] { flood = check("flood", "3000"); });
  const nlohmann::json idle = check("idle", "64");
  flooder.join();
  const double after = resident_mb(gateway.pid());
  EXPECT_EQ(idle["held"], 64) << idle;
  EXPECT_EQ(idle["page"], 200) << idle;
  EXPECT_FALSE(idle["answered_ms"].is_null()) << idle;
  EXPECT_TRUE(flood["closed"].get<bool>()) << flood;
  std::printf(
      "behind nginx: the flood sent %d of 3000 requests of 60 kB before it was closed; ispars-web's resident "
      "memory %.0f MB before, %.0f MB after; with 64 idle TLS connections held, another user had the page "
      "(%d) and a WebSocket answer in %d ms\n",
      flood["sent"].get<int>(), before, after, idle["page"].get<int>(), idle["answered_ms"].get<int>());
  EXPECT_LT(after - before, 120.0);
  EXPECT_EQ(gateway.stop(), 0);
  EXPECT_NE(gateway.log().find(" 1 browsers closed for not reading"), std::string::npos) << gateway.log();
}

}  // namespace
}  // namespace ispars::test
