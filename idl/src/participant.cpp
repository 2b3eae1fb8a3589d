#include "ispars/wire/participant.hpp"

#include "ispars/wire/identity.hpp"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <spdlog/spdlog.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/log/Log.hpp>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace ispars::wire {
namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

// Participant ports are 7400 + 250 * domain + 10 + 2 * id: at domain 232, ids up to 62 fit.
constexpr std::uint32_t kLocalParticipants = 32;

// Under DDS Security a participant's lease is long. Fast DDS 2.9.1 cannot re-authenticate a peer
// that one side dropped (its lease ran out here) while the other still holds the old session: the
// new handshake is refused as unexpected, and the pair stays deaf to each other until one of them
// leaves (measured: a secured daemon stopped for 5 s never again reached a replica that was
// following it; without security the replica caught up). A short lease turns any stall of that
// length (a loaded machine, a paused VM) into such a split; 20 s is Fast DDS's own default.

fdds::DomainParticipantQos localhost_qos(const ParticipantOptions& options) {
  const bool secure = !options.security.empty();
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(options.name);
  qos.transport().use_builtin_transports = false;
  // UDP alone, no shared memory transport: with Fast DDS 2.9.1's, a participant on a loaded host
  // could stop hearing its peers for good (a port marked broken and made anew, "Port ... Zombie.
  // Reset the port"): a fresh client never saw the daemon in 2 of 12 runs of a test beside a
  // ctest run, none of 12 over UDP alone; a restarted daemon went deaf in 3 of 3 tries, none of 3
  // over UDP. The price over loopback, measured with ispars-bench: a 237 MB snapshot at 38.4 MB/s
  // instead of 41.3, a stats round trip 238 us instead of 219 (median).
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back("127.0.0.1");
  // The initial peer is every participant port on 127.0.0.1 up to this many participants (the
  // default, 4, leaves two participants numbered 4 and up never discovering each other: with
  // three daemons and their clients on one host, some client would never see some daemon).
  udp->maxInitialPeersRange = kLocalParticipants;
  qos.transport().user_transports.push_back(udp);
  rtps::Locator_t peer;
  rtps::IPLocator::setIPv4(peer, "127.0.0.1");
  peer.kind = LOCATOR_KIND_UDPv4;
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  // Announce often and expire quickly: discovery in well under a second, and a killed peer is
  // noticed in seconds rather than the default 20.
  auto& discovery = qos.wire_protocol().builtin.discovery_config;
  discovery.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(0, 250'000'000);
  discovery.leaseDuration = eprosima::fastrtps::Duration_t(lease_seconds(options.lease_seconds, secure), 0);
  return qos;
}

class SpdlogConsumer final : public fdds::LogConsumer {
 public:
  void Consume(const fdds::Log::Entry& entry) override {
    auto level = entry.kind == fdds::Log::Kind::Error     ? spdlog::level::err
                 : entry.kind == fdds::Log::Kind::Warning ? spdlog::level::warn
                                                          : spdlog::level::debug;
    // Each client's replies travel in its own partition, so every other client's reply reader
    // is "incompatible" with that writer by design: not worth a warning.
    if (entry.message.find("Different Partitions") != std::string::npos) level = spdlog::level::debug;
    // Under DDS Security, said once per remote endpoint for every secured submessage received
    // before that endpoint's keys arrived (over a hundred lines for one client's first request):
    // transient and normal, and it buried every other line of a daemon's debug log.
    if (entry.message.find("No key material yet") != std::string::npos) return;
    spdlog::log(level, "fastdds [{}] {}", entry.context.category ? entry.context.category : "", entry.message);
  }
};

// What discovery and DDS Security say about the other participants, in this process's log: who
// joined, left or was dropped, and who failed to authenticate. A dropped peer under security is a
// warning (see kSecureLeaseSeconds).
class ParticipantEvents final : public fdds::DomainParticipantListener {
 public:
  ParticipantEvents(bool secure, std::shared_ptr<PeerWatch> peers, std::function<void(const RemoteReader&)> readers)
      : secure_(secure), peers_(std::move(peers)), readers_(std::move(readers)) {}

  void on_subscriber_discovery(fdds::DomainParticipant*, rtps::ReaderDiscoveryInfo&& info) override {
    if (info.status == rtps::ReaderDiscoveryInfo::CHANGED_QOS_READER) return;
    RemoteReader reader;
    reader.identity = identity_of(info.info.guid().guidPrefix);
    reader.topic = info.info.topicName().to_string();
    reader.partitions = info.info.m_qos.m_partition.names();
    reader.present = info.status == rtps::ReaderDiscoveryInfo::DISCOVERED_READER;
    readers_(reader);
  }

