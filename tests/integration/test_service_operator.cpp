// What an operator does to a running daemon: signals, restarts after unloading.

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

TEST_F(ServiceTest, SighupNeitherStopsTheDaemonNorDisturbsItsRequests) {
  auto daemon = start("d");
  Client c(client_options(domain_));
  c.load("s0");
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(::kill(daemon->pid(), SIGHUP), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // SIGHUPs 0.1 s apart
    EXPECT_TRUE(daemon->alive());
    EXPECT_EQ(c.stats("s0").scene, "s0");
  }
  EXPECT_NE(daemon->log().find("SIGHUP: log reopened (level debug)"), std::string::npos) << daemon->log();
  EXPECT_EQ(daemon->terminate(), 0) << "SIGTERM still stops it cleanly";
}

// An unloaded scene stays unloaded after a restart (its stored roadmap kept), and a load brings
// the roadmap back; a scene never unloaded is reloaded at start as before.
TEST_F(ServiceTest, AnUnloadSurvivesARestartAndALoadBringsTheRoadmapBack) {
  std::uint64_t vertices = 0;
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    for (const char* s : {"s0", "s1"}) {
      c.load(s);
      c.build(s, ispars_build(1200));
      c.wait_idle(s, {}, kLong);
    }
    vertices = c.stats("s0").vertices;
    c.unload("s0");
    ASSERT_EQ(daemon->terminate(), 0);
  }
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    const auto list = c.list_scenes();
    for (const auto& e : list) {
      if (e.scene == "s0") {
        EXPECT_FALSE(e.loaded) << "an unloaded scene was reloaded at start";
      }
      if (e.scene == "s1") {
        EXPECT_TRUE(e.loaded) << "a loaded scene was not reloaded at start";
      }
    }
    c.load("s0");
    EXPECT_EQ(c.stats("s0").vertices, vertices);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  auto daemon = start("d");
  Client c(client_options(domain_));
  EXPECT_EQ(c.stats("s0").vertices, vertices) << "loaded again, it is reloaded at start again";
}

// SIGHUP after an outside rotation (logrotate renames the file): the daemon writes a new file at
// the configured path, applies a new log level from the edited config, names the changed keys it
// applies only at a restart, and keeps serving; a broken config changes nothing.
TEST_F(ServiceTest, SighupReopensTheLogFileAndAppliesTheConfigsLogLevel) {
  const auto log_file = dir_.path() / "logs" / "isparsd.log";
  std::filesystem::create_directories(log_file.parent_path());
  const auto config = dir_.path() / "isparsd.yaml";
  const auto write_config = [&](const std::string& level, int workers) {
    std::ofstream(config) << "log_file: " << log_file.string() << "\nlog_level: " << level << "\nworkers: " << workers
                          << "\n";
  };
  write_config("info", 2);
  // --log-level is not given here: the config's level is the one SIGHUP re-reads.
  DaemonProcess daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", scene_dir_, "d",
                       {"--config", config.string(), "--log-file", log_file.string()});
  Client c(client_options(domain_));
  c.load("s0");
  c.load("s1");
  c.unload("s1");  // logs what it does with the updates of s1 at debug level
  const std::string before = read_text(log_file);
  EXPECT_NE(before.find("isparsd d serving on DDS domain"), std::string::npos) << before;
  EXPECT_EQ(before.find(" debug "), std::string::npos) << "level info logged debug lines";

  std::filesystem::rename(log_file, log_file.string() + ".1");
  write_config("debug", 3);
  ASSERT_EQ(::kill(daemon.pid(), SIGHUP), 0);
  (void)eventually([&] { return read_text(log_file).find("SIGHUP") != std::string::npos; }, std::chrono::seconds(10),
                   "the reopened log names the SIGHUP");  // checked below
  EXPECT_NE(read_text(log_file).find("SIGHUP: log reopened (level debug); changed but applied only at a restart: "
                                     "workers"),
            std::string::npos)
      << read_text(log_file);
  EXPECT_EQ(c.stats("s0").scene, "s0");
  c.load("s1");
  c.unload("s1");
  EXPECT_NE(read_text(log_file).find(" debug "), std::string::npos) << "the new level was not applied:\n"
                                                                    << read_text(log_file);
  // The renamed file holds what was logged before, and nothing of the reload.
  const std::string rotated = read_text(log_file.string() + ".1");
  EXPECT_EQ(rotated.rfind(before, 0), 0u);
  EXPECT_EQ(rotated.find("SIGHUP"), std::string::npos) << "the renamed file was written after the reopen";

  std::ofstream(config) << "log_level: [not, a, level]\n";
  ASSERT_EQ(::kill(daemon.pid(), SIGHUP), 0);
  const std::string refused = "SIGHUP: the config was not reloaded: " + config.string() + ": log_level";
  (void)eventually([&] { return read_text(log_file).find(refused) != std::string::npos; }, std::chrono::seconds(10),
                   "the log names the refused reload");  // checked below
  EXPECT_NE(read_text(log_file).find(refused), std::string::npos) << read_text(log_file);
  EXPECT_TRUE(daemon.alive());
  EXPECT_EQ(c.stats("s0").scene, "s0");
  EXPECT_EQ(daemon.terminate(), 0);
}

