// /healthz follows DDS, not only the daemon's threads: a daemon that receives no DDS traffic at all
// (every UDP packet into its host dropped by nftables, its own included; its HTTP endpoint still
// reachable over TCP) answers no client, and must say 503 within a stated bound, then 200 again
// once the packets pass. The daemon hears its own probe sample, written every 2 s, through the
// transport (server/daemon/include/ispars/server/self_probe.hpp, main.cpp, operator_endpoints.cpp).

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "integration/service_fixture.hpp"
#include "support/netns_lab.hpp"

// After Eigen (through the fixture): httplib pulls in OpenSSL, whose macros upset Eigen's headers.
#include <httplib.h>

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;
// Unhealthy within: the hearing limit (10 s) after the last probe heard, which came at most one
// probe period (2 s) before the cut, and a little for the poll.
constexpr std::chrono::seconds kUnhealthyBound{15};
// Healthy again within: the next probe (2 s) and a little.
constexpr std::chrono::seconds kHealthyBound{5};

class HealthTest : public ServiceTest {};

// Polls /healthz until it answers `status`, for at most `limit`; the seconds it took, or -1.
double seconds_until(httplib::Client& http, int status, std::chrono::seconds limit) {
  const auto t0 = Clock::now();
  const bool answered = eventually(
      [&] {
        const auto res = http.Get("/healthz");
        return res && res->status == status;
      },
      limit, "/healthz answers " + std::to_string(status), std::chrono::milliseconds(250));
  return answered ? std::chrono::duration<double>(Clock::now() - t0).count() : -1.0;
}

TEST_F(HealthTest, ADaemonThatHearsNoDdsIsUnhealthyAndHealthyAgainWhenItDoes) {
  NetnsLab lab(dir_.path() / "netns", {"d1", "ht"}, std::chrono::seconds(3));
  lab.enter("ht");
  const std::string address = lab.address("d1");
  DaemonProcess daemon(ISPARS_DAEMON, domain_, dir_.path() / "data-d1", scene_dir_, "d1",
                       {"--profile-file", lab.profile("d1").string(), "--metrics", address + ":0"}, "",
                       std::vector<std::string>{}, std::chrono::seconds(60), lab.prefix("d1"),
                       lab.profile("ht").string());
  const int port = metrics_port(daemon.log(), address);
  ASSERT_GT(port, 0) << daemon.log();
  httplib::Client http(address, port);
  http.set_connection_timeout(2, 0);
  http.set_read_timeout(2, 0);
  // Healthy for longer than the hearing limit: it hears itself.
  ASSERT_GE(seconds_until(http, 200, std::chrono::seconds(30)), 0.0) << daemon.log();
  std::this_thread::sleep_for(std::chrono::seconds(12));
  ASSERT_GE(seconds_until(http, 200, std::chrono::seconds(1)), 0.0) << "unhealthy while it hears DDS";

  const auto nft = [&](const std::string& args) {
    const auto r = lab.run("d1", "nft " + args);
    ASSERT_EQ(r.status, 0) << args << ": " << r.output;
  };
  nft("add table inet health_test");
  nft("add chain inet health_test in \"{ type filter hook input priority 0; }\"");
  nft("add rule inet health_test in meta l4proto udp drop");
  const double unhealthy_s = seconds_until(http, 503, kUnhealthyBound);
  nft("delete table inet health_test");
  ASSERT_GE(unhealthy_s, 0.0) << "still healthy " << kUnhealthyBound.count() << " s after it stopped hearing DDS";
  const double healthy_s = seconds_until(http, 200, kHealthyBound);
  ASSERT_GE(healthy_s, 0.0) << "not healthy again " << kHealthyBound.count() << " s after DDS came back";
  std::printf(
      "health: 503 %.2f s after every UDP packet into the daemon's host was dropped; 200 %.2f s after "
      "they passed again\n",
      unhealthy_s, healthy_s);
  EXPECT_TRUE(daemon.alive());
}

}  // namespace
}  // namespace ispars::test
