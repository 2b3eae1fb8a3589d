#pragma once
// Shared helpers for the tests: where the shipped scenes are, and random queries biased toward
// the surface, where the decisions are close and bugs show.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ispars/planning/builders/sample_batch.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::test {

/// Whether `text` contains `part` (an error message names what it should).
inline bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A valid sample at `q` that sees no POI, to step a builder by hand.
inline planning::PreparedSample valid_at(const Vec3& q) { return planning::PreparedSample{q, true, {}}; }

/// deploy/scenes in the source tree.
std::filesystem::path scenes_dir();
/// The five shared real-mesh scenes, by file stem.
const std::vector<std::string>& shared_scene_names();
/// Loads deploy/scenes/NAME.yaml once per process and keeps it.
const planning::Scene& shared_scene(const std::string& name);

/// A scene of free space around the origin (bounds +-50, robot radius 0.1, sensor range 1, t
/// 1.05, root at the origin, 3 POIs) with the given delta and Delta. Its obstacles are a far
/// tile at (40, 40, 40) and, with `wall`, a square at x = 2.5 (|y|, |z| <= 1) that blocks the
/// segment from the origin to (5, 0, 0).
planning::Scene open_scene(double delta, double big_delta, bool wall = false);

/// A fresh temporary directory, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  /// Writes `text` to path()/name and returns the full path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

/// `n` scaled by the environment variable ISPARS_TEST_QUERY_SCALE (default 1), at least
/// min(n, 20). The sanitizer pass of deploy/test.sh sets a small scale: the brute-force
/// references run 10x slower there, and the full-volume agreement runs in the Release pass.
std::size_t scaled(std::size_t n);

/// The whole content of file `path` (bytes as they are); empty when it cannot be read.
std::string read_text(const std::filesystem::path& path);

/// Prints the last `lines` lines of every *.log file directly in `dir` (the logs LocalDaemon
/// writes beside the data directories) to standard error, each under its file name.
void print_daemon_log_tails(const std::filesystem::path& dir, std::size_t lines);

/// Every thread's stack of running process `pid` (gdb, attached for a moment), for a test that
/// finds a daemon alive but deaf; a line saying why when gdb is missing or cannot attach.
std::string thread_stacks(int pid);

/// Runs `command` with /bin/sh; its exit status (-1 when it did not exit) and its standard output.
std::pair<int, std::string> run_command(const std::string& command);

/// Peak resident memory (VmHWM) of process `pid` (0: this process), in MiB; 0 when unreadable.
double peak_rss_mib(int pid = 0);

/// Half uniform in the bounds, half within about two robot radii of a random triangle (chosen
/// by index, so small triangles get their share), clamped into the bounds.
std::vector<Vec3> mixed_query_points(const planning::Scene& scene, scene_files::Rng& rng, std::size_t count);

/// Every byte of a roadmap that a build must reproduce: positions as hex floats, chi, edges
/// with costs, in id order. Two builds are identical exactly when their fingerprints are.
std::string fingerprint(const Roadmap& roadmap);

struct TestSegment {
  Vec3 a, b;
};
/// Segments from mixed points, random direction, length uniform in (0, dense_delta], inside
/// the bounds.
std::vector<TestSegment> mixed_query_segments(const planning::Scene& scene, scene_files::Rng& rng, std::size_t count);

}  // namespace ispars::test
