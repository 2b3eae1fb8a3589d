#pragma once
// What the gateway's tests share: ispars-web started as a user starts it (optionally inside a
// network namespace), one raw HTTP exchange, and a WebSocket client of a few lines (RFC 6455)
// that sends exactly the headers a test gives it.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/eventually.hpp"
#include "support/test_support.hpp"

extern char** environ;

namespace ispars::test {

// ispars-web as a user starts it, its output in a file; stopped with SIGTERM. `prefix` runs it
// elsewhere (`ip netns exec NS`); `listen` is its --listen.
class Gateway {
 public:
  Gateway(int domain, const std::filesystem::path& scene_dir, const std::filesystem::path& log,
          const std::vector<std::string>& extra = {}, const std::vector<std::string>& prefix = {},
          const std::string& listen = "127.0.0.1:0")
      : log_(log) {
    std::vector<std::string> args = prefix;
    const std::vector<std::string> own = {ISPARS_WEB,         "--domain",  std::to_string(domain),
                                          "--listen",         listen,      "--scene-dir",
                                          scene_dir.string(), "--timeout", "5"};
    args.insert(args.end(), own.begin(), own.end());
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawnp(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    const std::string said = "serving http://" + listen.substr(0, listen.rfind(':')) + ":";
    (void)eventually(
        [&] {
          const std::string text = read_text(log_);
          if (const auto at = text.find(said); at != std::string::npos)
            port_ = std::stoi(text.substr(at + said.size()));
          return port_ != 0 || !alive();
        },
        std::chrono::seconds(20), "the gateway says where it serves", std::chrono::milliseconds(100));  // port() 0 else
  }
  ~Gateway() {
    if (pid_ > 0 && alive()) stop();
  }
  Gateway(const Gateway&) = delete;
  Gateway& operator=(const Gateway&) = delete;
  // SIGTERM, then its exit code; a gateway still running 10 s later is killed and counts as a
  // failed stop (-2), so a hung stop is a named failure instead of a hung test.
  int stop() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    pid_t done = 0;
    (void)eventually(
        [&] {
          done = ::waitpid(pid_, &status, WNOHANG);
          return done != 0;
        },
        std::chrono::seconds(10), "the gateway exits", std::chrono::milliseconds(10));
    if (done == 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      return -2;
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  bool alive() { return pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0; }
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] pid_t pid() const { return pid_; }
  [[nodiscard]] std::string log() const { return read_text(log_); }

 private:
  std::filesystem::path log_;
  pid_t pid_ = -1;
  int port_ = 0;
};

// The resident memory of process `pid` in MB (VmRSS), or -1.
inline double resident_mb(pid_t pid) {
  const std::string status = read_text("/proc/" + std::to_string(pid) + "/status");
  const auto at = status.find("VmRSS:");
  return at == std::string::npos ? -1.0 : std::stod(status.substr(at + 6)) / 1024.0;
}

// A TCP connection to 127.0.0.1:`port` (-1 when refused).
inline int connect_local(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// A port free on 127.0.0.1 just now.
inline int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  ::close(fd);
  return ntohs(address.sin_port);
}

// One HTTP GET on localhost with the gateway's own Host and `headers` ("Name: value\r\n" each):
// the whole response, headers and body.
inline std::string http_response(int port, const std::string& path, const std::string& headers = "",
                                 const std::string& host = "") {
  const int fd = connect_local(port);
  if (fd < 0) return "no connection";
  const std::string request = "GET " + path +
                              " HTTP/1.1\r\nHost: " + (host.empty() ? "127.0.0.1:" + std::to_string(port) : host) +
                              "\r\n" + headers + "Connection: close\r\n\r\n";
  (void)::write(fd, request.data(), request.size());
  std::string response;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) response.append(buffer, static_cast<std::size_t>(n));
  ::close(fd);
  return response;
}

// The same: the status line and the body.
inline std::pair<std::string, std::string> http_get(int port, const std::string& path, const std::string& headers = "",
                                                    const std::string& host = "") {
  const std::string response = http_response(port, path, headers, host);
  const auto line_end = response.find("\r\n");
  const auto body = response.find("\r\n\r\n");
  return {response.substr(0, line_end), body == std::string::npos ? "" : response.substr(body + 4)};
}

// A WebSocket to the gateway on localhost, its upgrade sent with the gateway's own Host and
// `headers`; status() is the answer's status line, body() a refusal's text.
class RawWebSocket {
 public:
  RawWebSocket(int port, const std::string& target, const std::string& headers) : fd_(connect_local(port)) {
    if (fd_ < 0) return;
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
                                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n" +
                                headers + "\r\n";
    (void)::write(fd_, request.data(), request.size());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (in_.find("\r\n\r\n") == std::string::npos && fill(deadline)) {
    }
    const auto end = in_.find("\r\n\r\n");
    status_ = in_.substr(0, in_.find("\r\n"));
    if (end == std::string::npos) return;
    if (status_.find(" 101 ") == std::string::npos) {
      while (fill(deadline)) {
      }
    }
    body_ = in_.substr(end + 4);
    in_.erase(0, end + 4);
  }
  ~RawWebSocket() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawWebSocket(const RawWebSocket&) = delete;
  RawWebSocket& operator=(const RawWebSocket&) = delete;
  [[nodiscard]] const std::string& status() const { return status_; }
  [[nodiscard]] const std::string& body() const { return body_; }

  // One masked text frame.
  void send_text(const std::string& text) {
    std::string frame{static_cast<char>(0x81)};
    if (text.size() < 126) {
      frame += static_cast<char>(0x80 | text.size());
    } else {
      frame += static_cast<char>(0x80 | 126);
      frame += static_cast<char>((text.size() >> 8) & 0xff);
      frame += static_cast<char>(text.size() & 0xff);
    }
    const char mask[4] = {0x11, 0x22, 0x33, 0x44};
    frame.append(mask, 4);
    for (std::size_t i = 0; i < text.size(); ++i) frame += static_cast<char>(text[i] ^ mask[i % 4]);
    (void)::write(fd_, frame.data(), frame.size());
  }

  // The next text message, or nullopt when the socket closes or `timeout` passes first.
  std::optional<std::string> next(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::string message;
    for (;;) {
      if (!have(2, deadline)) return std::nullopt;
      const int opcode = in_[0] & 0x0f;
      const bool fin = (in_[0] & 0x80) != 0;
      std::size_t length = static_cast<unsigned char>(in_[1]) & 0x7f;
      std::size_t head = 2;
      if (length >= 126) {
        const std::size_t bytes = length == 126 ? 2 : 8;
        if (!have(2 + bytes, deadline)) return std::nullopt;
        length = 0;
        for (std::size_t i = 0; i < bytes; ++i) length = (length << 8) | static_cast<unsigned char>(in_[2 + i]);
        head += bytes;
      }
      if (!have(head + length, deadline)) return std::nullopt;
      const std::string payload = in_.substr(head, length);
      in_.erase(0, head + length);
      if (opcode == 8) return std::nullopt;
      if (opcode != 0 && opcode != 1) continue;  // a ping or a pong
      message += payload;
      if (fin) return message;
    }
  }

 private:
  bool have(std::size_t n, std::chrono::steady_clock::time_point deadline) {
    while (in_.size() < n) {
      if (!fill(deadline)) return false;
    }
    return true;
  }
  bool fill(std::chrono::steady_clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd_, POLLIN, 0};
    if (fd_ < 0 || left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) return false;
    char buffer[65536];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) return false;
    in_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  int fd_ = -1;
  std::string in_, status_, body_;
};

}  // namespace ispars::test
