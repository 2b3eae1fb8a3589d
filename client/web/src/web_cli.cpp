#include "web_cli.hpp"

#include <arpa/inet.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "ispars/web/access_policy.hpp"

#ifndef ISPARS_WEB_ROOT
#define ISPARS_WEB_ROOT ""
#endif

namespace ispars::web {
namespace {

// The flags as typed, before they are checked together and turned into the options.
struct Raw {
  std::string listen = "127.0.0.1:8080";
  std::string profile_file, profile_name = "ispars", security, token_file;
  double timeout_s = 10, feed_linger_s = 30;
  std::vector<std::string> allow_origins;
};

void declare(CLI::App& app, WebCommandLine& c, Raw& r) {
  WebServerOptions& o = c.server;
  app.add_option("--domain", c.domain, "DDS domain id")->envname("ISPARS_DOMAIN")->check(CLI::Range(0, 232));
  app.add_option("--profile-file", r.profile_file, "Fast DDS XML profiles file (default: built-in localhost only)")
      ->envname("ISPARS_PROFILE_FILE");
  app.add_option("--profile-name", r.profile_name, "participant profile in the profiles file");
  app.add_option("--security", r.security, "DDS Security identity directory (a viewer identity is enough)")
      ->envname("ISPARS_SECURITY");
  app.add_option("--timeout", r.timeout_s, "seconds to wait for a daemon and each reply")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option(
      "--listen", r.listen,
      "IPv4ADDRESS:PORT to serve on (port 0: a free one, printed); an address off loopback needs --token-file");
  app.add_option("--web-root", o.web_root, "the page's files (default: the build's)")->check(CLI::ExistingDirectory);
  app.add_option("--scene-dir", o.scene_dir, "scene YAML files, for the meshes (default: no meshes)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--max-browsers", o.max_connections, "connections at once")->check(CLI::Range(1, 10000));
  app.add_option("--max-vertices", o.limits.vertices, "vertices sent to a browser per scene")
      ->check(CLI::Range(1, 10'000'000));
  app.add_option("--max-edges", o.limits.edges, "edges sent to a browser per scene")->check(CLI::Range(1, 50'000'000));
  app.add_option("--tour-budget-max", o.tour_budget_max, "seconds a page may ask a tour to search")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--max-tours", o.max_tours, "tours searching at once over every page (more are refused, named)")
      ->check(CLI::Range(1, 64));
  app.add_option("--feed-linger", r.feed_linger_s, "seconds a scene no browser watches is still followed")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--allow-origin", r.allow_origins,
                 "a web origin (http[s]://HOST[:PORT]) whose pages may use the gateway besides its own; repeatable, "
                 "at most 32")
      ->take_all();
  app.add_option("--token-file", r.token_file,
                 "a file holding the token (16-256 of A-Za-z0-9._~-) that every peer off loopback must present")
      ->check(CLI::ExistingFile);
}

// The token in `file` (surrounding white space dropped), or a message naming the problem.
std::string read_token(const std::string& file, std::string& token) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) return "--token-file: cannot read " + file;
  token = text.str();
  const auto first = token.find_first_not_of(" \t\r\n");
  const auto last = token.find_last_not_of(" \t\r\n");
  token = first == std::string::npos ? std::string() : token.substr(first, last - first + 1);
  const std::string problem = token_problem(token);
  return problem.empty() ? std::string() : "--token-file: " + file + ": " + problem;
}

// Where to listen, the origins and the token: a message naming the problem, or empty.
std::string check_access(const Raw& r, WebServerOptions& o) {
  const auto colon = r.listen.rfind(':');
  char* end = nullptr;
  const long port = colon == std::string::npos ? -1 : std::strtol(r.listen.c_str() + colon + 1, &end, 10);
  if (colon == std::string::npos || end == r.listen.c_str() + colon + 1 || *end != '\0' || port < 0 || port > 65535) {
    return "--listen: '" + r.listen + "' is not IPv4ADDRESS:PORT";
  }
  o.address = r.listen.substr(0, colon);
  o.port = static_cast<std::uint16_t>(port);
  in_addr parsed{};
  if (::inet_pton(AF_INET, o.address.c_str(), &parsed) != 1)
    return "--listen: '" + o.address + "' is not an IPv4 address";
  if (r.allow_origins.size() > 32) return "--allow-origin: at most 32 origins";
  for (const std::string& origin : r.allow_origins) {
    if (origin.size() > 256 || normalize_origin(origin).empty()) {
      return "--allow-origin: '" + origin + "' is not an origin: http://HOST[:PORT] or https://HOST[:PORT], no path";
    }
  }
  o.access.allowed_origins = r.allow_origins;
  if (!r.token_file.empty()) {
    if (std::string why = read_token(r.token_file, o.access.token); !why.empty()) return why;
  }
  if (!is_loopback(o.address) && o.access.token.empty()) {
    return "--listen " + r.listen +
           " is not a loopback address: any machine that reaches it would use the gateway "
           "(and its DDS read rights) unchecked; give --token-file PATH (browsers off this machine then present the "
           "token), or listen on 127.0.0.1";
  }
  return {};
}

// The page's directory: the named one, the build's, or an installed one (share/ispars/web).
std::string check_web_root(const CLI::App& app, WebServerOptions& o) {
  if (app.count("--web-root") == 0 && !std::filesystem::exists(o.web_root / "index.html")) {
    std::error_code ec;
    const auto installed =
        std::filesystem::canonical("/proc/self/exe", ec).parent_path().parent_path() / "share/ispars/web";
    if (!ec && std::filesystem::exists(installed / "index.html")) o.web_root = installed;
  }
  if (!std::filesystem::exists(o.web_root / "index.html")) {
    return "--web-root: no index.html in " + o.web_root.string() +
           " (build the ispars_web_page target, or name the page's directory)";
  }
  return {};
}

}  // namespace

int parse_command_line(int argc, char** argv, WebCommandLine& out) {
  CLI::App app{"ispars-web: a live viewer of isparsd's roadmaps in the browser (HTTP and WebSocket)"};
  out.server.web_root = ISPARS_WEB_ROOT;
  Raw raw;
  declare(app, out, raw);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars-web: " << e.what() << " (see --help)\n";
    return 2;
  }
  std::string why = check_web_root(app, out.server);
  if (why.empty()) why = check_access(raw, out.server);
  if (!why.empty()) {
    std::cerr << "ispars-web: " << why << "\n";
    return 2;
  }
  out.server.feed_linger = std::chrono::milliseconds(static_cast<long>(raw.feed_linger_s * 1000));
  auto& p = out.client.participant;
  p.domain = out.domain;
  p.profile_file = raw.profile_file;
  p.profile_name = raw.profile_name;
  p.security = raw.security;
  p.name = "ispars-web";
  out.client.timeout = std::chrono::milliseconds(static_cast<long>(raw.timeout_s * 1000));
  return -1;
}

}  // namespace ispars::web
