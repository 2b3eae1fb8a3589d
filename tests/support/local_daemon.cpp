#include "support/local_daemon.hpp"

#include <algorithm>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace ispars::client {

int random_domain() {
  std::random_device rd;
  return 100 + static_cast<int>(rd() % 133);
}

void write_tank_tower_scenes(const std::filesystem::path& dir, const std::vector<std::string>& names) {
  std::filesystem::create_directories(dir);
  int seed = 1;
  for (const std::string& name : names) {
    std::ofstream(dir / (name + ".yaml")) << "procedural: {kind: tank_tower, seed: " << seed++ << "}\n";
  }
}

ClientOptions local_client_options(int domain) {
  ClientOptions options;
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

LocalDaemon::LocalDaemon(const std::string& daemon_binary, int domain, std::filesystem::path data_dir,
                         std::filesystem::path scene_dir, std::string server_id, std::vector<std::string> extra_args,
                         const std::string& probe_security)
    : domain_(domain), server_id_(std::move(server_id)) {
  log_path_ = data_dir.parent_path() / (server_id_ + "-" + data_dir.filename().string() + "-" + std::to_string(::getpid()) + ".log");
  std::vector<std::string> args = {daemon_binary, "--domain", std::to_string(domain), "--data-dir", data_dir.string(),
                                   "--scene-dir", scene_dir.string(), "--server-id", server_id_, "--log-level", "debug"};
  // One daemon per test mostly: listening 300 ms for others is plenty on localhost (fleet tests
  // that start several at once pass their own).
  if (std::find(extra_args.begin(), extra_args.end(), "--discovery-wait-ms") == extra_args.end()) {
    args.insert(args.end(), {"--discovery-wait-ms", "300"});
  }
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int fd = ::open(log_path_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  // Ready when it says it serves (it announces itself earlier, while it listens for the other
  // daemons) and a client sees its announcement.
  ClientOptions probe_options = local_client_options(domain);
  probe_options.participant.security = probe_security;
  Client probe(probe_options);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!alive()) throw std::runtime_error("isparsd exited at start:\n" + log());
    if (log().find("isparsd " + server_id_ + " serving on DDS domain") != std::string::npos) {
      for (const auto& d : probe.daemons()) {
        if (d.server_id() == server_id_) return;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  throw std::runtime_error("isparsd " + server_id_ + " did not announce itself within 20 s:\n" + log());
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

int LocalDaemon::wait_exit() {
  int status = 0;
  if (::waitpid(pid_, &status, 0) != pid_) return -1000;
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

int LocalDaemon::terminate() {
  if (pid_ <= 0) return -1000;
  ::kill(pid_, SIGTERM);
  return wait_exit();
}

void LocalDaemon::kill9() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  wait_exit();
}

std::string LocalDaemon::log() const {
  std::ifstream in(log_path_);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace ispars::client
