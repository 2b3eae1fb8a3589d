#include "ispars/local/local_daemon.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

extern char** environ;  // NOLINT: the process environment (POSIX)

namespace ispars::local {

int random_domain() {
  // A participant's ports are 7400 + 250 * domain + 10 (+ 1 for data) + 2 * id, and Fast DDS 2.9
  // never reuses an id within a process (deleted participants included).
  // Domains are spaced four apart: a process's participant number n listens on ports up to
  // 7400 + 250 * domain + 11 + 2 * n, so a test with more than 125 participants (the 300-client
  // test has over 300) reaches the ports of the next domains, where another test's daemon hears
  // it. Seen 2026-11-27: a daemon on domain 187 discovered the raw peers of the 300-client test,
  // warned that its multicast port 54150 was taken, and both tests failed. Four apart leaves each
  // test 375 participants.
  // Every port of every test domain lies below Linux's ephemeral ports (32768..60999), which any
  // socket bound to port 0 may get. Cyclone DDS reads the datagrams that reach its transmit socket
  // (an ephemeral port, new for each of its domain instances), and neither Fast DDS 2.9.1 nor
  // Cyclone tells one domain's discovery from another's (Fast DDS sends and checks no domain id):
  // when a fresh client of the vendor test, on domain 192, had its transmit socket on 54432, one of
  // the ports a daemon on domain 188 sends its announcements to, the client discovered that daemon
  // and was answered by it (19 replies of 20, in a network namespace whose ephemeral range was
  // 54432..54433). Seen 2026-11-27 in a full run, most likely so: 40 Cyclone clients in a row of
  // the vendor test were answered by the 300-client test's daemon on domain 188 (after one contact,
  // the next ones follow: Fast DDS 2.9.1 keeps a Cyclone participant that left until its lease
  // runs out, announcing itself to its port, which the next fresh client takes again). The domains
  // used to be 100..200, all of whose ports are ephemeral ones.
  constexpr int kFirst = 1;  // not 0, the default domain of a daemon and a client run by hand
  constexpr int kSpacing = 4;
  constexpr int kDomains = 25;  // 1, 5, ..., 97
  constexpr int kParticipants = 375;
  static_assert(7400 + 250 * (kFirst + kSpacing * (kDomains - 1)) + 11 + 2 * kParticipants < 32768,
                "a test domain's ports reach Linux's ephemeral ports");
  // Tests run in parallel, each in its own process: a domain is taken by locking its file (held
  // until the process exits), so no two running tests share one. Of the free domains, the one
  // taken longest ago is tried first (each file's time is set when it is taken): a domain a test
  // has just left may still carry what its daemons announced (a daemon killed with kill -9 is seen
  // until its lease runs out), and a test that drew it again would meet a namesake.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "ispars-test-domains";
  std::filesystem::create_directories(dir);
  std::vector<std::pair<std::filesystem::file_time_type, int>> order;
  std::random_device rd;
  const int start = static_cast<int>(rd() % kDomains);
  for (int i = 0; i < kDomains; ++i) {
    const int domain = kFirst + kSpacing * ((start + i) % kDomains);
    std::error_code ec;
    const auto taken = std::filesystem::last_write_time(dir / (std::to_string(domain) + ".lock"), ec);
    order.emplace_back(ec ? std::filesystem::file_time_type::min() : taken, domain);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [taken, domain] : order) {
    const int fd = ::open((dir / (std::to_string(domain) + ".lock")).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      ::futimens(fd, nullptr);  // taken now
      return domain;            // fd stays open: the lock lives with the process
    }
    ::close(fd);
  }
  throw std::runtime_error("every test DDS domain (1, 5, ..., 97) is taken by a running test");
}

void write_tank_tower_scenes(const std::filesystem::path& dir, const std::vector<std::string>& names) {
  std::filesystem::create_directories(dir);
  int seed = 1;
  for (const std::string& name : names) {
    std::ofstream(dir / (name + ".yaml")) << "procedural: {kind: tank_tower, seed: " << seed++ << "}\n";
  }
}

client::ClientOptions local_client_options(int domain) {
  client::ClientOptions options;
  options.participant.domain = domain;
  options.participant.name = "ispars local client";
  options.timeout = std::chrono::seconds(30);
  return options;
}

std::filesystem::path make_keystore(const std::string& script, const std::filesystem::path& dir,
                                    const std::vector<std::string>& identities) {
  std::string command = "'" + script + "' '" + dir.string() + "'";
  for (const std::string& id : identities) command += " '" + id + "'";
  command += " 2>&1";
  std::string output;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot run " + script);
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  if (::pclose(pipe) != 0) throw std::runtime_error(command + " failed:\n" + output);
  return dir;
}

namespace {

// The value after `flag` in `args`, or nullptr.
const std::string* flag_value(const std::vector<std::string>& args, std::string_view flag) {
  const auto it = std::find(args.begin(), args.end(), flag);
  return it != args.end() && it + 1 != args.end() ? &*(it + 1) : nullptr;
}

bool has_flag(const std::vector<std::string>& args, std::string_view flag) {
  return std::find(args.begin(), args.end(), flag) != args.end();
}

// The daemon's command line: `prefix`, the program, its identity and folders, then the test's
// own flags after the defaults they may override.
std::vector<std::string> daemon_command(const std::string& daemon_binary, int domain,
                                        const std::filesystem::path& data_dir, const std::filesystem::path& scene_dir,
                                        const std::string& server_id, const std::vector<std::string>& extra_args,
                                        const std::vector<std::string>& prefix) {
  std::vector<std::string> args = prefix;
  args.insert(args.end(), {daemon_binary, "--domain", std::to_string(domain), "--data-dir", data_dir.string(),
                           "--scene-dir", scene_dir.string(), "--server-id", server_id});
  // Debug logs unless the caller sets the level itself, or through a config file (which a flag
  // would override).
  if (!has_flag(extra_args, "--log-level") && !has_flag(extra_args, "--config")) {
    args.insert(args.end(), {"--log-level", "debug"});
  }
  // One daemon per test mostly: listening 300 ms for others is plenty on localhost (fleet tests
  // that start several at once pass their own).
  if (!has_flag(extra_args, "--discovery-wait-ms")) args.insert(args.end(), {"--discovery-wait-ms", "300"});
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  return args;
}

}  // namespace

LocalDaemon::LocalDaemon(const std::string& daemon_binary, int domain, std::filesystem::path data_dir,
                         std::filesystem::path scene_dir, std::string server_id, std::vector<std::string> extra_args,
                         const std::string& probe_security, const std::vector<std::string>& environment,
                         std::chrono::seconds ready_within, const std::vector<std::string>& command_prefix,
                         const std::string& probe_profile_file)
    : domain_(domain), server_id_(std::move(server_id)) {
  log_path_ = data_dir.parent_path() /
              (server_id_ + "-" + data_dir.filename().string() + "-" + std::to_string(::getpid()) + ".log");
  // A daemon told to log to a file says "serving" there, not on its output.
  if (const std::string* file = flag_value(extra_args, "--log-file")) own_log_path_ = *file;
  // A restart on the same data directory appends to the same log: only what this run writes counts.
  std::error_code size_error;
  const auto earlier = std::filesystem::file_size(log_path_, size_error);
  const std::size_t log_start = size_error ? 0 : static_cast<std::size_t>(earlier);
  spawn(daemon_command(daemon_binary, domain, data_dir, scene_dir, server_id_, extra_args, command_prefix),
        environment);
  // Ready when it says it serves (it announces itself earlier, while it listens for the other
  // daemons) and a client sees its announcement.
  client::ClientOptions probe_options = local_client_options(domain);
  probe_options.participant.security = probe_security;
  // A daemon on another discovery (a Discovery Server profile, say) is probed the same way.
  if (const std::string* file = flag_value(extra_args, "--profile-file"))
    probe_options.participant.profile_file = *file;
  if (!probe_profile_file.empty()) probe_options.participant.profile_file = probe_profile_file;
  probe_options.timeout = std::chrono::seconds(1);  // each look at the announcements
  wait_until_serving(probe_options, log_start, ready_within);
}

void LocalDaemon::spawn(std::vector<std::string> args, const std::vector<std::string>& environment) {
  // Everything the child needs is made before fork: after it, only async-signal-safe calls.
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> variables;
  for (char** e = environ; *e != nullptr; ++e) variables.emplace_back(*e);
  variables.insert(variables.end(), environment.begin(), environment.end());
  std::vector<char*> envp;
  for (std::string& v : variables) envp.push_back(v.data());
  envp.push_back(nullptr);
  const std::string log_path = log_path_.string();
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
    }
    // Nothing else of the test's: a daemon outliving a crashed test must not hold its files (a
    // lock a build waits on, say).
    ::close_range(3, ~0U, 0);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
}

