// isparsd's settings: the config file (keys, relative paths, named errors), the flags over it,
// and the one declaration list both walk (DaemonConfig::describe over daemon_settings.hpp's).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <type_traits>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_flags.hpp"
#include "ispars/server/daemon_settings.hpp"
#include "support/test_support.hpp"

namespace ispars::server {
namespace {

TEST(DaemonConfig, ReadsEveryKeyAndResolvesPathsAgainstTheFile) {
  test::TempDir dir;
  const auto path = dir.write("isparsd.yaml", R"(data_dir: data
scene_dir: /abs/scenes
domain: 42
workers: 3
build_threads: 2
profile_file: profiles.xml
profile_name: fleet
log_level: debug
server_id: east-1
max_samples: 1000
snapshot_compact_every: 7
preload: [a, b]
request_queue: 9
lease_s: 12
memory_budget_mb: 2048
log_file: logs/isparsd.log
log_file_mb: 8
metrics: 127.0.0.1:9464
ros2: true
ros2_frame: world
)");
  std::filesystem::create_directories(dir.path() / "logs");
  const DaemonConfig c = load_daemon_config(path);
  EXPECT_EQ(c.data_dir, dir.path() / "data");
  EXPECT_EQ(c.scene_dir, "/abs/scenes");
  EXPECT_EQ(c.participant.domain, 42);
  EXPECT_EQ(c.workers, 3u);
  EXPECT_EQ(c.build_threads, 2u);
  EXPECT_EQ(c.participant.profile_file, (dir.path() / "profiles.xml").string());
  EXPECT_EQ(c.participant.profile_name, "fleet");
  EXPECT_EQ(c.server_id, "east-1");
  EXPECT_EQ(c.max_samples, 1000u);
  EXPECT_EQ(c.snapshot_compact_every, 7u);
  EXPECT_EQ(c.preload, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(c.request_queue, 9u);
  EXPECT_EQ(c.participant.lease_seconds, 12u);
  EXPECT_EQ(c.memory_budget_mb, 2048u);
  EXPECT_EQ(c.log_file, dir.path() / "logs" / "isparsd.log");
  EXPECT_EQ(c.log_file_mb, 8u);
  EXPECT_EQ(c.metrics, (ListenAddress{"127.0.0.1", 9464}));
  EXPECT_TRUE(c.ros2);
  EXPECT_EQ(c.ros2_frame, "world");
  EXPECT_DOUBLE_EQ(memory_budget_bytes(c), 2048.0 * 1024 * 1024);
  EXPECT_GT(memory_budget_bytes(DaemonConfig{}), 0.0) << "the default is half of this machine's memory";
}

TEST(DaemonConfig, BadValuesAreNamed) {
  test::TempDir dir;
  const auto expect = [&](const std::string& text, const std::string& needle) {
    const auto path = dir.write("c.yaml", text);
    try {
      (void)load_daemon_config(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect("domain: 300\n", "domain: must be a whole number in [0, 232], got 300");
  expect("workers: 0\n", "workers: must be a whole number in [1, 64], got 0");
  expect("build_threads: 65\n", "build_threads: must be a whole number in [1, 64]");
  expect("build_threads: 0\n", "build_threads: must be a whole number in [1, 64]");
  expect("workers: many\n", "workers: expected a whole number, got 'many'");
  expect("workers: [1, 2]\n", "workers: has the wrong type");
  expect("colour: red\n", "colour: unknown key");
  expect("memory_budget_mb: 8\n", "memory_budget_mb: must be 0 (half of this machine's memory) or in 16..");
  expect("request_queue: 0\n", "request_queue: must be a whole number in [1, 100000], got 0");
  expect("request_queue: 100001\n", "request_queue: must be a whole number in [1, 100000]");
  expect("lease_s: 601\n", "lease_s: must be a whole number in [0, 600], got 601");
  expect("lease_s: -1\n", "lease_s: must be a whole number in [0, 600], got -1");
  expect("server_id: " + std::string(65, 'x') + "\n", "server_id: is longer than 64 characters");
  expect("log_level: chatty\n", "log_level: 'chatty' is not one of");
  expect("[1, 2]\n", "yaml: the config must be a mapping");
  expect("domain: [\n", "yaml");
  expect("log_file_mb: 0\n", "log_file_mb: must be a whole number in [1, 100000], got 0");
  expect("log_file_mb: 100001\n", "log_file_mb: must be a whole number in [1, 100000]");
  expect("log_file: nowhere/x.log\n",
         "log_file: its directory " + (dir.path() / "nowhere").string() + " does not exist");
  expect("metrics: localhost:9464\n", "metrics: 'localhost:9464' does not start with an IPv4 address");
  expect("metrics: 127.0.0.1\n", "metrics: '127.0.0.1' is not an address and a port");
  expect("metrics: 127.0.0.1:65536\n", "has no port in 0..65535");
  expect("metrics: '127.0.0.1:'\n", "has no port in 0..65535");
  expect("metrics: 127.0.0.1:+80\n", "has no port in 0..65535");
  expect("metrics: " + std::string(70, '1') + ":80\n", "is not an address and a port");
  expect("ros2: maybe\n", "ros2: expected true or false, got 'maybe'");
  expect("ros2_frame: ''\n", "ros2_frame: must not be empty");
  expect("ros2_frame: 'map frame'\n", "ros2_frame: 'map frame' has a character other than A-Z a-z 0-9 _ / . - at 3");
  EXPECT_THROW((void)load_daemon_config(dir.path() / "missing.yaml"), params::InputError);
}

TEST(DaemonConfig, Ros2AndSecurityAreRefusedTogether) {
  DaemonConfig config;
  config.ros2 = true;
  EXPECT_NO_THROW(check_together(config));
  config.participant.security = "/etc/ispars/identity";
  try {
    check_together(config);
    ADD_FAILURE() << "ros2 with security accepted";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ros2: cannot be on with security"), std::string::npos) << e.what();
  }
  config.ros2 = false;
  EXPECT_NO_THROW(check_together(config));
}

TEST(DaemonConfig, AListenAddressIsAnIpv4AddressAndAPort) {
  const ListenAddress any = parse_listen_address("0.0.0.0:0", "isparsd", "metrics");
  EXPECT_EQ(any.host, "0.0.0.0");
  EXPECT_EQ(any.port, 0);
  const ListenAddress local = parse_listen_address("127.0.0.1:65535", "isparsd", "metrics");
  EXPECT_EQ(local.host, "127.0.0.1");
  EXPECT_EQ(local.port, 65535);
  EXPECT_THROW((void)parse_listen_address("127.0.0.256:80", "isparsd", "metrics"), params::InputError);
  EXPECT_THROW((void)parse_listen_address("[::1]:80", "isparsd", "metrics"), params::InputError);
  EXPECT_THROW((void)parse_listen_address(":80", "isparsd", "metrics"), params::InputError);
}

// Parses `args` as isparsd's flags and applies them over `config`.
DaemonConfig with_flags(std::vector<std::string> args, DaemonConfig config = {}) {
  CLI::App app;
  const DaemonFlags flags(app);
  args.insert(args.begin(), "isparsd");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  app.parse(static_cast<int>(argv.size()), argv.data());
  flags.apply(config);
  return config;
}

TEST(DaemonFlags, EachSettingHasAFlagOverTheFile) {
  DaemonConfig file;
  file.preload = {"from-file"};
  file.workers = 5;
  const DaemonConfig c = with_flags({"--workers",
                                     "3",
                                     "--compact-every",
                                     "5",
                                     "--load",
                                     "a",
                                     "--preload",
                                     "b",
                                     "--metrics",
                                     "127.0.0.1:9",
                                     "--data-dir",
                                     "rel/data",
                                     "--log-level",
                                     "warn",
                                     "--discovery-wait-ms",
                                     "100",
                                     "--max-samples",
                                     "7",
                                     "--ros2",
                                     "--ros2-frame",
                                     "odom"},
                                    file);
  EXPECT_EQ(c.workers, 3u);
  EXPECT_EQ(c.snapshot_compact_every, 5u);
  EXPECT_EQ(c.preload, (std::vector<std::string>{"from-file", "a", "b"}));
  EXPECT_EQ(c.metrics, (ListenAddress{"127.0.0.1", 9}));
  EXPECT_EQ(c.data_dir, "rel/data") << "a flag's path is the caller's, as given";
  EXPECT_EQ(c.log_level, "warn");
  EXPECT_EQ(c.discovery_wait_ms, 100u);
  EXPECT_EQ(c.max_samples, 7u);
  EXPECT_TRUE(c.ros2) << "--ros2 is a switch: no value follows it";
  EXPECT_EQ(c.ros2_frame, "odom");
  EXPECT_EQ(with_flags({}, file).workers, 5u) << "no flag: the file's value stays";
  EXPECT_FALSE(with_flags({}, file).ros2) << "off by default";
}

TEST(DaemonFlags, BadValuesAreNamedByTheirFlag) {
  const auto expect = [](const std::vector<std::string>& args, const std::string& needle) {
    try {
      (void)with_flags(args);
      ADD_FAILURE() << "accepted: " << args[0] << " " << args[1];
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect({"--workers", "0"}, "command line: --workers: must be a whole number in [1, 64], got 0");
  expect({"--domain", "-1"}, "--domain: must be a whole number in [0, 232], got -1");
  expect({"--compact-every", "0"}, "--snapshot-compact-every: must be a whole number in [1, ");
  expect({"--memory-budget-mb", "8"}, "--memory-budget-mb: must be 0 (half of this machine's memory)");
  expect({"--log-level", "chatty"}, "--log-level: 'chatty' is not one of");
  expect({"--server-id", std::string(65, 'x')}, "--server-id: is longer than 64 characters");
  expect({"--log-file", "/nowhere/at/all/x.log"}, "--log-file: its directory /nowhere/at/all does not exist");
  expect({"--metrics", "localhost:1"}, "--metrics: 'localhost:1' does not start with an IPv4 address");
  expect({"--workers", "many"}, "--workers: expected a whole number, got 'many'");
  expect({"--workers", "1.5"}, "--workers: must be a whole number in [1, 64], got 1.5");
  expect({"--domain", "99999999999999999999"},
         "--domain: must be a whole number in [0, 232], got 99999999999999999999");
  expect({"--request-queue", "12x"}, "--request-queue: expected a whole number, got '12x'");
}

TEST(DaemonFlags, TheHelpGivesEachIntegerItsBoundsAndDefault) {
  CLI::App app;
  const DaemonFlags flags(app);
  const std::string help = app.help();
  EXPECT_NE(help.find("--request-queue"), std::string::npos) << help;
  EXPECT_NE(help.find("a whole number in [1, 100000] (default 256)"), std::string::npos) << help;
  EXPECT_NE(help.find("--snapshot-compact-every"), std::string::npos) << help;
  EXPECT_NE(help.find("--compact-every"), std::string::npos) << help;
}

// --print-config's output read back gives the same config, for the defaults and for a config
// with every setting changed (relative paths come out absolute, so they read back the same).
TEST(DaemonSettings, APrintedConfigReadsBackTheSame) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "logs");
  DaemonConfig changed = with_flags({"--data-dir",         "rel/data",
                                     "--domain",           "7",
                                     "--workers",          "3",
                                     "--preload",          "a",
                                     "--preload",          "b",
                                     "--metrics",          "127.0.0.1:9464",
                                     "--log-file",         (dir.path() / "logs" / "d.log").string(),
                                     "--server-id",        "east 1: \"quoted\"",
                                     "--memory-budget-mb", "64",
                                     "--compact-every",    "9"});
  for (const DaemonConfig& config : {DaemonConfig{}, changed}) {
    const std::string printed = to_yaml(config);
    const auto path = dir.write("printed.yaml", printed);
    EXPECT_EQ(to_yaml(load_daemon_config(path)), printed) << printed;
  }
  const std::string printed = to_yaml(changed);
  EXPECT_NE(printed.find("metrics: 127.0.0.1:9464"), std::string::npos) << printed;
  EXPECT_NE(printed.find((std::filesystem::current_path() / "rel" / "data").string()), std::string::npos) << printed;
  EXPECT_EQ(to_yaml(DaemonConfig{}).find("metrics"), std::string::npos) << "no address: the key is left out";
}

// Every declared default keeps its own bounds and rule (a default is never checked at run time).
TEST(DaemonSettings, EveryDefaultIsWithinItsBounds) {
  const DaemonConfig defaults;
  std::size_t settings = 0;
  params::visit(defaults, [&](const auto& s, const auto& value) {
    ++settings;
    using S = std::decay_t<decltype(s)>;
    if constexpr (requires { s.min; }) {
      EXPECT_EQ(params::problem(s, value), "") << s.name;
      EXPECT_LT(s.min, s.max) << s.name;
    } else if constexpr (std::is_same_v<S, params::TextSpec>) {
      EXPECT_EQ(params::problem(s, std::filesystem::path(value).string()), "") << s.name;
    } else if constexpr (std::is_same_v<S, params::ListSpec>) {
      EXPECT_EQ(params::problem(s, value), "") << s.name;
    }
  });
  EXPECT_EQ(settings, 22u);
}

// RocksDB's options_settable_test idea: a member added to the config or to the participant's
// options without its declaration fails here (the participant's name is the program's to set).
TEST(DaemonSettings, EveryMemberIsDeclared) {
  EXPECT_EQ(params::aggregate_size<wire::ParticipantOptions>(), params::field_count<wire::ParticipantOptions>() + 1);
  const std::size_t participant = params::field_count<wire::ParticipantOptions>();
  EXPECT_EQ(params::aggregate_size<DaemonConfig>(), params::field_count<DaemonConfig>() - participant + 1);
  // And the daemon declares each participant setting with the participant's own declaration.
  DaemonConfig config;
  wire::ParticipantOptions options;
  EXPECT_EQ(params::for_matching(options, config, [](const auto&, const auto&, const auto&) {}), participant);
}

// Each setting changed alone, through the same declaration list: `change` changes member `k`.
template <class F>
void change_one(DaemonConfig& config, std::size_t k, F&& change) {
  std::size_t i = 0;
  params::visit(config, [&](const auto& s, auto& member) {
    if (i++ == k) change(s, member);
  });
}

// A SIGHUP names each setting it cannot apply: every one declared needs_restart, changed alone,
// is named, and only it; a log setting changed is applied, so not named.
TEST(DaemonSettings, EverySettingChangedButNotAppliedOnSighupIsNamed) {
  const DaemonConfig running;
  std::size_t named = 0;
  for (std::size_t k = 0; k < params::field_count<DaemonConfig>(); ++k) {
    DaemonConfig fresh = running;
    change_one(fresh, k, [&](const auto& s, auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (std::is_arithmetic_v<T>) {
        value = static_cast<T>(value + 1);
      } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
        value.push_back("extra");
      } else if constexpr (std::is_same_v<T, std::optional<ListenAddress>>) {
        value = ListenAddress{"127.0.0.1", 9464};
      } else {
        value = T(std::string("changed"));
      }
      const std::vector<std::string> later = changed_needing_restart(running, fresh);
      if (!s.needs_restart) {
        EXPECT_TRUE(later.empty()) << s.name << " is applied on SIGHUP";
      } else {
        EXPECT_EQ(later, std::vector<std::string>{std::string(s.name)});
        ++named;
      }
    });
  }
  EXPECT_EQ(named, 19u) << "all but log_level, log_file and log_file_mb";
  DaemonConfig with_id = running;
  with_id.server_id = "d1";
  EXPECT_TRUE(changed_needing_restart(with_id, running).empty()) << "no server_id: the default the daemon holds";
}

// deploy/isparsd.yaml, the shipped config, names every setting (set or commented out) and no
// other key: a setting added to the declaration without it fails here.
TEST(DaemonSettings, TheShippedConfigNamesEverySetting) {
  std::set<std::string> declared;
  const DaemonConfig defaults;
  params::visit(defaults, [&](const auto& s, const auto&) { declared.insert(std::string(s.name)); });
  std::set<std::string> shipped;
  std::ifstream in(std::string(ISPARS_SCENES_DIR) + "/../isparsd.yaml");
  ASSERT_TRUE(in) << "deploy/isparsd.yaml";
  for (std::string line; std::getline(in, line);) {
    std::size_t at = line.find_first_not_of("# ");
    if (at == std::string::npos) continue;
    const std::size_t colon = line.find(':', at);
    const std::string key = colon == std::string::npos ? std::string() : line.substr(at, colon - at);
    if (!key.empty() && key.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos) {
      shipped.insert(key);
    }
  }
  EXPECT_EQ(shipped, declared);
}

}  // namespace
}  // namespace ispars::server
