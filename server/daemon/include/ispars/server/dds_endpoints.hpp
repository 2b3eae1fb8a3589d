#pragma once
// The daemon's DDS side: one participant, the query and change request readers, and the reply,
// update, status and announcement writers.

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "ispars.h"
#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_inbox.hpp"
#include "ispars/server/reply_routes.hpp"
#include "ispars/server/self_probe.hpp"
#include "ispars/wire/latest_samples.hpp"
#include "ispars/wire/participant.hpp"

namespace ispars::server {

/// The daemon's DDS entities: requests in; replies, updates, statuses and announcements out.
class DdsEndpoints final : public eprosima::fastdds::dds::DataReaderListener,
                           public eprosima::fastdds::dds::DataWriterListener {
 public:
  DdsEndpoints(DaemonInbox& daemon, const DaemonConfig& config, std::uint64_t joined_ms);
  ~DdsEndpoints() override;

  /// Writes a reply once the client's reply route is ready (reply_routes.hpp), waiting at most
  /// `wait`; the client retries with the same id if it is still lost.
  void send_reply(const msg::Reply& reply, std::chrono::milliseconds wait = std::chrono::milliseconds(2000));
  void publish_update(const msg::UpdateBatch& batch);
  /// Disposes `scene`'s update instance (its roadmap was dropped, or the scene left this daemon):
  /// its kept batches are released and every replica is told.
  void retire_updates(const std::string& scene);
  void publish_status(const msg::SceneStatus& status);
  /// Publishes `scene`'s tasks (ispars/tasks) when its roadmap's generation or task events
  /// differ from what this participant published last; `tasks` makes them (called only then).
  void publish_tasks(const std::string& scene, std::uint64_t generation, std::uint64_t events,
                     const std::function<std::vector<msg::SceneTask>()>& tasks);
  void announce(const msg::DaemonInfo& info);
  /// The DDS probe (self_probe.hpp); null under DDS Security.
  [[nodiscard]] SelfProbe* probe() { return probe_.get(); }
  [[nodiscard]] const SelfProbe* probe() const { return probe_.get(); }
  void publish_tour_progress(const msg::TourProgress& progress);
  /// The latest announcement of every other live daemon on the domain.
  [[nodiscard]] std::vector<msg::DaemonInfo> other_daemons() const;
  /// Whether another participant has announced this daemon's server id since this one joined.
  [[nodiscard]] bool id_announced_elsewhere() const { return id_elsewhere_; }
  /// True once after another participant announced this daemon's server id (then re-announce,
  /// so that readers keep this daemon's announcement as the latest).
  [[nodiscard]] bool take_id_contested() { return id_contested_.exchange(false); }
  /// The daemon (host and pid) that announces this daemon's server id and joined the domain
  /// before it (ties go to the lower participant GUID); empty while there is none. This daemon
  /// must then stop.
  [[nodiscard]] std::string older_namesake() const;
  /// Readers matched to the updates writer (replicas, watchers), clients whose reply routes are
  /// ready (reader matched and acknowledged), and reply routes held: for the metrics.
  [[nodiscard]] std::uint64_t update_subscribers() const;
  [[nodiscard]] std::uint64_t reply_clients() const;
  [[nodiscard]] std::uint64_t reply_routes() const;
  /// Stops delivering requests.
  void stop_requests();
  /// A peer this participant dropped and then discovered again under the same GUID, once.
  [[nodiscard]] wire::PeerWatch& peers() { return participant_.peers(); }

  // DataReaderListener (queries and changes)
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;
  // DataWriterListener (each client's reply writer): a route whose last reader left is released.
  void on_publication_matched(eprosima::fastdds::dds::DataWriter* writer,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& info) override;

 private:
  DaemonInbox& daemon_;
  std::string server_id_;
  wire::Participant participant_;
  eprosima::fastdds::dds::TypeSupport query_type_, change_type_, reply_type_, update_type_, status_type_, daemon_type_,
      progress_type_, task_type_;
  eprosima::fastdds::dds::DataReader* queries_ = nullptr;
  eprosima::fastdds::dds::DataReader* changes_ = nullptr;
  eprosima::fastdds::dds::DataWriter* updates_ = nullptr;
  eprosima::fastdds::dds::DataWriter* status_ = nullptr;
  eprosima::fastdds::dds::DataWriter* daemons_ = nullptr;
  eprosima::fastdds::dds::DataReader* status_reader_ = nullptr;
  wire::LatestSamples<msg::DaemonInfo> daemons_seen_;  // every daemon's announcement, with its sender
  wire::LatestSamples<msg::SceneStatus> statuses_;     // only from the participant announcing the daemon named
  eprosima::fastdds::dds::DataWriter* tasks_ = nullptr;
  eprosima::fastdds::dds::DataReader* tasks_reader_ = nullptr;
  wire::LatestSamples<msg::SceneTask> tasks_seen_;  // only from the participant announcing the daemon named
  std::mutex tasks_mutex_;
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> tasks_published_;  // scene: generation, events
  eprosima::fastdds::dds::DataReader* daemons_reader_ = nullptr;
  std::unique_ptr<ReplyRoutes> routes_;  // each client's replies in its own partition
  std::atomic<bool> accepting_{true};
  std::string own_identity_;  // this participant's GUID prefix (wire::identity_of)
  std::atomic<bool> id_elsewhere_{false};
  std::atomic<bool> id_contested_{false};
  std::unique_ptr<SelfProbe> probe_;
  std::uint64_t joined_ms_ = 0;  // this daemon's DaemonInfo.joined_ms (set before any reader exists)
  std::string host_;             // this machine's name, as this daemon announces it (set with joined_ms_)
  mutable std::mutex namesake_mutex_;
  std::string older_namesake_;

  void write_reply(const msg::Reply& reply);
  void note_namesake(const msg::DaemonInfo& other, const std::string& sender);
  /// True on a thread inside this object's DDS request callback.
  static thread_local bool in_dds_callback;
  /// Replies waiting for their client's reader at most; past this, a reply is dropped (logged;
  /// its client retries).
  static constexpr std::size_t kMaxOutbox = 16384;
  void send_pending_replies();  // the sender thread

  struct PendingReply {
    msg::Reply reply;
    std::chrono::steady_clock::time_point deadline;
  };
  std::mutex outbox_mutex_;
  std::condition_variable outbox_wake_;
  std::list<PendingReply> outbox_;
  bool closing_ = false;
  std::thread sender_;
};

}  // namespace ispars::server