void LocalDaemon::wait_until_serving(const client::ClientOptions& probe_options, std::size_t log_start,
                                     std::chrono::seconds ready_within) {
  auto probe = std::make_unique<client::Client>(probe_options);
  const auto deadline = std::chrono::steady_clock::now() + ready_within;
  std::optional<std::chrono::steady_clock::time_point> serving_since;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!alive())
      throw std::runtime_error("isparsd exited at start:\n" + log().substr(std::min(log_start, log().size())));
    if (log().find("isparsd " + server_id_ + " serving on DDS domain", log_start) != std::string::npos) {
      if (!serving_since) serving_since = std::chrono::steady_clock::now();
      for (const auto& d : probe->daemons()) {
        if (d.server_id == server_id_) return;
      }
      // Under DDS Security, Debian's Fast DDS 2.9.1 can fail a first handshake for good: a probe
      // that has not heard a serving daemon in 10 s joins again as a new participant.
      if (!probe_options.participant.security.empty() &&
          std::chrono::steady_clock::now() - *serving_since > std::chrono::seconds(10)) {
        probe.reset();
        probe = std::make_unique<client::Client>(probe_options);
        serving_since = std::chrono::steady_clock::now();
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const std::string so_far = log();
  kill9();  // no destructor runs for a constructor that throws: the process must not outlive the test
  throw std::runtime_error("isparsd " + server_id_ + " did not announce itself within " +
                           std::to_string(ready_within.count()) + " s:\n" + so_far);
}

LocalDaemon::~LocalDaemon() {
  if (pid_ > 0 && alive()) terminate();
}

bool LocalDaemon::alive() {
  if (pid_ <= 0) return false;
  int status = 0;
  const pid_t r = ::waitpid(pid_, &status, WNOHANG);
  if (r == pid_) {
    pid_ = -1;
    return false;
  }
  return r == 0;
}

namespace {

// gdb's bound, and its own: a tool that hangs must not hang the stop it reports on.
constexpr const char* kGdbSeconds = "20";
constexpr const char* kGdbKillAfterSeconds = "5";
constexpr std::chrono::seconds kGdbReapDeadline{30};

// reap_within's result for a process that is not (or no longer) a child of this one.
constexpr int kNotAChild = -1;

// Waits up to `limit` for child `pid` to exit: its wait status (or kNotAChild), or nullopt when
// it still runs.
std::optional<int> reap_within(pid_t pid, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    int status = 0;
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) return status;
    if (r < 0 && errno == ECHILD) return kNotAChild;
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// Appends every thread's stack of process `pid` to `log` (gdb -p PID -batch, bounded by timeout).
void append_thread_stacks(pid_t pid, const std::filesystem::path& log) {
  std::ofstream(log, std::ios::app) << "\n==== LocalDaemon: every thread's stack of pid " << pid
                                    << " (gdb), which did not stop in time ====\n";
  std::vector<std::string> args = {
      "/usr/bin/timeout", "--kill-after", kGdbKillAfterSeconds, kGdbSeconds, "/usr/bin/gdb",       "-nx",
      "-batch",           "-p",           std::to_string(pid),  "-ex",       "thread apply all bt"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t gdb = ::fork();
  if (gdb < 0) return;
  if (gdb == 0) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, STDIN_FILENO);
    ::close_range(3, ~0U, 0);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  if (!reap_within(gdb, kGdbReapDeadline)) {
    ::kill(gdb, SIGKILL);
    (void)reap_within(gdb, std::chrono::seconds(1));
  }
  std::ofstream(log, std::ios::app) << "==== LocalDaemon: end of the stacks of pid " << pid << " ====\n";
}

}  // namespace

std::optional<int> LocalDaemon::exit_within(std::chrono::milliseconds limit) {
  if (pid_ <= 0) return std::nullopt;
  const auto status = reap_within(pid_, limit);
  if (!status) return std::nullopt;
  pid_ = -1;
  if (*status == kNotAChild) return -1000;
  return WIFEXITED(*status) ? WEXITSTATUS(*status) : -WTERMSIG(*status);
}

int LocalDaemon::terminate() {
  if (pid_ <= 0) return -1000;
  const pid_t pid = pid_;
  ::kill(pid, SIGTERM);
  if (const auto status = exit_within(kStopDeadline)) return *status;
  stop_timed_out_ = true;
  std::cerr << "LocalDaemon: STOP TIMED OUT: isparsd " << server_id_ << " (pid " << pid << ") did not exit within "
            << kStopDeadline.count() << " s of SIGTERM; every thread's stack goes into " << log_path_.string()
            << ", then SIGKILL" << std::endl;
  append_thread_stacks(pid, log_path_);
  kill9();
  return kStopTimedOut;
}

bool LocalDaemon::kill9() {
  if (pid_ <= 0) return true;
  const pid_t pid = pid_;
  ::kill(pid, SIGKILL);
  if (exit_within(kStopDeadline)) return true;
  stop_timed_out_ = true;
  pid_ = -1;  // not waited for again (by the destructor, say)
  std::cerr << "LocalDaemon: STOP TIMED OUT: isparsd " << server_id_ << " (pid " << pid << ") did not exit within "
            << kStopDeadline.count() << " s of SIGKILL (uninterruptible sleep?); left behind" << std::endl;
  return false;
}

std::string LocalDaemon::log() const {
  std::string text;
  for (const auto& path : {log_path_, own_log_path_}) {
    if (path.empty()) continue;
    std::ifstream in(path, std::ios::binary);
    text.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return text;
}

}  // namespace ispars::local
