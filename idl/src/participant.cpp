#include "ispars/wire/participant.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>

namespace ispars::wire {
namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

// Participant ports are 7400 + 250 * domain + 10 + 2 * id: at domain 232, ids up to 62 fit.
constexpr std::uint32_t kLocalParticipants = 32;

// Every process watching a shared-memory port marks it broken when a listener has been on one
// message (or has not woken) for this long, and the port is then made anew: with the default,
// 1 s, a daemon slow on one message on a loaded machine lost its port and went deaf ("Error
// receiving data: No such file or directory"; the kill -9 campaign saw it about once a run). A
// port left by a killed process is still found at once, by its lock.
constexpr std::uint32_t kShmHealthyCheckMs = 10000;

fdds::DomainParticipantQos localhost_qos(const std::string& name) {
  fdds::DomainParticipantQos qos = fdds::PARTICIPANT_QOS_DEFAULT;
  qos.name(name);
  qos.transport().use_builtin_transports = false;
  auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
  // Room for snapshot chunks and large batches in flight to several readers (default 512 KB).
  shm->segment_size(8 * 1024 * 1024);
  shm->healthy_check_timeout_ms(kShmHealthyCheckMs);
  qos.transport().user_transports.push_back(shm);
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
  discovery.leaseDuration = eprosima::fastrtps::Duration_t(3, 0);
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
    // Under DDS Security, samples that arrive during a peer's handshake: transient.
    if (entry.message.find("No key material yet") != std::string::npos) level = spdlog::level::debug;
    spdlog::log(level, "fastdds [{}] {}", entry.context.category ? entry.context.category : "", entry.message);
  }
};

}  // namespace

Participant::Participant(const ParticipantOptions& options, fdds::DomainParticipantListener* listener) {
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  if (options.domain < 0 || options.domain > 232) {
    throw std::runtime_error("DDS domain " + std::to_string(options.domain) + " is out of range (0..232)");
  }
  const auto mask = listener ? fdds::StatusMask::all() : fdds::StatusMask::none();
  fdds::DomainParticipantQos qos;
  if (options.profile_file.empty()) {
    qos = localhost_qos(options.name);
  } else {
    if (factory->load_XML_profiles_file(options.profile_file) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot load the Fast DDS profiles file " + options.profile_file);
    }
    if (factory->get_participant_qos_from_profile(options.profile_name, qos) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("no participant profile '" + options.profile_name + "' in " + options.profile_file);
    }
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
    throw std::runtime_error("security identity " + dir + " is not a directory (make one with "
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

void route_fastdds_log_to_spdlog() {
  static std::once_flag once;
  std::call_once(once, [] {
    fdds::Log::ClearConsumers();
    fdds::Log::RegisterConsumer(std::make_unique<SpdlogConsumer>());
    fdds::Log::SetVerbosity(fdds::Log::Kind::Warning);
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
