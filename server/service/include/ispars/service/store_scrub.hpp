#pragma once
// The background check of stored copies: every store in the data directory that no session
// holds is read whole (store_scrub_problem) once per version of its files, on a thread of its
// own, so that damage in a copy that only sits on disk (a standby, or one handed over) is found
// and named before a takeover needs it, not only when it is opened. Reads only: a damaged store
// is left as it is. Each read holds the file in memory; it is made only while the service's
// memory budget has room for it, and takes no lease (so it never makes a build or a tour busy);
// one that does not fit waits for a later pass.

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ispars/roadmap/file_system.hpp"
#include "ispars/service/memory_budget.hpp"

namespace ispars::service {

class StoreScrub {
 public:
  /// Scenes held by a session now (their stores are being written: never read here).
  using Held = std::function<std::vector<std::string>()>;

  /// Starts the thread: a pass over `data_dir` at once, then every `period`.
  StoreScrub(std::filesystem::path data_dir, Held held, std::shared_ptr<MemoryBudget> budget,
             std::chrono::milliseconds period, const FileSystem& fs = disk());
  ~StoreScrub();
  StoreScrub(const StoreScrub&) = delete;
  StoreScrub& operator=(const StoreScrub&) = delete;

  /// Ends the pass (after the file being read) and joins the thread. Idempotent.
  void stop();
  /// The damage found in `scene`'s store as its files are now; empty when none was found, or its
  /// files changed since it was read (a session holds it again, or it was rebuilt).
  [[nodiscard]] std::string problem(const std::string& scene) const;
  /// Passes completed (for tests: a pass after a change has looked at it).
  [[nodiscard]] std::uint64_t passes() const;

 private:
  /// The sizes and modification times of a store's files: a new version of them is read again.
  using FilesKey = std::vector<std::int64_t>;
  struct Verdict {
    FilesKey key;
    std::string problem;
  };
  [[nodiscard]] FilesKey key_of(const std::filesystem::path& dir) const;
  void run();
  void pass();
  void check(const std::string& scene);

  const std::filesystem::path data_dir_;
  const Held held_;
  const std::shared_ptr<MemoryBudget> budget_;
  const std::chrono::milliseconds period_;
  const FileSystem& fs_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::uint64_t passes_ = 0;
  std::map<std::string, Verdict> verdicts_;  // scene -> the last read (bounded by the scenes on disk)
  std::thread thread_;                       // last: started once the rest is made
};

}  // namespace ispars::service
