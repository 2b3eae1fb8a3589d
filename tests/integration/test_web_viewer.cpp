// The live viewer against a real daemon and gateway, in headless Chromium: pages follow a build
// and draw exactly what `stats` says, a screenshot holds the drawing, a
// tour comes on request, an unknown scene, a closed browser and a roadmap past the drawing limits
// are handled, and the gateway keeps serving when the daemon goes away.

#include <nlohmann/json.hpp>

#include <fstream>
#include <thread>

#include "integration/service_fixture.hpp"
#include "integration/test_web_support.hpp"
#include "ispars/render/scene_render.hpp"

namespace ispars::test {
namespace {

// A JSON value as text: a string as it is, anything else as JSON.
std::string text_of(const nlohmann::json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

class WebViewerTest : public ServiceTest {
 protected:
  // One page of scene s0 on the gateway at `port`, once its element ID contains TEXT ("ID:TEXT"):
  // that element's text and the page's vertex and edge counts.
  nlohmann::json page_text(int port, const std::string& wait) { return one_page(port, "'--wait-text=" + wait + "'"); }
  // One page of scene s0 driven by viewer_check.mjs's `flag`: what it printed.
  nlohmann::json one_page(int port, const std::string& flag) {
    const auto out = dir_.path() / "page_text.txt";
    const std::string command = "ISPARS_WEB_NODE_MODULES='" + std::string(ISPARS_WEB_NODE_MODULES) +
                                "' timeout -k 5 300 node '" + ISPARS_SOURCE_DIR +
                                "/tests/web/viewer_check.mjs' 'http://127.0.0.1:" + std::to_string(port) +
                                "/' s0 1 unused.png 60 " + flag + " > '" + out.string() + "' 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << read_text(out);
    const auto json = nlohmann::json::parse(read_text(out), nullptr, false);
    return json.is_discarded() ? nlohmann::json{{"text", read_text(out)}, {"vertices", -1}, {"edges", -1}} : json;
  }
};

TEST_F(WebViewerTest, FourBrowsersFollowABuildAndDrawWhatStatsSays) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium")) << "Debian's chromium (deploy/install-deps.sh installs it)";
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log");
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const std::string url = "http://127.0.0.1:" + std::to_string(gateway.port()) + "/";
  // Plain HTTP first: the page, the scene list, a mesh, and what is refused.
  EXPECT_EQ(http_get(gateway.port(), "/").first, "HTTP/1.1 200 OK");
  EXPECT_NE(http_get(gateway.port(), "/api/scenes").second.find("\"s0\""), std::string::npos);
  EXPECT_EQ(http_get(gateway.port(), "/api/mesh/s0").first, "HTTP/1.1 200 OK");
  const auto unknown_mesh = http_get(gateway.port(), "/api/mesh/nowhere");
  EXPECT_EQ(unknown_mesh.first, "HTTP/1.1 404 Not Found");
  EXPECT_NE(unknown_mesh.second.find("nowhere"), std::string::npos) << unknown_mesh.second;
  EXPECT_EQ(http_get(gateway.port(), "/../../etc/passwd").first, "HTTP/1.1 404 Not Found");
  EXPECT_EQ(http_get(gateway.port(), "/api/mesh/..%2Fx").first, "HTTP/1.1 400 Bad Request");

  // Four pages open, and one more that closes mid-stream; then a build starts (20,000 samples;
  // the quickstart's 60,000 with four pages is measured in docs/results/viewer.md), which the
  // pages follow from its first batch.
  const auto shot = dir_.path() / "viewer.png";
  const auto ready = dir_.path() / "pages-open";
  const auto node_out = dir_.path() / "node.txt";
  const std::string command = "ISPARS_WEB_NODE_MODULES='" + std::string(ISPARS_WEB_NODE_MODULES) +
                              "' timeout -k 5 300 node '" + ISPARS_SOURCE_DIR + "/tests/web/viewer_check.mjs' '" + url +
                              "' s0 4 '" + shot.string() + "' 240 --close-one-early --ready-file='" + ready.string() +
                              "' > '" + node_out.string() + "' 2>&1; echo $? > '" + node_out.string() + ".exit'";
  ASSERT_EQ(std::system(("(" + command + ") &").c_str()), 0);
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(ready); }, std::chrono::seconds(60),
                         "the pages are ready", std::chrono::milliseconds(100)))
      << read_text(node_out);
  const auto t0 = std::chrono::steady_clock::now();
  BuildArgs args;
  args.samples = scaled(20'000);  // a twentieth in the sanitizer pass
  args.seed = 1;
  client.build("s0", args);
  (void)eventually([&] { return std::filesystem::exists(node_out.string() + ".exit"); }, std::chrono::seconds(300),
                   "the browser check ends", std::chrono::milliseconds(100));  // its exit status checked below
  ASSERT_EQ(read_text(node_out.string() + ".exit"), "0\n") << read_text(node_out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string out = read_text(node_out);
  const auto result =
      nlohmann::json::parse(out.substr(out.rfind("\n{") == std::string::npos ? 0 : out.rfind("\n{") + 1));
  ASSERT_FALSE(result.contains("failure")) << out << "\n" << gateway.log();
  const SceneStatus stats = client.stats("s0");
  EXPECT_EQ(stats.samples_done, scaled(20'000));
  ASSERT_EQ(result["pages"].size(), 4u);
  int most_batches = 0;
  for (const auto& page : result["pages"]) {
    EXPECT_EQ(page["vertices"], stats.vertices) << page;
    EXPECT_EQ(page["edges"], stats.edges) << page;
    EXPECT_EQ(page["shown_vertices"], stats.vertices) << page;
    EXPECT_EQ(page["shown_edges"], stats.edges) << page;
    EXPECT_TRUE(page["mesh"].get<bool>()) << page;
    EXPECT_TRUE(page["errors"].empty()) << page;
    EXPECT_GE(page["batches"].get<int>(), 1) << page;
    most_batches = std::max(most_batches, page["batches"].get<int>());
  }
  // The pages were open before the build: they drew the roadmap as it grew.
  EXPECT_GT(most_batches, 1);
  EXPECT_TRUE(result["console_errors"].empty()) << result["console_errors"];
  // The drawing is there: in the page's canvas and in the screenshot.
  EXPECT_GT(result["drawn_pixels"]["drawn"].get<double>(), 0.03 * result["drawn_pixels"]["total"].get<double>())
      << result;
  const render::Image image = render::read_png(shot.string());
  std::size_t drawn = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      drawn += std::abs(p[0] - 0xe8) + std::abs(p[1] - 0xee) + std::abs(p[2] - 0xf6) > 30 ? 1 : 0;
    }
  }
  EXPECT_GT(drawn, static_cast<std::size_t>(image.width) * image.height / 20) << "a blank screenshot";
  EXPECT_TRUE(result["tour"]["valid"].get<bool>()) << result["tour"];
  EXPECT_GT(result["tour"]["waypoints"], 2) << result["tour"];
  EXPECT_NE(text_of(result["unknown_scene_error"]).find("no_such_scene"), std::string::npos) << result;
  std::cout << "viewer: " << seconds << " s for the build and 4 pages; waited ms per page:";
  for (const auto& page : result["pages"])
    std::cout << " " << page["waited_ms"] << " (" << page["batches"] << " batches)";
  std::cout << "\n";

  // A roadmap past the viewer's limits: drawn up to them, and the page says so.
  {
    Gateway small(domain_, scene_dir_, dir_.path() / "web-small.log", {"--max-vertices", "50", "--max-edges", "100"});
    ASSERT_GT(small.port(), 0) << small.log();
    const auto note = page_text(small.port(), "note:drawing the first");
    EXPECT_EQ(note["vertices"], 50) << note << "\n" << small.log();
    EXPECT_LE(note["edges"], 100) << note;
    EXPECT_NE(text_of(note["text"]).find("drawing the first 50 of " + std::to_string(stats.vertices) + " vertices"),
              std::string::npos)
        << note;
  }

  // The daemon goes away: the gateway says so and keeps serving.
  daemon->kill9();
  // A page says so too, once the daemon's lease runs out.
  const auto gone = page_text(gateway.port(), "daemon_note:has left the DDS domain");
  EXPECT_NE(text_of(gone["text"]).find("daemon d has left the DDS domain"), std::string::npos) << gone;
  EXPECT_EQ(gone["vertices"], stats.vertices) << "the last roadmap stays shown\n" << gateway.log();
  std::pair<std::string, std::string> scenes;
  (void)eventually(  // its announcement lasts until its lease (3 s) runs out
      [&] {
        scenes = http_get(gateway.port(), "/api/scenes");
        return scenes.first == "HTTP/1.1 503 Service Unavailable";
      },
      std::chrono::seconds(15), "the gateway answers 503", std::chrono::seconds(1));  // checked below
  EXPECT_EQ(scenes.first, "HTTP/1.1 503 Service Unavailable") << scenes.second;
  EXPECT_NE(scenes.second.find("\"error\""), std::string::npos) << scenes.second;
  std::cout << "with the daemon gone, /api/scenes says: " << scenes.second << "\n";
  EXPECT_EQ(http_get(gateway.port(), "/").first, "HTTP/1.1 200 OK");
  EXPECT_TRUE(gateway.alive());
  EXPECT_EQ(gateway.stop(), 0) << gateway.log();
}

// A page opened before any daemon holds its scene says why, and draws the roadmap once the scene
// is loaded and built: the gateway keeps asking while the page stays open (it once asked once,
// and a page opened a moment too early stayed blank until it was reloaded).
TEST_F(WebViewerTest, APageOpenedBeforeItsSceneIsLoadedDrawsItOnceItIs) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium")) << "Debian's chromium (deploy/install-deps.sh installs it)";
  auto daemon = start("d");
  Client client(client_options(domain_));
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log");
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  nlohmann::json seen;
  std::thread page([&] { seen = page_text(gateway.port(), "state:drawn"); });
  // The gateway has asked the daemon for the scene and been told it is not loaded.
  const std::string refused = "stats 's0': request: scene: scene 's0' is not loaded";
  EXPECT_TRUE(eventually([&] { return daemon->log().find(refused) != std::string::npos; }, std::chrono::seconds(60),
                         "the daemon refuses the gateway's stats", std::chrono::milliseconds(100)));
  client.load("s0");
  client.build("s0", ispars_build(scaled(5'000)));
  page.join();
  const SceneStatus stats = client.stats("s0");
  EXPECT_EQ(seen["vertices"], stats.vertices) << seen << "\n" << gateway.log();
  EXPECT_EQ(seen["edges"], stats.edges) << seen;
  ASSERT_TRUE(seen["errors"].is_array()) << seen;
  ASSERT_FALSE(seen["errors"].empty()) << seen;
  EXPECT_NE(text_of(seen["errors"][0]).find("scene 's0' is not loaded"), std::string::npos) << seen;
  EXPECT_EQ(gateway.stop(), 0) << gateway.log();
}

// A page lists the scene's inspection tasks; the one chosen has its POIs drawn and the tour aimed
// at those of them seen from the root's component, as `ispars tour --task` is.
TEST_F(WebViewerTest, APageDrawsTheChosenTasksPoisAndToursThem) {
  ASSERT_TRUE(std::filesystem::exists("/usr/bin/chromium")) << "Debian's chromium (deploy/install-deps.sh installs it)";
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", ispars_build(scaled(5'000)));
  (void)client.wait_idle("s0", {}, kLong);
  for (const auto& [name, seed] : {std::pair<std::string, int>{"cracks", 5}, {"welds", 6}}) {
    client.add_sampled_task("s0", name, 40 - seed, seed);  // one at a time: an addition is refused while one runs
    (void)client.wait_idle("s0", {}, kLong);
  }
  const std::vector<client::TaskEntry> tasks = client.tasks("s0");
  ASSERT_EQ(tasks.size(), 2u);
  client.remove_task("s0", "welds");  // a removed task is not listed
  Gateway gateway(domain_, scene_dir_, dir_.path() / "web.log");
  ASSERT_GT(gateway.port(), 0) << gateway.log();
  const nlohmann::json seen = one_page(gateway.port(), "--task=cracks");
  ASSERT_FALSE(seen.contains("failure")) << seen << "\n" << gateway.log();
  EXPECT_EQ(seen["task_pois"], 35) << seen;
  ASSERT_EQ(seen["tasks"].size(), 1u) << seen;
  EXPECT_EQ(seen["tasks"][0]["name"], "cracks");
  EXPECT_EQ(seen["tour"]["task"], "cracks") << seen;
  EXPECT_EQ(seen["tour"]["targets"], tasks[0].pois_covered_root) << seen;
  EXPECT_EQ(seen["tour"]["covered"], seen["tour"]["targets"]) << seen;
  EXPECT_TRUE(seen["tour"]["valid"].get<bool>()) << seen;
  EXPECT_NE(text_of(seen["tour"]["text"]).find("POIs of task cracks"), std::string::npos) << seen;
  EXPECT_TRUE(seen["errors"].empty()) << seen;
  EXPECT_EQ(gateway.stop(), 0) << gateway.log();
}

// A bad command line stops the gateway before it joins DDS, with exit 2 and a line naming the
// option (a bound of the access policy too); a port already in use stops it with exit 1, naming the address.
TEST_F(WebViewerTest, BadCommandLinesAndABusyPortStopTheStartByName) {
  const auto run = [&](const std::string& args) {
    const auto out = dir_.path() / "bad.txt";
    const int status = std::system((std::string(ISPARS_WEB) + " --domain " + std::to_string(domain_) + " " + args +
                                    " > '" + out.string() + "' 2>&1")
                                       .c_str());
    return std::make_pair(WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out));
  };
  const auto short_token = dir_.path() / "short-token";
  std::ofstream(short_token) << "short\n";
  for (const auto& [args, named] : std::vector<std::pair<std::string, std::string>>{
           {"--listen 127.0.0.1:99999", "--listen"},
           {"--listen localhost:80", "--listen: 'localhost' is not an IPv4 address"},
           {"--listen 127.0.0.1", "--listen"},
           {"--max-browsers 0", "--max-browsers"},
           {"--web-root /", "--web-root: no index.html in /"},
           {"--tour-budget-max -1", "--tour-budget-max"},
           {"--max-tours 0", "--max-tours"},
           {"--max-tours 65", "--max-tours"},
           {"--feed-linger -1", "--feed-linger"},
           {"--allow-origin evil.example", "--allow-origin: 'evil.example' is not an origin"},
           {"--allow-origin http://evil.example/page", "--allow-origin: 'http://evil.example/page' is not an origin"},
           {"--token-file /nonexistent", "--token-file"},
           {"--token-file " + short_token.string(),
            "--token-file: " + short_token.string() + ": the token has 5 characters"}}) {
    const auto [code, text] = run(args);
    EXPECT_EQ(code, 2) << args << ": " << text;
    EXPECT_NE(text.find(named), std::string::npos) << args << ": " << text;
  }
  Gateway first(domain_, scene_dir_, dir_.path() / "first.log");
  ASSERT_GT(first.port(), 0) << first.log();
  const auto [code, text] = run("--listen 127.0.0.1:" + std::to_string(first.port()));
  EXPECT_EQ(code, 1) << text;
  EXPECT_NE(text.find("cannot listen on 127.0.0.1:" + std::to_string(first.port())), std::string::npos) << text;
  EXPECT_TRUE(first.alive());
}

}  // namespace
}  // namespace ispars::test
