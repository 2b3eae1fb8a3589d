#pragma once
// Where isparsd's log goes: standard output (the journal under systemd) or a file rotated by
// size. The log's sink can be replaced while other threads log, which is how SIGHUP reopens the
// file after an outside rotation (logrotate) and applies a new level.

#include "ispars/server/daemon_config.hpp"

namespace ispars::server {

/// Makes the default logger write where `config` says (log_file, log_file_mb) at config.log_level.
/// Throws std::runtime_error when the log file cannot be opened.
void start_daemon_log(const DaemonConfig& config);

/// Reopens the log where `config` says, at its level. On failure keeps the current log, logs the
/// error there and returns false.
bool reopen_daemon_log(const DaemonConfig& config);

}  // namespace ispars::server
