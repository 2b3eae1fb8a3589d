#pragma once
// The fixture of the fleet's fault campaigns on real networks: the daemons d1, d2 and d3 and the
// test's clients (host hc) on hosts that are Linux network namespaces (support/netns_lab.hpp),
// talking Fast DDS over UDP, optionally under DDS Security (keystore_ set by the test).

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "integration/service_fixture.hpp"
#include "support/netns_lab.hpp"

namespace ispars::test {

inline const std::vector<std::string> kDaemons{"d1", "d2", "d3"};

class NetnsFleetTest : public ServiceTest {
 protected:
  using Clock = std::chrono::steady_clock;

  // The daemon `id` on its own host.
  std::unique_ptr<DaemonProcess> start_on(const std::string& id, std::vector<std::string> extra = {},
                                          const std::filesystem::path& scenes = {}) {
    std::vector<std::string> args{"--profile-file", lab_->profile(id).string(), "--discovery-wait-ms", "2000"};
    args.insert(args.end(), extra.begin(), extra.end());
    if (!keystore_.empty()) args.insert(args.end(), {"--security", (keystore_ / "identities" / id).string()});
    return std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id),
                                           scenes.empty() ? scene_dir_ : scenes, id, args, probe_identity(),
                                           std::vector<std::string>{}, std::chrono::seconds(60), lab_->prefix(id),
                                           lab_->profile("hc").string());
  }
  std::string probe_identity() const { return keystore_.empty() ? "" : (keystore_ / "identities" / "probe").string(); }
  client::ClientOptions options_on_hc() const {
    client::ClientOptions o = client_options(domain_);
    o.participant.profile_file = lab_->profile("hc").string();
    if (!keystore_.empty()) o.participant.security = (keystore_ / "identities" / "op").string();
    return o;
  }
  // A client on hc that sees every daemon. Under DDS Security a first handshake can fail for good
  // in Debian's Fast DDS 2.9.1 (docs/service.md, "A stall under security"): a client that has not
  // seen them all in 10 s joins again.
  std::unique_ptr<Client> joined(std::size_t daemons = kDaemons.size()) const {
    for (int attempt = 1;; ++attempt) {
      if (auto client = fresh(daemons)) return client;
      if (attempt == 3) throw std::runtime_error("a client heard not every daemon in three tries of 10 s");
      std::fprintf(stderr, "a client heard not every daemon in 10 s (try %d); joining again\n", attempt);
    }
  }
  // A new client that hears `daemons` daemons within 10 s, or nullptr.
  std::unique_ptr<Client> fresh(std::size_t daemons) const {
    auto client = std::make_unique<Client>(options_on_hc());
    if (eventually([&] { return client->daemons().size() >= daemons; }, std::chrono::seconds(10),
                   "the client hears the daemons", std::chrono::milliseconds(100))) {
      return client;
    }
    return nullptr;
  }
  // `ispars ARGS --json` on `host`: its last JSON line, or an error naming its output.
  nlohmann::json cli_on(const std::string& host, const std::string& args) const {
    std::string command =
        "ISPARS_DOMAIN=" + std::to_string(domain_) + " ISPARS_PROFILE_FILE=" + lab_->profile(host).string();
    if (!keystore_.empty()) command += " ISPARS_SECURITY=" + (keystore_ / "identities" / ("op-" + host)).string();
    command += std::string(" ") + ISPARS_CLI + " " + args;
    // Its warnings (a peer dropped as the client stops, say) go to a file of their own: on the
    // output they could land after the JSON line, or inside it.
    const std::filesystem::path warnings = dir_.path() / ("cli-" + host + ".err");
    const NetnsLab::Result r = lab_->run(host, command + " --json 2> " + warnings.string());
    std::string last;
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty() && line[0] == '{') last = line;
    }
    if (r.status != 0 || last.empty()) {
      std::ifstream err(warnings);
      const std::string stderr_text{std::istreambuf_iterator<char>(err), std::istreambuf_iterator<char>()};
      throw std::runtime_error("ispars " + args + " on " + host + " failed (" + std::to_string(r.status) + "):\n" +
                               r.output + stderr_text);
    }
    return nlohmann::json::parse(last);
  }

  std::unique_ptr<NetnsLab> lab_;
  std::filesystem::path keystore_;
};

}  // namespace ispars::test
