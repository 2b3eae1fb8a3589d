#include "support/netns_lab.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace ispars::test {
namespace {

constexpr const char* kIp = "/usr/sbin/ip";
constexpr const char* kNft = "/usr/sbin/nft";

// Runs a shell command whose failure changes nothing (removing what may not exist).
void quietly(const std::string& command) {
  if (std::system((command + " >/dev/null 2>&1").c_str()) != 0) return;
}

// Runs a shell command; throws with its output when it fails.
std::string must(const std::string& command) {
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot run: " + command);
  std::string output;
  std::array<char, 512> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  if (::pclose(pipe) != 0) throw std::runtime_error("failed: " + command + "\n" + output);
  return output;
}

std::string profile_xml(const std::string& address, std::chrono::seconds lease) {
  const long announce = std::max<long>(1, static_cast<long>(lease.count()) / 3);
  return R"(<?xml version="1.0" encoding="UTF-8" ?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <transport_descriptors>
      <transport_descriptor>
        <transport_id>netns_udp</transport_id>
        <type>UDPv4</type>
        <interfaceWhiteList><address>)" +
         address + R"(</address></interfaceWhiteList>
        <sendBufferSize>4194304</sendBufferSize>
        <receiveBufferSize>4194304</receiveBufferSize>
      </transport_descriptor>
    </transport_descriptors>
    <participant profile_name="ispars">
      <rtps>
        <userTransports><transport_id>netns_udp</transport_id></userTransports>
        <useBuiltinTransports>false</useBuiltinTransports>
        <builtin>
          <discovery_config>
            <leaseDuration><sec>)" +
         std::to_string(lease.count()) + R"(</sec></leaseDuration>
            <leaseAnnouncement><sec>)" +
         std::to_string(announce) + R"(</sec></leaseAnnouncement>
          </discovery_config>
        </builtin>
      </rtps>
    </participant>
  </profiles>
</dds>
)";
}

}  // namespace

NetnsLab::NetnsLab(const std::filesystem::path& dir, std::vector<std::string> hosts, std::chrono::seconds lease)
    : prefix_("ispt" + std::to_string(::getpid()) + "-"), hosts_(std::move(hosts)), dir_(dir) {
  if (hosts_.empty() || hosts_.size() > 200) throw std::invalid_argument("NetnsLab: 1 to 200 hosts");
  std::filesystem::create_directories(dir_);
  const std::string hub = prefix_ + "hub";
  try {
    must(std::string(kIp) + " netns add " + hub);
    must(std::string(kIp) + " -n " + hub + " link set lo up");
    must(std::string(kIp) + " -n " + hub + " link add br0 type bridge mcast_snooping 0");
    must(std::string(kIp) + " -n " + hub + " link set br0 up");
    for (std::size_t k = 0; k < hosts_.size(); ++k) {
      const std::string n = ns(hosts_[k]);
      const std::string hub_end = "vh" + std::to_string(k);
      const std::string host_end = "vn" + std::to_string(k);
      must(std::string(kIp) + " netns add " + n);
      must(std::string(kIp) + " -n " + n + " link set lo up");
      must(std::string(kIp) + " -n " + hub + " link add " + hub_end + " type veth peer name " + host_end + " netns " +
           n);
      must(std::string(kIp) + " -n " + hub + " link set " + hub_end + " master br0");
      must(std::string(kIp) + " -n " + hub + " link set " + hub_end + " up");
      must(std::string(kIp) + " -n " + n + " addr add " + address(hosts_[k]) + "/24 dev " + host_end);
      must(std::string(kIp) + " -n " + n + " link set " + host_end + " up");
      // SPDP multicast has no route in a fresh namespace.
      must(std::string(kIp) + " -n " + n + " route add 224.0.0.0/4 dev " + host_end);
      std::ofstream(profile(hosts_[k])) << profile_xml(address(hosts_[k]), lease);
    }
  } catch (...) {
    for (const std::string& h : hosts_) quietly(std::string(kIp) + " netns del " + ns(h));
    quietly(std::string(kIp) + " netns del " + hub);
    throw;
  }
}