  void on_participant_discovery(fdds::DomainParticipant*, rtps::ParticipantDiscoveryInfo&& info) override {
    const std::string who = describe(info.info.m_guid, info.info.m_participantName.to_string());
    switch (info.status) {
      case rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT:
        spdlog::debug("participant {} discovered", who);
        peers_->discovered(prefix_of(info.info.m_guid), info.info.m_participantName.to_string());
        break;
      case rtps::ParticipantDiscoveryInfo::REMOVED_PARTICIPANT:
        spdlog::debug("participant {} left", who);
        peers_->left(prefix_of(info.info.m_guid));
        break;
      case rtps::ParticipantDiscoveryInfo::DROPPED_PARTICIPANT:
        peers_->dropped(prefix_of(info.info.m_guid));
        if (secure_) {
          spdlog::warn(
              "participant {} dropped: its lease ran out here; if it is still running, DDS Security "
              "(Fast DDS 2.9.1) cannot authenticate it again until one of the two restarts",
              who);
        } else {
          spdlog::debug("participant {} dropped: its lease ran out here", who);
        }
        break;
      default:
        break;
    }
  }

#if HAVE_SECURITY
  void onParticipantAuthentication(fdds::DomainParticipant*, rtps::ParticipantAuthenticationInfo&& info) override {
    const std::string who = describe(info.guid, "");
    if (info.status == rtps::ParticipantAuthenticationInfo::AUTHORIZED_PARTICIPANT) {
      spdlog::debug("participant {} authenticated", who);
      peers_->authenticated(prefix_of(info.guid));
    } else {
      spdlog::warn("participant {} failed DDS Security authentication", who);
      peers_->refused(prefix_of(info.guid));
    }
  }
#endif

 private:
  static std::string prefix_of(const rtps::GUID_t& guid) {
    std::ostringstream text;
    text << guid.guidPrefix;
    return text.str();
  }
  static std::string describe(const rtps::GUID_t& guid, const std::string& name) {
    std::ostringstream text;
    text << guid.guidPrefix;
    if (!name.empty()) text << " (" << name << ")";
    return text.str();
  }
  bool secure_;
  std::shared_ptr<PeerWatch> peers_;
  std::function<void(const RemoteReader&)> readers_;
};

}  // namespace

void PeerWatch::dropped(const std::string& prefix) {
  std::lock_guard lock(mutex_);
  if (dropped_.size() >= kMaxPeers) dropped_.clear();
  dropped_.insert(prefix);
  awaited_.erase(prefix);
}

void PeerWatch::discovered(const std::string& prefix, const std::string& name, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (dropped_.erase(prefix) > 0) {
    awaited_[prefix] = {{prefix, name, false}, now};
  } else if (first_ && name.starts_with(kDaemonNamePrefix) && name != first_->self && !met_.contains(prefix) &&
             awaited_.size() < 2 * kMaxPeers) {
    awaited_.try_emplace(prefix, Awaited{{prefix, name, true}, now});
  }
}

void PeerWatch::authenticated(const std::string& prefix) {
  std::lock_guard lock(mutex_);
  if (first_) {
    if (met_.size() >= kMaxPeers) met_.clear();
    met_.insert(prefix);
  }
  awaited_.erase(prefix);
}

void PeerWatch::left(const std::string& prefix) {
  std::lock_guard lock(mutex_);
  dropped_.erase(prefix);
  awaited_.erase(prefix);
}

std::optional<PeerWatch::Peer> PeerWatch::unhealed(Clock::time_point now, Clock::duration grace) const {
  std::lock_guard lock(mutex_);
  for (const auto& [prefix, a] : awaited_) {
    if (now - a.at >= grace) return a.peer;
  }
  return std::nullopt;
}

std::optional<PeerWatch::Peer> PeerWatch::take_unhealed(Clock::time_point now, Clock::duration grace) {
  std::lock_guard lock(mutex_);
  for (auto it = awaited_.begin(); it != awaited_.end(); ++it) {
    if (now - it->second.at < grace) continue;
    Peer peer = it->second.peer;
    awaited_.erase(it);
    return peer;
  }
  return std::nullopt;
}

