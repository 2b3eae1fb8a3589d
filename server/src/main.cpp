// isparsd: the Inspection-SPARS roadmap daemon.

#include <CLI/CLI.hpp>
#include <fastrtps/attributes/LibrarySettingsAttributes.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <iostream>

#include "daemon.hpp"
#include "daemon_log.hpp"
#include "ispars/input_error.hpp"
#include "ispars/wire/participant.hpp"

int main(int argc, char** argv) {
  using ispars::server::DaemonConfig;
  CLI::App app{"isparsd: holds scenes and persistent Inspection-SPARS roadmaps, and serves them over DDS"};
  std::string config_file;
  std::string data_dir, scene_dir, profile_file, profile_name, log_level, server_id, security;
  std::optional<int> domain;
  std::optional<unsigned> workers;
  std::optional<unsigned> build_threads;
  std::optional<std::uint64_t> max_samples;
  std::optional<std::size_t> compact_every;
  std::optional<std::size_t> request_queue;
  std::optional<std::uint64_t> memory_budget_mb;
  std::optional<std::uint32_t> discovery_wait_ms;
  std::optional<std::uint64_t> log_file_mb;
  std::string log_file, metrics;
  std::vector<std::string> preload;
  app.add_option("-c,--config", config_file, "YAML config file (flags override it)")->check(CLI::ExistingFile);
  app.add_option("--data-dir", data_dir, "where roadmaps are stored");
  app.add_option("--scene-dir", scene_dir, "the only directory scenes are loaded from");
  app.add_option("--domain", domain, "DDS domain id (default: config, else $ISPARS_DOMAIN, else 0)");
  app.add_option("--workers", workers, "build worker threads");
  app.add_option("--build-threads", build_threads, "threads each build uses (the roadmap is the same for any count)");
  app.add_option("--profile-file", profile_file, "Fast DDS XML profiles file (default: built-in localhost only)");
  app.add_option("--profile-name", profile_name, "participant profile in the profiles file");
  app.add_option("--security", security,
                 "DDS Security identity directory (deploy/security/make-keystore.sh); default: no security");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error");
  app.add_option("--server-id", server_id, "this daemon's unique id on the domain (default HOST-PID)");
  app.add_option("--max-samples", max_samples, "largest build or extend a request may ask for");
  app.add_option("--compact-every", compact_every, "journal commits between compacted snapshots");
  app.add_option("--load", preload, "scenes to load at start");
  app.add_option("--memory-budget-mb", memory_budget_mb,
                 "MiB all loaded roadmaps may be expected to hold; builds past it are refused (0: half of RAM)");
  app.add_option("--request-queue", request_queue,
                 "requests each lane (quick, slow) holds waiting before it answers busy (1..100000, default 256)");
  app.add_option("--discovery-wait-ms", discovery_wait_ms,
                 "how long to listen for the other daemons before claiming scenes (100..60000, default 1000)");
  app.add_option("--log-file", log_file, "log to this file, rotated by size and reopened on SIGHUP (default: stdout)");
  app.add_option("--log-file-mb", log_file_mb, "MiB a log file reaches before it is rotated (1..100000, default 64)");
  app.add_option("--metrics", metrics,
                 "ADDRESS:PORT serving /metrics (Prometheus) and /healthz over HTTP, e.g. 127.0.0.1:9464 "
                 "(default: none)");
  CLI11_PARSE(app, argc, argv);

  // Block the stop signals in every thread; main waits for them below.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGHUP);  // never a stop: a reload (see below)
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  // The config: the file (read again on SIGHUP), then the flags over it.
  const auto configure = [&] {
    DaemonConfig config = config_file.empty() ? DaemonConfig{} : ispars::server::load_daemon_config(config_file);
    if (config_file.empty()) config.domain = ispars::wire::domain_from_environment();
    if (!data_dir.empty()) config.data_dir = data_dir;
    if (!scene_dir.empty()) config.scene_dir = scene_dir;
    if (domain) config.domain = *domain;
    if (workers) config.workers = *workers;
    if (build_threads) config.build_threads = *build_threads;
    if (!profile_file.empty()) config.profile_file = profile_file;
    if (!profile_name.empty()) config.profile_name = profile_name;
    if (!security.empty()) config.security = security;
    if (!log_level.empty()) config.log_level = log_level;
    if (!server_id.empty()) config.server_id = server_id;
    if (max_samples) config.max_samples = *max_samples;
    if (compact_every) config.snapshot_compact_every = *compact_every;
    if (request_queue) config.request_queue = *request_queue;
    if (memory_budget_mb) config.memory_budget_mb = *memory_budget_mb;
    if (discovery_wait_ms) config.discovery_wait_ms = *discovery_wait_ms;
    if (!log_file.empty()) config.log_file = log_file;
    if (log_file_mb) config.log_file_mb = *log_file_mb;
    if (!metrics.empty()) config.metrics = ispars::server::parse_listen_address(metrics, "command line", "--metrics");
    config.preload.insert(config.preload.end(), preload.begin(), preload.end());
    ispars::server::check_daemon_config(config, config_file.empty() ? "command line" : config_file);
    return config;
  };

  try {
    DaemonConfig config = configure();
    ispars::server::start_daemon_log(config);
    ispars::wire::route_fastdds_log_to_spdlog();
    // Undone when this scope ends, after the daemon (declared below) is gone, on every path.
    struct StopRouting {
      ~StopRouting() { ispars::wire::stop_fastdds_log_routing(); }
    } stop_routing;

    // The daemon hears its own probe samples through the transport, not through a shortcut inside
    // the process: its health (daemon_operator.cpp, self_probe.hpp) then covers its sockets and
    // receive threads. Not under DDS Security: there a daemon never heard its own announcements
    // through the transport (measured with Fast DDS 2.9.1: /healthz went 503; the cause was not looked
    // into), so a secured daemon keeps in-process delivery and has no probe.
    if (config.security.empty()) {
      eprosima::fastrtps::LibrarySettingsAttributes library;
      library.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
      eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(library);
    }
    ispars::server::Daemon daemon(std::move(config));
    int signal = 0;
    for (;;) {
      sigwait(&stop_signals, &signal);
      if (signal != SIGHUP) break;
      try {
        daemon.reload(configure());
      } catch (const std::exception& e) {
        spdlog::error("SIGHUP: the config was not reloaded: {}; serving on as before", e.what());
      }
    }
    if (daemon.displaced()) {
      spdlog::error("stopping: an older daemon serves server id '{}'", daemon.server_id());
    } else {
      spdlog::info("{}: finishing the current batches and stopping", signal == SIGTERM ? "SIGTERM" : "SIGINT");
    }
    daemon.shutdown();
    return daemon.displaced() ? ispars::server::kExitServerIdTaken : 0;
  } catch (const ispars::InputError& e) {
    std::cerr << "isparsd: " << e.what() << "\n";
    return 2;
  } catch (const ispars::server::ServerIdTaken& e) {
    std::cerr << "isparsd: " << e.what() << "\n";
    return ispars::server::kExitServerIdTaken;
  } catch (const std::exception& e) {
    std::cerr << "isparsd: " << e.what() << "\n";
    return 1;
  }
}
