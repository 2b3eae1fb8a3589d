// The fleet profile for networks without multicast (deploy/fastdds_discovery.xml): daemons and
// clients as CLIENTs of a Fast DDS Discovery Server, here on 127.0.0.1.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"

namespace ispars::test {
namespace {

// fast-discovery-server (what `fastdds discovery` runs), stopped when this goes.
class DiscoveryServer {
 public:
  DiscoveryServer(int port, const std::filesystem::path& log) {
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      if (std::FILE* out = std::freopen(log.c_str(), "w", stdout)) ::dup2(::fileno(out), STDERR_FILENO);
      const std::string p = std::to_string(port);
      ::execl("/usr/bin/fast-discovery-server", "fast-discovery-server", "-i", "0", "-l", "127.0.0.1", "-p", p.c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~DiscoveryServer() {
    ::kill(pid_, SIGINT);  // its documented way to stop
    if (eventually([&] { return ::waitpid(pid_, nullptr, WNOHANG) == pid_; }, std::chrono::seconds(2),
                   "the discovery server stops", std::chrono::milliseconds(20))) {
      return;
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  DiscoveryServer(const DiscoveryServer&) = delete;
  DiscoveryServer& operator=(const DiscoveryServer&) = delete;

 private:
  pid_t pid_ = -1;
};

// The shipped profile with the server's port changed to `port` (each test run its own).
std::filesystem::path discovery_profile(const std::filesystem::path& dir, int port) {
  std::string xml = read_text(std::filesystem::path(ISPARS_SOURCE_DIR) / "deploy" / "fastdds_discovery.xml");
  const auto at = xml.find("<port>11811</port>");
  if (at == std::string::npos) throw std::runtime_error("deploy/fastdds_discovery.xml names no port 11811");
  xml.replace(at, std::string("<port>11811</port>").size(), "<port>" + std::to_string(port) + "</port>");
  const auto path = dir / "fastdds_discovery.xml";
  std::ofstream(path) << xml;
  return path;
}

TEST_F(ServiceTest, DaemonsAndClientsFindEachOtherThroughADiscoveryServer) {
  const int port = 20000 + domain_;  // the domain is this test process's own
  DiscoveryServer server(port, dir_.path() / "discovery-server.log");
  const auto profile = discovery_profile(dir_.path(), port);
  auto one = start("one", {"--profile-file", profile.string(), "--discovery-wait-ms", "1000"});
  auto two = start("two", {"--profile-file", profile.string(), "--discovery-wait-ms", "1000"});
  auto options = client_options(domain_);
  options.participant.profile_file = profile.string();
  Client client(options);
  // Both daemons, found through the server only (no multicast, no initial peers in the profile).
  std::vector<std::string> ids;
  (void)eventually(
      [&] {
        ids.clear();
        for (const auto& d : client.daemons()) ids.push_back(d.server_id);
        return ids.size() >= 2;
      },
      std::chrono::seconds(15), "the client hears both daemons");  // checked below
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<std::string>{"one", "two"}));
  // One owner for a scene, a build through it, and its updates followed by a replica.
  client.load("s0");
  client::RoadmapReplica replica(client, "s0");
  client.build("s0", ispars_build(1500));
  const SceneStatus built = client.wait_idle("s0", {}, kLong);
  EXPECT_GT(built.vertices, 0u);
  EXPECT_TRUE(replica.wait_for(0, built.version, std::chrono::seconds(20)));
  EXPECT_EQ(replica.version(), built.version);
  EXPECT_EQ(replica.roadmap().vertex_count(), built.vertices);
  EXPECT_EQ(one->terminate(), 0);
  EXPECT_EQ(two->terminate(), 0);
}

}  // namespace
}  // namespace ispars::test