// A build interrupted by SIGTERM and one still queued behind it (one build worker) both finish
// after a restart, each byte for byte the roadmap an uninterrupted build gives; once done, a
// further restart resumes nothing.
TEST_F(ServiceTest, AnInterruptedBuildAndAQueuedOneResumeAfterARestart) {
  const std::vector<std::string> one_worker = {"--workers", "1"};
  {
    auto daemon = start("d", one_worker);
    Client c(client_options(domain_));
    c.load("s0");
    c.load("s1");
    c.load("s2");
    c.build("s0", ispars_build(30'000));
    c.build("s1", ispars_build(2000, 2));
    c.build("s2", ispars_build(1000, 3));
    c.cancel("s2");  // queued and cancelled: never resumed
    ASSERT_TRUE(
        eventually([&] { return c.stats("s0").samples_done > 0; }, std::chrono::seconds(30), "s0's build commits"));
    ASSERT_LT(c.stats("s0").samples_done, 30'000u) << "the build ended before SIGTERM: make it longer";
    EXPECT_EQ(c.stats("s1").state, SceneState::queued);
    EXPECT_EQ(daemon->terminate(), 0);
  }
  {
    auto daemon = start("d", one_worker);
    Client c(client_options(domain_));
    const SceneStatus s0 = c.wait_idle("s0", {}, kLong);
    const SceneStatus s1 = c.wait_idle("s1", {}, kLong);
    EXPECT_EQ(s0.samples_done, 30'000u) << s0.last_error;
    EXPECT_EQ(s1.samples_done, 2000u) << s1.last_error;
    EXPECT_EQ(s1.seed, 2u);
    EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 30'000, 1));
    EXPECT_EQ(roadmap_digest(c.snapshot("s1").roadmap), reference_digest(scene_dir_ / "s1.yaml", 2000, 2));
    EXPECT_EQ(c.load("s2").status.method, "") << "a cancelled build was resumed";
    const std::string log = daemon->log();
    EXPECT_NE(log.find("scene 's0': resuming an interrupted job at "), std::string::npos) << log;
    EXPECT_NE(log.find("scene 's1': resuming a build that had not committed: 2000 samples, seed 2"), std::string::npos)
        << log;
    EXPECT_EQ(daemon->terminate(), 0);
  }
  auto daemon = start("d", one_worker);
  Client c(client_options(domain_));
  EXPECT_EQ(c.stats("s0").state, SceneState::idle);
  // The log holds all three runs: the two resumptions of the second, none of the third.
  const std::string log = daemon->log();
  std::size_t resumed = 0;
  for (auto at = log.find("resuming"); at != std::string::npos; at = log.find("resuming", at + 1)) ++resumed;
  EXPECT_EQ(resumed, 2u) << "a finished job was resumed again:\n" << log;
}

// A rolling upgrade restarts the daemon cleanly again and again: the build is resumed every time
// (clean stops do not count against the cap of three resumes after deaths) and ends byte for byte
// the roadmap an uninterrupted build gives.
TEST_F(ServiceTest, ABuildSurvivesFiveCleanRestarts) {
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(30'000));
    EXPECT_EQ(daemon->terminate(), 0);
  }
  for (int restart = 1; restart <= 4; ++restart) {
    auto daemon = start("d");
    (void)eventually([&] { return daemon->log().find("scene 's0': resuming") != std::string::npos; },
                     std::chrono::seconds(30), "the daemon resumes s0");  // checked below
    ASSERT_NE(daemon->log().find("scene 's0': resuming"), std::string::npos)
        << "restart " << restart << ": the build was not resumed:\n"
        << daemon->log();
    EXPECT_EQ(daemon->terminate(), 0);
  }
  auto daemon = start("d");
  Client c(client_options(domain_));
  const SceneStatus s0 = c.wait_idle("s0", {}, kLong);
  EXPECT_EQ(s0.samples_done, 30'000u) << s0.last_error << "\n" << daemon->log();
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 30'000, 1));
  EXPECT_EQ(daemon->terminate(), 0);
}

TEST_F(ServiceTest, ALogFileOrMetricsAddressThatCannotBeUsedStopsTheStartWithItsName) {
  const auto run = [&](const std::vector<std::string>& extra) {
    std::string cmd = std::string(ISPARS_DAEMON) + " --domain " + std::to_string(domain_) + " --data-dir " +
                      (dir_.path() / "data").string() + " --scene-dir " + scene_dir_.string();
    for (const auto& a : extra) cmd += " '" + a + "'";
    return run_command(cmd + " 2>&1");
  };
  const auto [missing_status, missing] = run({"--log-file", (dir_.path() / "no" / "such" / "x.log").string()});
  EXPECT_EQ(missing_status, 2);
  // A bad flag is named by the flag (a bad key of the config file by the key: DaemonConfig tests).
  EXPECT_NE(missing.find("isparsd: command line: --log-file: its directory " + (dir_.path() / "no" / "such").string() +
                         " does not exist"),
            std::string::npos)
      << missing;
  for (const std::string bad : {"localhost:9464", "127.0.0.1", "127.0.0.1:70000", "127.0.0.1:-1", "::1:80"}) {
    const auto [status, out] = run({"--metrics", bad});
    EXPECT_EQ(status, 2) << bad;
    EXPECT_NE(out.find("isparsd: command line: --metrics: '" + bad + "'"), std::string::npos) << out;
  }
  const auto [size_status, size_out] = run({"--log-file-mb", "0"});
  EXPECT_EQ(size_status, 2);
  EXPECT_NE(size_out.find("isparsd: command line: --log-file-mb: must be a whole number in [1, 100000], got 0"),
            std::string::npos)
      << size_out;
}

}  // namespace
}  // namespace ispars::test