Participant::Participant(const ParticipantOptions& options, fdds::DomainParticipantListener* listener) {
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  // Checked as declared (participant_options.hpp), once more here: a program may fill the options
  // in code, past any flag or file.
  if (std::string why = params::problem(kDomain, options.domain); !why.empty()) {
    throw std::runtime_error("participant domain: " + why);
  }
  if (std::string why = params::problem(kLease, options.lease_seconds); !why.empty()) {
    throw std::runtime_error("participant lease_s: " + why);
  }
  // Without a listener of the caller's, this one logs participant events; discovery and
  // authentication callbacks come whatever the mask, and no entity status reaches it.
  if (!options.security.empty()) peers_ = std::make_shared<PeerWatch>(PeerWatch::FirstMeetings{options.name});
  if (listener == nullptr) {
    events_ = std::make_unique<ParticipantEvents>(!options.security.empty(), peers_,
                                                  [slot = readers_](const RemoteReader& reader) {
                                                    std::lock_guard lock(slot->mutex);
                                                    if (slot->watch) slot->watch(reader);
                                                  });
    listener = events_.get();
  }
  const auto mask = events_ ? fdds::StatusMask::none() : fdds::StatusMask::all();
  fdds::DomainParticipantQos qos;
  if (options.profile_file.empty()) {
    qos = localhost_qos(options);
  } else {
    if (factory->load_XML_profiles_file(options.profile_file) != ReturnCode_t::RETCODE_OK) {
      fdds::Log::Flush();  // Fast DDS's own lines naming the bad element come out before the error
      throw std::runtime_error("cannot load the Fast DDS profiles file " + options.profile_file);
    }
    if (factory->get_participant_qos_from_profile(options.profile_name, qos) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("no participant profile '" + options.profile_name + "' in " + options.profile_file);
    }
    qos.name(options.name);  // who it is, whatever the profile calls it: peers' logs and PeerWatch read it
  }
  if (!options.security.empty()) {
    const fdds::PropertyPolicyQos secure = security_properties(options.security);
    for (const auto& property : secure.properties()) {
      qos.properties().properties().push_back(property);
    }
  }
  participant_ = factory->create_participant(options.domain, qos, listener, mask);
  if (participant_ == nullptr) {
    throw std::runtime_error(
        "cannot create a DDS participant on domain " + std::to_string(options.domain) +
        (options.profile_file.empty() ? std::string(" (localhost profile)")
                                      : " with profile '" + options.profile_name + "' of " + options.profile_file) +
        (options.security.empty() ? std::string()
                                  : " and the security identity " + options.security +
                                        " (is its certificate signed by its ca.pem, and its permissions by the same "
                                        "authority, and valid now?)"));
  }
}

void Participant::watch_readers(ReaderWatch watch) {
  std::lock_guard lock(readers_->mutex);
  readers_->watch = std::move(watch);
}

Participant::~Participant() {
  if (participant_ != nullptr) {
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
}

fdds::PropertyPolicyQos security_properties(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path root = fs::canonical(dir, error);
  if (error || !fs::is_directory(root)) {
    throw std::runtime_error("security identity " + dir +
                             " is not a directory (make one with "
                             "deploy/security/make-keystore.sh)");
  }
  const auto uri = [&](const char* file) {
    const fs::path path = root / file;
    if (!std::ifstream(path).good()) {
      throw std::runtime_error("security identity " + dir + " has no readable " + file +
                               " (make it with deploy/security/make-keystore.sh)");
    }
    return "file://" + path.string();
  };
  fdds::PropertyPolicyQos p;
  auto& list = p.properties();
  list.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  list.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", uri("ca.pem"));
  list.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", uri("cert.pem"));
  list.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", uri("key.pem"));
  list.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  // A separate permissions authority when the directory has one, else the identity authority.
  list.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca",
                    fs::exists(root / "permissions_ca.pem") ? uri("permissions_ca.pem") : uri("ca.pem"));
  list.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", uri("governance.p7s"));
  list.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions", uri("permissions.p7s"));
  list.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  return p;
}

int domain_from_environment() {
  if (const char* text = std::getenv("ISPARS_DOMAIN")) {
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    if (end != text && *end == '\0' && value >= 0 && value <= 232) return static_cast<int>(value);
    throw std::runtime_error(std::string("ISPARS_DOMAIN must be a DDS domain id in 0..232, got '") + text + "'");
  }
  return 0;
}

void route_fastdds_log_to_spdlog(bool warnings) {
  static std::once_flag once;
  std::call_once(once, [warnings] {
    fdds::Log::ClearConsumers();
    fdds::Log::RegisterConsumer(std::make_unique<SpdlogConsumer>());
    fdds::Log::SetVerbosity(warnings ? fdds::Log::Kind::Warning : fdds::Log::Kind::Error);
  });
}

void stop_fastdds_log_routing() {
  // Fast DDS logs from its own thread, which outlives main; spdlog's loggers do not (static
  // destruction). Entries still queued go out now, then no consumer refers to spdlog.
  fdds::Log::Flush();
  fdds::Log::ClearConsumers();
  fdds::Log::KillThread();
}

}  // namespace ispars::wire
