#include "ispars/server/daemon_metrics.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <fstream>

namespace ispars::server {
namespace {

const char* outcome_name(RequestOutcome outcome) {
  switch (outcome) {
    case RequestOutcome::ok:
      return "ok";
    case RequestOutcome::refused:
      return "refused";
    case RequestOutcome::failed:
      return "failed";
    case RequestOutcome::busy:
      return "busy";
  }
  return "unknown";
}

// A label value as the exposition format wants it: backslash, quote and newline escaped.
std::string label(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

void family(std::string& out, const char* name, const char* type, const char* help) {
  fmt::format_to(std::back_inserter(out), "# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
}

}  // namespace

void DaemonMetrics::count_request(std::string_view operation, RequestOutcome outcome, double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{std::string(operation), outcome}];
  Latency& l = latency_[std::string(operation)];
  std::size_t bucket = 0;
  while (bucket < kLatencyBuckets.size() && seconds > kLatencyBuckets[bucket]) ++bucket;
  if (bucket < kLatencyBuckets.size()) ++l.buckets[bucket];
  ++l.count;
  l.sum += seconds;
}

void DaemonMetrics::observe_samples(const std::string& scene, std::uint64_t samples_done) {
  std::lock_guard lock(mutex_);
  std::uint64_t& last = last_samples_[scene];
  if (samples_done > last) samples_built_ += samples_done - last;
  last = samples_done;
}

std::string DaemonMetrics::render(const DaemonGauges& g) const {
  std::string out;
  auto line = [&](std::string_view text) { out.append(text); };
  {
    std::lock_guard lock(mutex_);
    family(out, "ispars_requests_total", "counter", "Requests answered, by operation and outcome.");
    for (const auto& [key, n] : requests_) {
      line(fmt::format("ispars_requests_total{{operation=\"{}\",outcome=\"{}\"}} {}\n", label(key.first),
                       outcome_name(key.second), n));
    }
    family(out, "ispars_request_duration_seconds", "histogram",
           "Seconds from taking a request off its lane to its reply, by operation.");
    for (const auto& [operation, l] : latency_) {
      std::uint64_t cumulative = 0;
      for (std::size_t i = 0; i < kLatencyBuckets.size(); ++i) {
        cumulative += l.buckets[i];
        line(fmt::format("ispars_request_duration_seconds_bucket{{operation=\"{}\",le=\"{}\"}} {}\n", label(operation),
                         kLatencyBuckets[i], cumulative));
      }
      line(fmt::format("ispars_request_duration_seconds_bucket{{operation=\"{}\",le=\"+Inf\"}} {}\n", label(operation),
                       l.count));
      line(fmt::format("ispars_request_duration_seconds_sum{{operation=\"{}\"}} {}\n", label(operation), l.sum));
      line(fmt::format("ispars_request_duration_seconds_count{{operation=\"{}\"}} {}\n", label(operation), l.count));
    }
    family(out, "ispars_samples_built_total", "counter", "Samples added to roadmaps by builds and extends.");
    line(fmt::format("ispars_samples_built_total {}\n", samples_built_));
  }
  // Every state on every scrape (0 when none), so a series never vanishes.
  std::map<std::string, std::uint64_t> by_state{{"empty", 0},     {"idle", 0},     {"queued", 0},
                                                {"replaying", 0}, {"building", 0}, {"failed", 0}};
  for (const SceneGauges& s : g.scenes) ++by_state[s.state];
  family(out, "ispars_scenes", "gauge", "Loaded scenes, by state.");
  for (const auto& [state, n] : by_state) line(fmt::format("ispars_scenes{{state=\"{}\"}} {}\n", label(state), n));
  const std::pair<const char*, std::uint64_t SceneGauges::*> per_scene[] = {
      {"ispars_roadmap_samples", &SceneGauges::samples},
      {"ispars_roadmap_vertices", &SceneGauges::vertices},
      {"ispars_roadmap_edges", &SceneGauges::edges},
      {"ispars_roadmap_pois", &SceneGauges::pois},
      {"ispars_roadmap_pois_covered", &SceneGauges::pois_covered}};
  for (const auto& [name, field] : per_scene) {
    family(out, name, "gauge", "Of each loaded scene's published roadmap.");
    for (const SceneGauges& s : g.scenes) line(fmt::format("{}{{scene=\"{}\"}} {}\n", name, label(s.scene), s.*field));
  }
  family(out, "ispars_update_subscribers", "gauge", "Readers matched to this daemon's roadmap updates.");
  line(fmt::format("ispars_update_subscribers {}\n", g.update_subscribers));
  family(out, "ispars_reply_clients", "gauge",
         "Clients whose reply routes are ready (reply reader matched and route acknowledged).");
  line(fmt::format("ispars_reply_clients {}\n", g.reply_clients));
  family(out, "ispars_reply_routes", "gauge", "Reply routes held (one per client whose reply reader is present).");
  line(fmt::format("ispars_reply_routes {}\n", g.reply_routes));
  family(out, "ispars_other_daemons", "gauge", "Other live daemons announced on the domain.");
  line(fmt::format("ispars_other_daemons {}\n", g.other_daemons));
  family(out, "ispars_fleet_tasks_known", "gauge",
         "Inspection tasks other daemons published that this daemon holds, should it take their scenes over.");
  line(fmt::format("ispars_fleet_tasks_known {}\n", g.fleet_tasks_known));
  family(out, "ispars_fleet_handed_over", "gauge",
         "Stored copies this daemon handed over to the daemon that outweighed it, by scene and winner: kept on "
         "disk, not served here (what it had accepted goes with the scene).");
  for (const auto& [scene, to] : g.handed_over) {
    line(fmt::format("ispars_fleet_handed_over{{scene=\"{}\",to=\"{}\"}} 1\n", label(scene), label(to)));
  }
  family(out, "ispars_fleet_declined_scenes", "gauge",
         "Scenes this daemon declines after its takeover of them failed, until it tries again.");
  line(fmt::format("ispars_fleet_declined_scenes {}\n", g.declined));
  family(out, "ispars_stored_unservable", "gauge",
         "Stored copies this daemon keeps and does not offer, by scene: damaged, or made by another builder version "
         "or on another version of the scene file (the reason is in the scenes list and the log).");
  for (const std::string& scene : g.unservable) {
    line(fmt::format("ispars_stored_unservable{{scene=\"{}\"}} 1\n", label(scene)));
  }
  family(out, "ispars_memory_budget_bytes", "gauge", "Memory all loaded roadmaps may be expected to hold.");
  line(fmt::format("ispars_memory_budget_bytes {}\n", g.memory_budget_bytes));
  family(out, "ispars_memory_reserved_bytes", "gauge", "Of the budget: the loaded roadmaps' estimated peaks.");
  line(fmt::format("ispars_memory_reserved_bytes {}\n", g.memory_reserved_bytes));
  family(out, "ispars_memory_leased_bytes", "gauge", "Of the budget: snapshot encodings and tours, estimated.");
  line(fmt::format("ispars_memory_leased_bytes {}\n", g.memory_leased_bytes));
  family(out, "process_resident_memory_bytes", "gauge", "Resident memory of the daemon.");
  line(fmt::format("process_resident_memory_bytes {}\n", g.resident_bytes));
  return out;
}

std::uint64_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGE_SIZE));
}

}  // namespace ispars::server