NetnsLab::~NetnsLab() {
  if (home_fd_ >= 0) {
    ::setns(home_fd_, CLONE_NEWNET);
    ::close(home_fd_);
  }
  for (const std::string& h : hosts_) quietly(std::string(kIp) + " netns del " + ns(h));
  quietly(std::string(kIp) + " netns del " + prefix_ + "hub");
}

std::size_t NetnsLab::index(const std::string& host) const {
  for (std::size_t k = 0; k < hosts_.size(); ++k) {
    if (hosts_[k] == host) return k;
  }
  throw std::invalid_argument("NetnsLab: no host " + host);
}

std::string NetnsLab::ns(const std::string& host) const { return prefix_ + host; }
std::string NetnsLab::address(const std::string& host) const { return "10.251.0." + std::to_string(index(host) + 1); }
std::filesystem::path NetnsLab::profile(const std::string& host) const { return dir_ / (ns(host) + ".xml"); }
std::vector<std::string> NetnsLab::prefix(const std::string& host) const { return {kIp, "netns", "exec", ns(host)}; }

void NetnsLab::cut(const std::string& host) {
  must(std::string(kIp) + " -n " + prefix_ + "hub link set vh" + std::to_string(index(host)) + " nomaster");
}

void NetnsLab::heal(const std::string& host) {
  must(std::string(kIp) + " -n " + prefix_ + "hub link set vh" + std::to_string(index(host)) + " master br0");
}

namespace {

// The drop sets of the lab's input filter: every packet from an address in "deaf", unicast ones
// from an address in "deaf_unicast".
struct DropSet {
  const char* name;
  const char* match;  // what narrows the rule, before "drop"
};
constexpr DropSet kDeaf{"deaf", ""};
constexpr DropSet kDeafUnicast{"deaf_unicast", "meta pkttype unicast "};

}  // namespace

void NetnsLab::drop_from(const std::string& host, const std::string& from, bool unicast_only, bool drop) {
  const DropSet& set = unicast_only ? kDeafUnicast : kDeaf;
  const std::string nft = std::string(kIp) + " netns exec " + ns(host) + " " + kNft;
  const std::string name = set.name;
  if (drop) {
    must(nft + " add table inet ispars_lab");
    must(nft + " add set inet ispars_lab " + name + " '{ type ipv4_addr; }'");
    must(nft + " add chain inet ispars_lab in '{ type filter hook input priority 0; }'");
    if (must(nft + " list chain inet ispars_lab in").find("@" + name + " ") == std::string::npos) {
      must(nft + " add rule inet ispars_lab in ip saddr @" + name + " " + set.match + "drop");  // once per set
    }
  }
  must(nft + (drop ? " add" : " delete") + " element inet ispars_lab " + name + " '{ " + address(from) + " }'");
}

void NetnsLab::deafen(const std::string& host, const std::string& from) { drop_from(host, from, false, true); }
void NetnsLab::undeafen(const std::string& host, const std::string& from) { drop_from(host, from, false, false); }
void NetnsLab::deafen_unicast(const std::string& host, const std::string& from) { drop_from(host, from, true, true); }
void NetnsLab::undeafen_unicast(const std::string& host, const std::string& from) {
  drop_from(host, from, true, false);
}

void NetnsLab::enter(const std::string& host) {
  if (home_fd_ < 0) home_fd_ = ::open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
  const std::string path = "/var/run/netns/" + ns(host);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::setns(fd, CLONE_NEWNET) != 0) {
    if (fd >= 0) ::close(fd);
    throw std::runtime_error("cannot enter network namespace " + ns(host));
  }
  ::close(fd);
}

NetnsLab::Result NetnsLab::run(const std::string& host, const std::string& command) const {
  const std::string full = std::string(kIp) + " netns exec " + ns(host) + " /bin/sh -c '" + command + "' 2>&1";
  FILE* pipe = ::popen(full.c_str(), "r");
  if (pipe == nullptr) return {"cannot run: " + full, -1};
  Result r;
  std::array<char, 512> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.output += buffer.data();
  const int status = ::pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace ispars::test
