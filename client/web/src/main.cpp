// ispars-web: the live viewer's gateway. Follows scenes over DDS as a replica, like `ispars
// watch`, and serves a page (three.js) over HTTP and WebSocket to any number of browsers. Binds to
// 127.0.0.1 unless told otherwise.

#include <CLI/CLI.hpp>
#include <arpa/inet.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>

#include "ispars/client/client.hpp"
#include "web_server.hpp"

#ifndef ISPARS_WEB_ROOT
#define ISPARS_WEB_ROOT ""
#endif

int main(int argc, char** argv) {
  CLI::App app{"ispars-web: a live viewer of isparsd's roadmaps in the browser (HTTP and WebSocket)"};
  ispars::web::WebServerOptions options;
  options.web_root = ISPARS_WEB_ROOT;
  ispars::client::ClientOptions client_options;
  int domain = 0;
  std::string listen = "127.0.0.1:8080";
  std::string profile_file, profile_name = "ispars", security;
  double timeout_s = 10;
  app.add_option("--domain", domain, "DDS domain id")->envname("ISPARS_DOMAIN")->check(CLI::Range(0, 232));
  app.add_option("--profile-file", profile_file, "Fast DDS XML profiles file (default: built-in localhost only)")
      ->envname("ISPARS_PROFILE_FILE");
  app.add_option("--profile-name", profile_name, "participant profile in the profiles file");
  app.add_option("--security", security, "DDS Security identity directory (a viewer identity is enough)")
      ->envname("ISPARS_SECURITY");
  app.add_option("--timeout", timeout_s, "seconds to wait for a daemon and each reply")->check(CLI::Range(0.1, 3600.0));
  app.add_option("--listen", listen, "IPv4ADDRESS:PORT to serve on (port 0: a free one, printed)");
  app.add_option("--web-root", options.web_root, "the page's files (default: the build's)")->check(CLI::ExistingDirectory);
  app.add_option("--scene-dir", options.scene_dir, "scene YAML files, for the meshes (default: no meshes)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--max-browsers", options.max_connections, "connections at once")->check(CLI::Range(1, 10000));
  app.add_option("--max-vertices", options.limits.vertices, "vertices sent to a browser per scene")
      ->check(CLI::Range(1, 10'000'000));
  app.add_option("--max-edges", options.limits.edges, "edges sent to a browser per scene")->check(CLI::Range(1, 50'000'000));
  app.add_option("--tour-budget-max", options.tour_budget_max, "seconds a page may ask a tour to search")
      ->check(CLI::Range(0.1, 3600.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars-web: " << e.what() << " (see --help)\n";
    return 2;
  }
  if (app.count("--web-root") == 0 && !std::filesystem::exists(options.web_root / "index.html")) {
    // Installed (cmake --install): the page lies in share/ispars/web beside bin/.
    std::error_code ec;
    const auto installed = std::filesystem::canonical("/proc/self/exe", ec).parent_path().parent_path() / "share/ispars/web";
    if (!ec && std::filesystem::exists(installed / "index.html")) options.web_root = installed;
  }
  if (!std::filesystem::exists(options.web_root / "index.html")) {
    std::cerr << "ispars-web: --web-root: no index.html in " << options.web_root.string()
              << " (build the ispars_web_page target, or name the page's directory)\n";
    return 2;
  }

  const auto colon = listen.rfind(':');
  char* end = nullptr;
  const long port = colon == std::string::npos ? -1 : std::strtol(listen.c_str() + colon + 1, &end, 10);
  if (colon == std::string::npos || end == listen.c_str() + colon + 1 || *end != '\0' || port < 0 || port > 65535) {
    std::cerr << "ispars-web: --listen: '" << listen << "' is not IPv4ADDRESS:PORT\n";
    return 2;
  }
  options.address = listen.substr(0, colon);
  options.port = static_cast<std::uint16_t>(port);
  in_addr parsed{};
  if (::inet_pton(AF_INET, options.address.c_str(), &parsed) != 1) {
    std::cerr << "ispars-web: --listen: '" << options.address << "' is not an IPv4 address\n";
    return 2;
  }

  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  ::signal(SIGPIPE, SIG_IGN);  // a browser that goes away mid-write is an error code, not a signal

  client_options.participant.domain = domain;
  client_options.participant.profile_file = profile_file;
  client_options.participant.profile_name = profile_name;
  client_options.participant.security = security;
  client_options.participant.name = "ispars-web";
  client_options.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
  try {
    ispars::client::Client client(client_options);
    ispars::web::WebServer server(client, options);
    std::cout << "ispars-web: serving http://" << options.address << ":" << server.port() << "/ (DDS domain " << domain
              << ", web root " << options.web_root.string() << ")" << std::endl;
    int signal = 0;
    sigwait(&stop_signals, &signal);
    const auto stats = server.stats();
    std::cout << "ispars-web: stopping (" << stats.browsers_total << " browsers served, " << stats.messages_sent
              << " messages sent)" << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "ispars-web: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
