#pragma once
// isparsd: the roadmap service. Holds loaded scenes and their persistent roadmaps
// (RoadmapSession), answers requests addressed to it over DDS, runs builds on a worker pool, and
// publishes each committed batch and every status change.

#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "daemon_config.hpp"
#include "ispars.h"
#include "ispars/service/roadmap_session.hpp"
#include "reply_cache.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::server {

class DdsEndpoints;

/// This machine's host name ("host" when it cannot be read).
[[nodiscard]] std::string host_name();

class Daemon {
 public:
  /// Joins the domain, reloads every stored roadmap and starts serving. Throws on a bad data
  /// directory, a data directory held by another daemon, or DDS setup failure.
  explicit Daemon(DaemonConfig config);
  /// Same as shutdown().
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// Stops: running builds commit their current chunk and stop, requests stop being served,
  /// final statuses are published, and the participant leaves.
  void shutdown();

  [[nodiscard]] const std::string& server_id() const { return config_.server_id; }

  /// Called by the DDS layer for every request addressed to this daemon (any thread).
  void enqueue(msg::Request request);

 private:
  friend class DdsEndpoints;

  void serve_requests();
  void handle(const msg::Request& request);
  msg::Reply answer(const msg::Request& request);
  void check_request(const msg::Request& request) const;

  // Request kinds.
  void list_scenes(msg::Reply& reply) const;
  void load_scene(const std::string& name, msg::Reply& reply);
  void unload_scene(const std::string& name, msg::Reply& reply);
  void build(const msg::Request& request, msg::Reply& reply);
  void extend(const msg::Request& request, msg::Reply& reply);
  void snapshot(const msg::Request& request, msg::Reply& reply);
  void tour(const msg::Request& request, msg::Reply& reply);

  std::shared_ptr<RoadmapSession> session(const std::string& name) const;  // InputError when not loaded
  std::shared_ptr<RoadmapSession> session_or_null(const std::string& name) const;
  std::shared_ptr<RoadmapSession> open_session(const std::string& name);
  void schedule(const std::shared_ptr<RoadmapSession>& session);
  void publish_status(const std::string& scene);
  void publish_unloaded(const std::string& name);
  void announce();
  void recover_stored_roadmaps();
  msg::SceneStatus status_message(const RoadmapSession& session) const;

  DaemonConfig config_;
  int lock_fd_ = -1;
  std::atomic<bool> stopping_{false};
  ReplyCache cache_;

  mutable std::mutex status_mutex_;   // stamps statuses in order
  mutable std::uint64_t status_seq_ = 0;
  std::mutex publish_mutex_;          // writes statuses in stamp order
  mutable std::mutex sessions_mutex_;
  std::map<std::string, std::shared_ptr<RoadmapSession>> sessions_;
  std::set<std::string> loading_;  // names being loaded (reserved)

  struct EncodedSnapshot {
    std::string scene;
    std::uint64_t generation = 0;
    std::uint64_t version = 0;
    std::shared_ptr<const std::string> bytes;
  };
  std::mutex snapshots_mutex_;
  std::deque<EncodedSnapshot> snapshots_;  // the few most recent, for chunked transfer

  std::mutex queue_mutex_;
  std::condition_variable queue_wake_;
  std::deque<msg::Request> queue_;
  std::vector<std::thread> request_threads_;

  std::unique_ptr<WorkerPool> workers_;
  std::unique_ptr<WorkerPool> tour_workers_;  // tours run here, never on a request thread
  // Tours admitted (queued or running), bounded; the stop flag of each running tour by scene,
  // set by CANCEL on the scene and at shutdown.
  std::mutex tours_mutex_;
  std::size_t tours_admitted_ = 0;
  std::multimap<std::string, std::shared_ptr<std::atomic<bool>>> running_tours_;
  /// Sets the stop flag of every running tour on `scene` (every scene when empty); returns how many.
  std::size_t stop_tours(const std::string& scene);
  std::unique_ptr<DdsEndpoints> dds_;
  bool shut_down_ = false;
};

}  // namespace ispars::server
