#pragma once
// Test hosts made of Linux network namespaces, for partitions between real processes: every host
// is a namespace with one veth into a bridge (in a hub namespace of its own), an address
// 10.251.0.K/24 that exists only inside these namespaces, multicast routed to its veth, and a
// Fast DDS profile of UDP on that address alone (no shared memory: namespaces share /dev/shm,
// which would bypass a cut). Nothing is connected to the machine's own namespace, so no packet
// can leave. cut() takes a host's veth off the bridge, heal() puts it back; deafen() cuts one
// direction only (nftables, Debian's `nftables`). Needs root; a
// constructor that cannot make the namespaces throws (a test fails, never skips). The destructor
// removes every namespace it made.

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace ispars::test {

class NetnsLab {
 public:
  /// Makes the hosts `hosts` (names of 1-8 letters and digits), their profiles in `dir`, with
  /// participants announcing a lease of `lease` (what a cut peer is dropped after).
  NetnsLab(const std::filesystem::path& dir, std::vector<std::string> hosts, std::chrono::seconds lease);
  ~NetnsLab();
  NetnsLab(const NetnsLab&) = delete;
  NetnsLab& operator=(const NetnsLab&) = delete;

  /// The host's namespace name, address and Fast DDS profile file (profile name "ispars").
  [[nodiscard]] std::string ns(const std::string& host) const;
  [[nodiscard]] std::string address(const std::string& host) const;
  [[nodiscard]] std::filesystem::path profile(const std::string& host) const;
  /// The command prefix that runs a program on the host (`ip netns exec NS`).
  [[nodiscard]] std::vector<std::string> prefix(const std::string& host) const;

  /// Cuts the host off the bridge (both ends stay up: processes on the host still reach each
  /// other), and puts it back.
  void cut(const std::string& host);
  void heal(const std::string& host);
  /// One way: `host` drops every packet from `from` (nftables in its namespace), while `from`
  /// still hears `host`; and undoes it.
  void deafen(const std::string& host, const std::string& from);
  void undeafen(const std::string& host, const std::string& from);
  /// Like deafen(), for unicast packets only: multicast from `from` (SPDP's announcements) still
  /// arrives, so `host` discovers `from`, but their DDS Security handshake cannot end.
  void deafen_unicast(const std::string& host, const std::string& from);
  void undeafen_unicast(const std::string& host, const std::string& from);

  /// Moves the calling thread, and every thread it makes afterwards, onto the host. Call it
  /// before any DDS participant exists; the destructor moves the thread back.
  void enter(const std::string& host);

  /// Runs `command` with /bin/sh on the host; its output (stdout and stderr) and exit status.
  struct Result {
    std::string output;
    int status = 0;
  };
  Result run(const std::string& host, const std::string& command) const;

 private:
  std::size_t index(const std::string& host) const;
  // Adds (`drop`) or removes `from` in `host`'s drop set of every packet, or of unicast ones.
  void drop_from(const std::string& host, const std::string& from, bool unicast_only, bool drop);
  std::string prefix_;  // namespace names start with it (unique per process)
  std::vector<std::string> hosts_;
  std::filesystem::path dir_;
  int home_fd_ = -1;  // the namespace the entering thread came from
};

}  // namespace ispars::test
