#include "ispars/server/daemon_config.hpp"

#include <fmt/format.h>
#include <spdlog/common.h>
#include <yaml-cpp/yaml.h>

#include <arpa/inet.h>
#include <unistd.h>

#include <set>
#include <type_traits>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/server/daemon_settings.hpp"

namespace ispars::server {

namespace {

// Reads each declared setting from a config file's mapping, checking it as it arrives.
struct YamlReader {
  const YAML::Node& root;
  const std::string& source;
  std::filesystem::path base;  // relative paths are resolved against the file's directory

  template <class T, class Member>
  void operator()(const params::Spec<T>& s, Member& member) const {
    if (const YAML::Node v = root[std::string(s.name)]) {
      member = checked_number(s, read<std::string>(v, s.name), source, std::string(s.name));
    }
  }
  template <class Member>  // std::string or std::filesystem::path
  void operator()(const params::TextSpec& s, Member& member) const {
    if (const YAML::Node v = root[std::string(s.name)]) {
      member = checked_text(s, read<std::string>(v, s.name), base, source, std::string(s.name));
    }
  }
  void operator()(const params::ListSpec& s, std::vector<std::string>& member) const {
    if (const YAML::Node v = root[std::string(s.name)]) {
      member = checked_list(s, read<std::vector<std::string>>(v, s.name), source, std::string(s.name));
    }
  }
  void operator()(const AddressSpec& s, std::optional<ListenAddress>& member) const {
    if (const YAML::Node v = root[std::string(s.name)]) {
      member = parse_listen_address(read<std::string>(v, s.name), source, std::string(s.name));
    }
  }

  template <class T>
  T read(const YAML::Node& value, std::string_view key) const {
    try {
      return value.as<T>();
    } catch (const YAML::Exception&) {
      throw params::InputError(source, std::string(key),
                               fmt::format("has the wrong type (line {})", value.Mark().line + 1));
    }
  }
};

// Writes each setting under its key.
struct YamlWriter {
  YAML::Emitter& out;

  template <class T, class Member>
  void operator()(const params::Spec<T>& s, const Member& member) const {
    out << YAML::Key << std::string(s.name) << YAML::Value << member;
  }
  template <class Member>
  void operator()(const params::TextSpec& s, const Member& member) const {
    std::string text = std::filesystem::path(member).string();
    if (s.path && !text.empty()) text = std::filesystem::absolute(text).lexically_normal().string();
    out << YAML::Key << std::string(s.name) << YAML::Value << YAML::DoubleQuoted << text;
  }
  void operator()(const params::ListSpec& s, const std::vector<std::string>& member) const {
    out << YAML::Key << std::string(s.name) << YAML::Value << YAML::Flow << member;
  }
  void operator()(const AddressSpec& s, const std::optional<ListenAddress>& member) const {
    if (member)
      out << YAML::Key << std::string(s.name) << YAML::Value << fmt::format("{}:{}", member->host, member->port);
  }
};

}  // namespace

DaemonConfig load_daemon_config(const std::filesystem::path& path) {
  const std::string source = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(source);
  } catch (const YAML::BadFile&) {
    throw params::InputError(source, "file", "cannot be read");
  } catch (const YAML::Exception& e) {
    throw params::InputError(source, "yaml", e.what());
  }
  DaemonConfig config;
  if (!root || root.IsNull()) return config;
  if (!root.IsMap()) throw params::InputError(source, "yaml", "the config must be a mapping of keys to values");
  std::set<std::string> known;
  params::visit(config, [&](const auto& spec, const auto&) { known.insert(std::string(spec.name)); });
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    if (!known.count(key)) throw params::InputError(source, key.substr(0, 64), "unknown key");
  }
  const YAML::Node& mapping = root;
  params::visit(config, YamlReader{mapping, source, path.parent_path()});
  return config;
}

std::string to_yaml(const DaemonConfig& config) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  params::visit(config, YamlWriter{out});
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::string checked_text(const params::TextSpec& spec, const std::string& text, const std::filesystem::path& base,
                         const std::string& source, const std::string& field) {
  if (text.size() > spec.max_length) {
    throw params::InputError(source, field, fmt::format("is longer than {} characters", spec.max_length));
  }
  std::string typed = text;
  if (spec.path && !text.empty()) {
    const std::filesystem::path given(text);
    typed = (given.is_absolute() ? given : base / given).string();
  }
  if (std::string why = params::problem(spec, typed); !why.empty())
    throw params::InputError(source, field, std::move(why));
  return typed;
}

std::vector<std::string> checked_list(const params::ListSpec& spec, std::vector<std::string> items,
                                      const std::string& source, const std::string& field) {
  if (std::string why = params::problem(spec, items); !why.empty())
    throw params::InputError(source, field, std::move(why));
  return items;
}

std::string log_level_rule(const std::string& level) {
  if (spdlog::level::from_str(level) != spdlog::level::off || level == "off") return {};
  return fmt::format("'{}' is not one of trace, debug, info, warn, error, critical, off", level);
}

std::string log_file_rule(const std::string& text) {
  const std::filesystem::path file(text);
  if (file.empty()) return {};
  const std::filesystem::path dir = file.parent_path().empty() ? "." : file.parent_path();
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return {};
  return fmt::format("its directory {} does not exist", dir.string());
}

std::string memory_budget_rule(std::uint64_t mib) {
  if (mib == 0 || mib >= 16) return {};
  return fmt::format("must be 0 (half of this machine's memory) or in 16..{}, got {}", 1ull << 30, mib);
}

void check_together(const DaemonConfig& config) {
  if (config.ros2 && !config.participant.security.empty()) {
    throw params::InputError("config", "ros2",
                             "cannot be on with security: the ROS 2 mirror's topics (rt/ispars/...) are in no "
                             "daemon's DDS Security permissions");
  }
}

std::string ros2_frame_rule(const std::string& frame) {
  if (frame.empty()) return "must not be empty";
  const auto bad = frame.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_/.-");
  if (bad == std::string::npos) return {};
  return fmt::format("'{}' has a character other than A-Z a-z 0-9 _ / . - at {}", frame.substr(0, 64), bad);
}

double memory_budget_bytes(const DaemonConfig& config) {
  if (config.memory_budget_mb != 0) return static_cast<double>(config.memory_budget_mb) * 1024.0 * 1024.0;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4.0 * 1024.0 * 1024.0 * 1024.0;  // unknown: 4 GiB
  return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

ListenAddress parse_listen_address(const std::string& text, const std::string& source, const std::string& field) {
  const auto colon = text.rfind(':');
  const auto bad = [&](const std::string& why) {
    return params::InputError(source, field,
                              fmt::format("'{}' {}; write ADDRESS:PORT, e.g. 127.0.0.1:9464", text.substr(0, 64), why));
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

std::vector<std::string> changed_needing_restart(const DaemonConfig& running, DaemonConfig fresh) {
  if (fresh.server_id.empty()) fresh.server_id = running.server_id;
  std::vector<std::string> out;
  (void)params::for_matching(running, fresh, [&](const auto& spec, const auto& was, const auto& now) {
    if (spec.needs_restart && !(was == now)) out.emplace_back(spec.name);
  });
  return out;
}

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  return buffer;
}

}  // namespace ispars::server
