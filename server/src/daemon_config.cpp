#include "daemon_config.hpp"

#include <fmt/format.h>
#include <spdlog/common.h>
#include <yaml-cpp/yaml.h>

#include <arpa/inet.h>
#include <unistd.h>

#include <set>

#include "ispars/input_error.hpp"

namespace ispars::server {

DaemonConfig load_daemon_config(const std::filesystem::path& path) {
  const std::string source = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(source);
  } catch (const YAML::BadFile&) {
    throw InputError(source, "file", "cannot be read");
  } catch (const YAML::Exception& e) {
    throw InputError(source, "yaml", e.what());
  }
  DaemonConfig config;
  if (!root || root.IsNull()) return config;
  if (!root.IsMap()) throw InputError(source, "yaml", "the config must be a mapping of keys to values");
  const std::set<std::string> known{"data_dir", "scene_dir", "domain", "workers", "build_threads", "profile_file", "profile_name",
                                    "log_level", "server_id", "max_samples", "snapshot_compact_every", "preload",
                                    "request_queue", "memory_budget_mb", "security", "discovery_wait_ms",
                                    "log_file", "log_file_mb", "metrics"};
  const std::filesystem::path base = path.parent_path();
  const auto resolve = [&](const std::string& p) {
    const std::filesystem::path fp(p);
    return fp.is_absolute() ? fp : base / fp;
  };
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    if (!known.count(key)) throw InputError(source, key, "unknown key");
    const YAML::Node& value = item.second;
    try {
      if (key == "data_dir") config.data_dir = resolve(value.as<std::string>());
      if (key == "scene_dir") config.scene_dir = resolve(value.as<std::string>());
      if (key == "domain") config.domain = value.as<int>();
      if (key == "workers") config.workers = value.as<unsigned>();
      if (key == "build_threads") config.build_threads = value.as<unsigned>();
      if (key == "profile_file") config.profile_file = resolve(value.as<std::string>()).string();
      if (key == "profile_name") config.profile_name = value.as<std::string>();
      if (key == "security") config.security = resolve(value.as<std::string>()).string();
      if (key == "log_level") config.log_level = value.as<std::string>();
      if (key == "server_id") config.server_id = value.as<std::string>();
      if (key == "max_samples") config.max_samples = value.as<std::uint64_t>();
      if (key == "snapshot_compact_every") config.snapshot_compact_every = value.as<std::size_t>();
      if (key == "preload") config.preload = value.as<std::vector<std::string>>();
      if (key == "request_queue") config.request_queue = value.as<std::size_t>();
      if (key == "memory_budget_mb") config.memory_budget_mb = value.as<std::uint64_t>();
      if (key == "discovery_wait_ms") config.discovery_wait_ms = value.as<std::uint32_t>();
      if (key == "log_file") config.log_file = resolve(value.as<std::string>());
      if (key == "log_file_mb") config.log_file_mb = value.as<std::uint64_t>();
      if (key == "metrics") config.metrics = parse_listen_address(value.as<std::string>(), source, "metrics");
    } catch (const YAML::Exception&) {
      throw InputError(source, key, fmt::format("has the wrong type (line {})", value.Mark().line + 1));
    }
  }
  check_daemon_config(config, source);
  return config;
}

double memory_budget_bytes(const DaemonConfig& config) {
  if (config.memory_budget_mb != 0) return static_cast<double>(config.memory_budget_mb) * 1024.0 * 1024.0;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4.0 * 1024.0 * 1024.0 * 1024.0;  // unknown: 4 GiB
  return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

void check_daemon_config(const DaemonConfig& c, const std::string& source) {
  if (c.domain < 0 || c.domain > 232) throw InputError(source, "domain", fmt::format("must be in 0..232, got {}", c.domain));
  if (c.workers < 1 || c.workers > 64) throw InputError(source, "workers", fmt::format("must be in 1..64, got {}", c.workers));
  if (c.build_threads < 1 || c.build_threads > 64) {
    throw InputError(source, "build_threads", fmt::format("must be in 1..64, got {}", c.build_threads));
  }
  if (c.max_samples < 1) throw InputError(source, "max_samples", "must be at least 1");
  if (c.snapshot_compact_every < 1) throw InputError(source, "snapshot_compact_every", "must be at least 1");
  if (spdlog::level::from_str(c.log_level) == spdlog::level::off && c.log_level != "off") {
    throw InputError(source, "log_level", fmt::format("'{}' is not one of trace, debug, info, warn, error, critical, off",
                                                      c.log_level));
  }
  if (c.server_id.size() > 64) throw InputError(source, "server_id", "is longer than 64 characters");
  if (c.memory_budget_mb != 0 && (c.memory_budget_mb < 16 || c.memory_budget_mb > (1ull << 30))) {
    throw InputError(source, "memory_budget_mb",
                     fmt::format("must be 0 (half of this machine's memory) or in 16..{}, got {}", 1ull << 30,
                                 c.memory_budget_mb));
  }
  if (c.request_queue < 1 || c.request_queue > 100'000) {
    throw InputError(source, "request_queue", fmt::format("must be in 1..100000, got {}", c.request_queue));
  }
  if (c.discovery_wait_ms < 100 || c.discovery_wait_ms > 60'000) {
    throw InputError(source, "discovery_wait_ms", fmt::format("must be in 100..60000, got {}", c.discovery_wait_ms));
  }
  if (c.log_file_mb < 1 || c.log_file_mb > 100'000) {
    throw InputError(source, "log_file_mb", fmt::format("must be in 1..100000, got {}", c.log_file_mb));
  }
  if (!c.log_file.empty()) {
    if (c.log_file.string().size() > 4096) throw InputError(source, "log_file", "is longer than 4096 characters");
    const std::filesystem::path dir = c.log_file.parent_path().empty() ? "." : c.log_file.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
      throw InputError(source, "log_file", fmt::format("its directory {} does not exist", dir.string()));
    }
  }
}

ListenAddress parse_listen_address(const std::string& text, const std::string& source, const std::string& field) {
  const auto colon = text.rfind(':');
  const auto bad = [&](const std::string& why) {
    return InputError(source, field, fmt::format("'{}' {}; write ADDRESS:PORT, e.g. 127.0.0.1:9464",
                                                 text.substr(0, 64), why));
  };
  if (text.size() > 64 || colon == std::string::npos) throw bad("is not an address and a port");
  ListenAddress out;
  out.host = text.substr(0, colon);
  in_addr parsed{};
  if (::inet_pton(AF_INET, out.host.c_str(), &parsed) != 1) throw bad("does not start with an IPv4 address");
  const std::string port = text.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stoul(port) > 65535) {
    throw bad("has no port in 0..65535");
  }
  out.port = static_cast<int>(std::stoul(port));
  return out;
}

}  // namespace ispars::server
