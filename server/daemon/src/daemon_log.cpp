#include "ispars/server/daemon_log.hpp"

#include <spdlog/sinks/dist_sink.h>
#include <spdlog/sinks/rotating_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <mutex>

namespace ispars::server {
namespace {

constexpr const char* kPattern = "%Y-%m-%dT%H:%M:%S.%e %l %v";
constexpr std::size_t kKeptFiles = 4;  // isparsd.log.1 .. .4 beside the current one

// The default logger's only sink: it forwards to the current target, swapped under its mutex.
std::shared_ptr<spdlog::sinks::dist_sink_mt> switchboard;
std::mutex switchboard_mutex;

spdlog::sink_ptr make_target(const DaemonConfig& config) {
  spdlog::sink_ptr target;
  if (config.log_file.empty()) {
    target = std::make_shared<spdlog::sinks::stdout_sink_mt>();
  } else {
    target = std::make_shared<spdlog::sinks::rotating_file_sink_mt>(config.log_file.string(),
                                                                    config.log_file_mb * 1024 * 1024, kKeptFiles);
  }
  target->set_formatter(std::make_unique<spdlog::pattern_formatter>(kPattern));
  return target;
}

}  // namespace

void start_daemon_log(const DaemonConfig& config) {
  std::lock_guard lock(switchboard_mutex);
  auto target = make_target(config);  // throws spdlog_ex when the file cannot be opened
  switchboard = std::make_shared<spdlog::sinks::dist_sink_mt>(std::vector<spdlog::sink_ptr>{target});
  auto logger = std::make_shared<spdlog::logger>("isparsd", switchboard);
  logger->set_level(spdlog::level::from_str(config.log_level));
  logger->flush_on(spdlog::level::trace);  // every line: a log file read while the daemon runs is up to date
  spdlog::set_default_logger(std::move(logger));
}

bool reopen_daemon_log(const DaemonConfig& config) {
  std::lock_guard lock(switchboard_mutex);
  if (!switchboard) return false;
  try {
    switchboard->set_sinks({make_target(config)});
  } catch (const std::exception& e) {
    spdlog::error("the log could not be reopened at {}: {}; logging goes on where it was", config.log_file.string(),
                  e.what());
    return false;
  }
  spdlog::default_logger_raw()->set_level(spdlog::level::from_str(config.log_level));
  return true;
}

}  // namespace ispars::server
