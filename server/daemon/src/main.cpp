// isparsd: the Inspection-SPARS roadmap daemon.

#include <fastrtps/attributes/LibrarySettingsAttributes.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <functional>
#include <iostream>

#include "ispars/params/input_error.hpp"
#include "ispars/server/daemon.hpp"
#include "ispars/server/daemon_flags.hpp"
#include "ispars/server/daemon_log.hpp"
#include "ispars/server/daemon_settings.hpp"
#include "ispars/server/stop_watchdog.hpp"
#include "ispars/wire/participant.hpp"

namespace {

using ispars::server::DaemonConfig;

// Blocks the stop signals in every thread (threads made later inherit it); main waits for them.
sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGHUP);  // never a stop: a reload (see serve)
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

// The daemon hears its own probe samples through the transport, not through a shortcut inside
// the process: its health (operator_endpoints.cpp, self_probe.hpp) then covers its sockets and
// receive threads. Not under DDS Security: there a daemon never heard its own announcements
// through the transport (measured with Fast DDS 2.9.1: /healthz went 503; the cause was not looked
// into), so a secured daemon keeps in-process delivery and has no probe.
void deliver_through_the_transport(const DaemonConfig& config) {
  if (!config.participant.security.empty()) return;
  eprosima::fastrtps::LibrarySettingsAttributes library;
  library.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(library);
}

// Runs the daemon until SIGTERM or SIGINT (SIGHUP reloads what `configure` reads now); its exit status.
int serve(DaemonConfig config, const std::function<DaemonConfig()>& configure, const sigset_t& signals) {
  ispars::server::start_daemon_log(config);
  ispars::wire::route_fastdds_log_to_spdlog();
  // Undone when this scope ends, after the daemon (declared below) is gone, on every path.
  struct StopRouting {
    ~StopRouting() { ispars::wire::stop_fastdds_log_routing(); }
  } stop_routing;
  deliver_through_the_transport(config);
  ispars::server::Daemon daemon(std::move(config));
  int signal = 0;
  for (;;) {
    sigwait(&signals, &signal);
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
  ispars::server::arm_stop_watchdog();  // from here the process ends within kStopDeadline
  // For tests only (DaemonStopWatchdogTest): the stop stalls here, as a Fast DDS deadlock once
  // stalled one, until the watchdog ends the process.
  if (std::getenv("ISPARS_TEST_STALL_STOP") != nullptr) {
    ispars::server::note_stop_step("a stall a test asked for (ISPARS_TEST_STALL_STOP)");
    for (;;) ::pause();
  }
  daemon.shutdown();
  ispars::server::note_stop_step("the daemon's destruction");
  return daemon.displaced() ? ispars::server::kExitServerIdTaken : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"isparsd: holds scenes and persistent Inspection-SPARS roadmaps, and serves them over DDS"};
  std::string config_file;
  app.add_option("-c,--config", config_file, "YAML config file (flags override it)")->check(CLI::ExistingFile);
  bool print_config = false;
  app.add_flag("--print-config", print_config, "print the config the file and flags make, as a config file, and exit");
  const ispars::server::DaemonFlags flags(app);  // one per setting (daemon_settings.hpp)
  CLI11_PARSE(app, argc, argv);
  const sigset_t stop_signals = block_stop_signals();

  // The config: the file (read again on SIGHUP), then the flags over it.
  const auto configure = [&] {
    DaemonConfig config = config_file.empty() ? DaemonConfig{} : ispars::server::load_daemon_config(config_file);
    if (config_file.empty()) config.participant.domain = ispars::wire::domain_from_environment();
    flags.apply(config);
    ispars::server::check_together(config);
    return config;
  };
  try {
    DaemonConfig config = configure();
    if (print_config) {
      std::cout << ispars::server::to_yaml(config);
      return 0;
    }
    const int status = serve(std::move(config), configure, stop_signals);
    ispars::server::note_stop_step("the process's exit (static destructors: Fast DDS's participant factory)");
    return status;
  } catch (const ispars::params::InputError& e) {
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
