#pragma once
// The C++ client of isparsd: requests with correlation, retries and timeouts; scene ownership
// across several daemons; snapshots; and live replicas of a roadmap (replica.hpp). It speaks the
// library's types (types.hpp); the wire's messages stay behind it (wire_calls.hpp).

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "ispars/client/types.hpp"
#include "ispars/roadmap/build_request.hpp"
#include "ispars/roadmap/roadmap.hpp"
#include "ispars/wire/participant_options.hpp"

namespace ispars::wire {
class Participant;
}

namespace ispars::client {

/// A failed call. kind() tells a missing daemon and a timeout from a request the daemon refused.
class ClientError : public std::runtime_error {
 public:
  /// no_daemon: none found; timeout: no reply in time; rejected: the daemon refused (its message
  /// says why); protocol: another protocol version; forbidden: this client's DDS Security
  /// permissions do not let it send that request (a viewer's change request).
  enum class Kind { no_daemon, timeout, rejected, protocol, forbidden };
  ClientError(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  [[nodiscard]] Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

/// How a client joins the domain and how long it waits.
struct ClientOptions {
  wire::ParticipantOptions participant;
  /// How long a call waits for a daemon and its reply, retries included.
  std::chrono::milliseconds timeout{15000};
  /// How long to wait for a reply before resending the same request.
  std::chrono::milliseconds retry_interval{1000};
  /// The daemon to address when a scene is owned by none (empty: choose).
  std::string server;
};

/// A build as a client asks for it: the one typed request every caller fills (the daemon checks
/// every field again).
using BuildArgs = BuildRequest;

/// A whole roadmap fetched at one version.
struct Snapshot {
  std::string scene;
  std::uint64_t generation = 0;
  std::uint64_t version = 0;
  Roadmap roadmap;
  Vec3 root = Vec3::Zero();
  std::vector<Vec3> pois;
  SceneStatus status;
};

/// Something a caller makes on a client's DDS participant (a replica's update reader): made by
/// attach(), deleted by detach(), and made again on the new participant when the client rejoins
/// the domain. Both run with the client's participant held still (no call runs meanwhile).
class ParticipantUser {
 public:
  virtual ~ParticipantUser() = default;
  virtual void attach(wire::Participant& participant) = 0;
  virtual void detach(wire::Participant& participant) = 0;
};

/// A connection to every isparsd on a domain: calls addressed to each scene's owner. Under DDS
/// Security a client rejoins by itself: when a daemon (or any peer) that its participant dropped
/// comes back under the same participant and does not authenticate again within 10 s (Debian's
/// Fast DDS 2.9.1 cannot while the peer keeps its old session), it replaces its participant (at
/// most once in 30 s), keeping what it knows, its calls, and its participant's users
/// (docs/service.md, "A stall under security"). A change request sent before a rejoin is not sent again after it (the
/// daemon could not tell it from a new one): its call fails naming the rejoin.
class Client {
 public:
  /// Joins the domain (throws std::runtime_error when the participant cannot be created).
  explicit Client(ClientOptions options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  /// Scenes of every daemon on the domain.
  std::vector<SceneEntry> list_scenes();
  Reply load(const std::string& scene);
  Reply unload(const std::string& scene);
  Reply build(const std::string& scene, const BuildArgs& args);
  Reply extend(const std::string& scene, std::uint64_t samples);
  Reply cancel(const std::string& scene);
  SceneStatus stats(const std::string& scene);
  PathReply path(const std::string& scene, const Vec3& from, const Vec3& to);
  Reply drop(const std::string& scene);
  VerifyReply verify(const std::string& scene);
  /// Adds an inspection task of these POIs (on the structure's surface) to the scene's built
  /// roadmap. Queued like an extend: wait_idle() waits for it, and tasks() lists it once added.
  Reply add_task(const std::string& scene, const std::string& name, const std::vector<Vec3>& pois);
  /// The same with `count` POIs the daemon samples on the surface from `seed`.
  Reply add_sampled_task(const std::string& scene, const std::string& name, std::uint32_t count, std::uint64_t seed);
  /// Removes the task `name`, at once: its POIs leave every target set (the roadmap keeps its
  /// vertices) and the name is free again. ClientError (request) when no task has that name, or
  /// it was removed already.
  Reply remove_task(const std::string& scene, const std::string& name);
  /// The roadmap's tasks (not removed), in the order they were added, with their coverage.
  std::vector<TaskEntry> tasks(const std::string& scene);
  /// The whole roadmap, fetched in chunks at one version.
  Snapshot snapshot(const std::string& scene);
  /// An inspection tour on the scene's roadmap, searched for `budget` seconds; `progress` is
  /// called with (seconds, best cost, proven bound) as the daemon improves either (0: none yet).
  /// Empty targets: every POI seen from the root's component.
  TourReply tour(const std::string& scene, double budget, std::uint64_t seed, const std::vector<std::uint32_t>& targets,
                 const std::function<void(double seconds, double cost, double bound)>& progress = {});
  /// The same for the POIs of inspection task `task` that the roadmap sees from the root's
  /// component.
  TourReply task_tour(const std::string& scene, const std::string& task, double budget, std::uint64_t seed,
                      const std::function<void(double seconds, double cost, double bound)>& progress = {});

  /// Waits until the scene has no job (idle, empty or failed), calling `progress` on each status
  /// change seen meanwhile. Throws ClientError(timeout) after `timeout`.
  SceneStatus wait_idle(const std::string& scene, const std::function<void(const SceneStatus&)>& progress,
                        std::chrono::milliseconds timeout);

  /// The daemon owning `scene` under the fleet's rule (ispars/wire/scene_owner.hpp): the live
  /// daemon holding it, else options.server when set, else the daemon the rule assigns it to.
  /// Throws ClientError(no_daemon) when none is running.
  std::string owner_of(const std::string& scene);
  /// Daemons seen on the domain (waits up to the timeout for the first).
  std::vector<DaemonInfo> daemons();
  /// This client's identity: its participant's GUID prefix (24 hex digits), as the daemon reads
  /// it from the transport and writes it into every reply to this client. A rejoin changes it.
  [[nodiscard]] std::string id() const;
  [[nodiscard]] const ClientOptions& options() const { return options_; }
  /// Attaches `user` to this client's participant now, and to each new one after a rejoin,
  /// until it is removed (before it is destroyed, and before the client is).
  void add_participant_user(ParticipantUser& user);
  void remove_participant_user(ParticipantUser& user);
  /// Times this client replaced its participant.
  [[nodiscard]] std::uint64_t rejoins() const;
  /// The latest status of `scene` seen on the status topic, written by the participant that
  /// announces the daemon the status names (a status from any other participant is not shown).
  [[nodiscard]] std::optional<SceneStatus> latest_status(const std::string& scene) const;
  /// The transport identity (wire::identity_of) of the participant announcing daemon
  /// `server_id`; empty when no such daemon is seen.
  [[nodiscard]] std::string daemon_identity(const std::string& server_id) const;
  /// Whether `sender` announces daemon `server_id` (wire::written_by_daemon): the rule for
  /// believing a status or an update that names that daemon.
  [[nodiscard]] bool written_by_daemon(const std::string& server_id, const std::string& sender) const;

 private:
  TourReply tour(const std::string& scene, double budget, std::uint64_t seed, const std::vector<std::uint32_t>& targets,
                 const std::string& task,
                 const std::function<void(double seconds, double cost, double bound)>& progress);
  class Impl;
  /// Sends requests as messages (wire_calls.hpp), for this class and the seam's free functions.
  friend struct WireAccess;
  ClientOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::client
