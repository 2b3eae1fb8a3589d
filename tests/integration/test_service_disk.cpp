// The data directory on a filesystem that fills up or turns read-only (a tmpfs this test mounts:
// it needs root, as CI has; elsewhere it is skipped, saying so): each a clear error, no commit
// lost, nothing rewritten.

#include <gtest/gtest.h>
#include <sys/mount.h>

#include <cerrno>
#include <cstring>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

// A tmpfs of a given size mounted at a directory, unmounted when this goes.
class SmallFilesystem {
 public:
  SmallFilesystem(const std::filesystem::path& at, const std::string& size) : at_(at) {
    std::filesystem::create_directories(at);
    const std::string options = "size=" + size + ",mode=0755";
    if (::mount("tmpfs", at.c_str(), "tmpfs", 0, options.c_str()) != 0) error_ = std::strerror(errno);
  }
  ~SmallFilesystem() {
    if (error_.empty()) ::umount2(at_.c_str(), MNT_DETACH);
  }
  SmallFilesystem(const SmallFilesystem&) = delete;
  SmallFilesystem& operator=(const SmallFilesystem&) = delete;
  [[nodiscard]] const std::string& error() const { return error_; }
  // Remounts with `options` ("ro", "rw", "size=64m"); false on failure.
  bool remount(const std::string& options) {
    const unsigned long flags = MS_REMOUNT | (options == "ro" ? MS_RDONLY : 0);
    return ::mount("tmpfs", at_.c_str(), "tmpfs", flags,
                   options == "ro" || options == "rw" ? nullptr : options.c_str()) == 0;
  }

 private:
  std::filesystem::path at_;
  std::string error_;
};

TEST_F(ServiceTest, AFullDiskFailsTheBuildLoudlyAndLosesNoCommit) {
  SmallFilesystem disk(dir_.path() / "data-d", "384k");
  if (!disk.error().empty()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.error() << "); CI runs as root";
  std::uint64_t samples = 0, digest = 0;
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    c.load("s1");
    c.build("s0", ispars_build(40'000));
    const SceneStatus failed = c.wait_idle("s0", {}, kLong);
    ASSERT_EQ(failed.state, SceneState::failed) << "the build fitted in the small disk: " << failed.samples_done;
    EXPECT_NE(failed.last_error.find("No space left on device"), std::string::npos) << failed.last_error;
    EXPECT_NE(failed.last_error.find((dir_.path() / "data-d").string()), std::string::npos) << failed.last_error;
    samples = failed.samples_done;
    ASSERT_GT(samples, 0u);
    EXPECT_LT(samples, 40'000u);
    // What it serves is what it committed: valid, and the same after a restart.
    EXPECT_EQ(c.verify("s0").verify.violations, 0u);
    digest = roadmap_digest(c.snapshot("s0").roadmap);
    EXPECT_EQ(c.stats("s1").state, SceneState::empty) << "another scene is untouched";
    EXPECT_TRUE(daemon->alive());
    EXPECT_EQ(daemon->terminate(), 0);
  }
  ASSERT_TRUE(disk.remount("size=64m"));
  auto daemon = start("d");
  Client c(client_options(domain_));
  const SceneStatus back = c.stats("s0");
  EXPECT_NE(back.state, SceneState::failed) << back.last_error;
  EXPECT_EQ(back.samples_done, samples);
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), digest);
  // With room again, it extends from its last commit.
  c.extend("s0", 2000);
  const SceneStatus extended = c.wait_idle("s0", {}, kLong);
  EXPECT_EQ(extended.state, SceneState::idle) << extended.last_error;
  EXPECT_EQ(extended.samples_done, samples + 2000);
  EXPECT_EQ(c.verify("s0").verify.violations, 0u);
}

// (A filesystem with files open for writing cannot be remounted read-only, so a daemon meets a
// read-only data directory at start: it refuses, naming it, and the roadmap is as it was.)
TEST_F(ServiceTest, AReadOnlyDataDirStopsTheStartNamingItAndLeavesTheRoadmapAsItWas) {
  SmallFilesystem disk(dir_.path() / "data-d", "64m");
  if (!disk.error().empty()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.error() << "); CI runs as root";
  std::uint64_t digest = 0, samples = 0;
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(1500));
    samples = c.wait_idle("s0", {}, kLong).samples_done;
    digest = roadmap_digest(c.snapshot("s0").roadmap);
    EXPECT_EQ(daemon->terminate(), 0);
  }
  ASSERT_TRUE(disk.remount("ro")) << std::strerror(errno);
  try {
    DaemonProcess refused(ISPARS_DAEMON, domain_, dir_.path() / "data-d", scene_dir_, "d");
    ADD_FAILURE() << "a daemon started on a read-only data directory:\n" << refused.log();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("data directory " + (dir_.path() / "data-d").string() +
                                         " is not writable (.isparsd.lock: Read-only file system)"),
              std::string::npos)
        << e.what();
  }
  ASSERT_TRUE(disk.remount("rw")) << std::strerror(errno);
  auto daemon = start("d");
  Client c(client_options(domain_));
  const SceneStatus back = c.stats("s0");
  EXPECT_EQ(back.state, SceneState::idle) << back.last_error;
  EXPECT_EQ(back.samples_done, samples);
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), digest);
}

}  // namespace
}  // namespace ispars::test
