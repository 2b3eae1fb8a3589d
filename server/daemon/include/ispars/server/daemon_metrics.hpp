#pragma once
// What an operator scrapes from isparsd: requests by operation and outcome with a latency
// histogram, samples built, and gauges read at scrape time (scenes by state, roadmap sizes,
// subscribers, memory), in the Prometheus text exposition format (version 0.0.4).

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ispars::server {

/// How a request ended: answered, refused for its input, failed inside the daemon, or refused
/// because its lane was full.
enum class RequestOutcome { ok, refused, failed, busy };

/// One loaded scene as a scrape sees it.
struct SceneGauges {
  std::string scene;
  std::string state;  ///< "idle", "building", ... as in ispars stats
  std::uint64_t samples = 0;
  std::uint64_t vertices = 0;
  std::uint64_t edges = 0;
  std::uint64_t pois = 0;
  std::uint64_t pois_covered = 0;
};

/// The values read at scrape time.
struct DaemonGauges {
  std::vector<SceneGauges> scenes;
  std::uint64_t update_subscribers = 0;  ///< readers matched to the updates writer
  std::uint64_t reply_clients = 0;       ///< clients whose reply routes are ready
  std::uint64_t reply_routes = 0;        ///< reply routes held (a publisher and two writers each)
  std::uint64_t resident_bytes = 0;
  double memory_budget_bytes = 0;
  double memory_reserved_bytes = 0;  ///< the loaded scenes' roadmap peaks (memory_budget.hpp)
  double memory_leased_bytes = 0;    ///< held by snapshot encodings and tours now
  std::uint64_t other_daemons = 0;
  std::uint64_t fleet_tasks_known = 0;  ///< Other daemons' tasks this daemon holds for a takeover.
  /// Copies this daemon handed over (scene, winner): kept on disk, served by the winner.
  std::vector<std::pair<std::string, std::string>> handed_over;
  std::uint64_t declined = 0;  ///< Scenes declined after a failed takeover, until its retry.
  /// Stored copies not offered to the fleet (damaged, another builder version or scene file).
  std::vector<std::string> unservable;
};

/// Request counters and latency histograms, safe to update from many threads.
class DaemonMetrics {
 public:
  /// Upper bounds (seconds) of the latency histogram's buckets; +Inf follows.
  static constexpr std::array<double, 12> kLatencyBuckets{0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025,
                                                          0.05,   0.1,   0.25,   0.5,   1.0,  5.0};

  /// Counts one answered request of `operation` ("stats", "build", ...).
  void count_request(std::string_view operation, RequestOutcome outcome, double seconds);
  /// Notes a scene's samples done; increases are counted as samples built (a rebuild from zero
  /// counts afresh).
  void observe_samples(const std::string& scene, std::uint64_t samples_done);
  /// The whole exposition: these counters, then `gauges`.
  [[nodiscard]] std::string render(const DaemonGauges& gauges) const;

 private:
  struct Latency {
    std::array<std::uint64_t, kLatencyBuckets.size()> buckets{};  // non-cumulative
    std::uint64_t count = 0;
    double sum = 0;
  };
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, RequestOutcome>, std::uint64_t> requests_;
  std::map<std::string, Latency> latency_;  // by operation
  std::map<std::string, std::uint64_t> last_samples_;
  std::uint64_t samples_built_ = 0;
};

/// This process's resident memory in bytes (0 when /proc cannot be read).
[[nodiscard]] std::uint64_t resident_memory_bytes();

}  // namespace ispars::server
