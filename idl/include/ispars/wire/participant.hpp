#pragma once
// Creating DDS participants the same way in the daemon, the clients, the tests and benchmarks.

#include <fastdds/dds/core/policy/QosPolicies.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/wire/participant_options.hpp"

namespace ispars::wire {

/// The DDS Security properties (PKI-DH authentication, access control by signed governance and
/// permissions, AES-GCM encryption) for the identity directory `dir`. Throws std::runtime_error
/// naming the first file that is missing or unreadable.
[[nodiscard]] eprosima::fastdds::dds::PropertyPolicyQos security_properties(const std::string& dir);

/// Peers whose DDS Security session is missing while they run: "unhealed". Two kinds.
/// - Returned: dropped here (their lease ran out) and discovered again under the same GUID. The
///   peer kept running (it stalled, or the link between them was cut) while this side forgot it.
///   When both sides dropped each other (a cut both ways) they authenticate afresh; when only this
///   side did, Debian's Fast DDS 2.9.1 cannot authenticate the peer again while it keeps the old
///   session (docs/service.md, "A stall under security").
/// - First meetings (only when constructed with FirstMeetings): a daemon (a peer named
///   "isparsd ...", not this participant's own name) discovered for the first time whose first
///   handshake never ends. Fast DDS 2.9.1 leaves about one such handshake in some secured runs
///   (CI, 2026-11-29: two daemons that never heard each other).
/// A peer stays unhealed until it authenticates, is refused, leaves or is dropped (again). Safe
/// from any thread.
class PeerWatch {
 public:
  using Clock = std::chrono::steady_clock;
  struct Peer {
    std::string prefix;          ///< Its GUID prefix, as Fast DDS prints it.
    std::string name;            ///< Its participant name ("isparsd ID" for a daemon).
    bool first_meeting = false;  ///< Never authenticated here (else: returned after a drop).
  };
  /// Watch first meetings of daemons too; `self` is this participant's own name (another
  /// participant of the same daemon, during its rejoin, is not watched).
  struct FirstMeetings {
    std::string self;
  };
  PeerWatch() = default;
  explicit PeerWatch(FirstMeetings first) : first_(std::move(first)) {}

  void dropped(const std::string& prefix);
  void discovered(const std::string& prefix, const std::string& name, Clock::time_point now = Clock::now());
  /// DDS Security authenticated the peer (again).
  void authenticated(const std::string& prefix);
  /// DDS Security refused the peer (a rejoin would not change that).
  void refused(const std::string& prefix) { left(prefix); }
  /// The peer deleted its participant (it stopped, or rejoined with a new one itself).
  void left(const std::string& prefix);
  /// An unhealed peer discovered at least `grace` before `now`; nothing otherwise. Left in place
  /// (take_unhealed() takes it).
  [[nodiscard]] std::optional<Peer> unhealed(Clock::time_point now, Clock::duration grace) const;
  /// Like unhealed(), and forgets it.
  [[nodiscard]] std::optional<Peer> take_unhealed(Clock::time_point now, Clock::duration grace);

 private:
  struct Awaited {
    Peer peer;
    Clock::time_point at;
  };
  static constexpr std::size_t kMaxPeers = 1024;  // dropped ones forgotten all at once past this
  std::optional<FirstMeetings> first_;
  mutable std::mutex mutex_;
  std::set<std::string> dropped_;
  std::set<std::string> met_;               // authenticated here (whichever callback came first)
  std::map<std::string, Awaited> awaited_;  // by prefix; at most 2 kMaxPeers
};

/// A reader another participant announced (or withdrew), as discovery reports it.
struct RemoteReader {
  std::string identity;  ///< Its participant's GUID prefix (identity_of).
  std::string topic;
  std::vector<std::string> partitions;  ///< Its subscriber's partitions.
  bool present = true;                  ///< False when it left (or its participant did).
};

/// Called in DDS's discovery thread for every remote reader that comes or goes: it must only
/// take note (creating or deleting DDS entities there deadlocks with DDS's own locks).
using ReaderWatch = std::function<void(const RemoteReader&)>;

/// What a daemon's participant name starts with ("isparsd ID"): peers tell a daemon by it.
inline constexpr std::string_view kDaemonNamePrefix = "isparsd ";
/// The participant name of daemon `server_id`.
[[nodiscard]] inline std::string daemon_participant_name(const std::string& server_id) {
  return std::string(kDaemonNamePrefix) + server_id;
}

/// Owns a participant and deletes it (with its entities) on destruction. Without a listener of
/// the caller's, it logs (spdlog) which participants join, leave, are dropped (their lease ran
/// out) or fail to authenticate.
class Participant {
 public:
  /// Throws std::runtime_error naming the domain and the profile when creation fails.
  explicit Participant(const ParticipantOptions& options,
                       eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  [[nodiscard]] eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  /// Peers whose session is missing (PeerWatch; first meetings under DDS Security), only when
  /// this object logs the events itself, that is when no listener was given.
  [[nodiscard]] PeerWatch& peers() { return *peers_; }
  eprosima::fastdds::dds::DomainParticipant* operator->() const { return participant_; }
  /// Calls `watch` for each remote reader discovered or gone from now on (only when this object
  /// logs the events itself); an empty one stops the calls, and returns once none is running.
  void watch_readers(ReaderWatch watch);

 private:
  std::shared_ptr<PeerWatch> peers_ = std::make_shared<PeerWatch>();
  struct ReaderSlot {
    std::mutex mutex;  // held while the watch runs: clearing it waits for a running call
    ReaderWatch watch;
  };
  std::shared_ptr<ReaderSlot> readers_ = std::make_shared<ReaderSlot>();
  std::unique_ptr<eprosima::fastdds::dds::DomainParticipantListener> events_;  // outlives participant_
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
};

/// The domain to use: the value given, else $ISPARS_DOMAIN, else 0.
[[nodiscard]] int domain_from_environment();

/// Routes Fast DDS's own log messages to spdlog, once per process: its warnings and errors (a
/// daemon's log), or with `warnings` false its errors alone, as Fast DDS's console shows by
/// default (a client program's stderr: a peer unmatched as the client leaves is no news there).
void route_fastdds_log_to_spdlog(bool warnings = true);
/// Undoes route_fastdds_log_to_spdlog before the process exits: Fast DDS's logging thread would
/// otherwise write through spdlog after spdlog is destroyed (a crash at exit).
void stop_fastdds_log_routing();

}  // namespace ispars::wire
