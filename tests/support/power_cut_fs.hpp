#pragma once
// A file system in memory that can lose power, in the spirit of SQLite's crash-test VFS and
// RocksDB's FaultInjectionTestFS. It keeps, for every file, the bytes its last sync() made
// durable, and for every directory the entries (creations, renames, removals) its last
// sync_directory() made durable. At a chosen operation the power goes: that call and every later
// one throw PowerCut. power_on() then brings back exactly what was durable, as a machine that
// lost its page cache would find its disk: every unsynced write, truncation, creation, rename and
// removal is gone (optionally with a torn prefix of a file's unsynced appended bytes kept).

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>

#include "ispars/roadmap/file_system.hpp"

namespace ispars::test {

/// Thrown by every call of a PowerCutFileSystem once its power is cut.
struct PowerCut : std::runtime_error {
  PowerCut() : std::runtime_error("the power was cut") {}
};

/// See the file comment. Paths are absolute; "/" exists from the start. Safe from many threads.
class PowerCutFileSystem final : public FileSystem {
 public:
  PowerCutFileSystem();
  ~PowerCutFileSystem() override;

  /// The `n`-th mutating call from now (1: the next) and every call after it throw PowerCut.
  /// Mutating: a write, truncation, sync, directory sync, creation, rename or removal. 0 disarms.
  void cut_at(std::uint64_t n);
  /// The `n`-th mutating call from now (1: the next) fails as a disk error would: it changes
  /// nothing and throws std::runtime_error("cannot WHAT PATH: injected I/O error"); the power
  /// stays on. 0 disarms.
  void fail_at(std::uint64_t n);
  /// The error fail_at() injected; empty before it struck.
  [[nodiscard]] std::string injected() const;
  /// Mutating calls made so far.
  [[nodiscard]] std::uint64_t operations() const;
  /// Whether the power is off.
  [[nodiscard]] bool is_cut() const;
  /// The machine starts again with what was durable, with nothing armed. With `torn_seed`, a file whose unsynced
  /// bytes extend its durable ones keeps a seeded random prefix of them (a write torn by the
  /// cut); without, none.
  void power_on(std::optional<std::uint64_t> torn_seed = {});
  /// Whether exchange() can swap (a file system with RENAME_EXCHANGE); true by default.
  void set_exchange_supported(bool supported);

  std::unique_ptr<File> open(const std::filesystem::path& path, Open how) override;
  [[nodiscard]] std::optional<std::string> read(const std::filesystem::path& path) const override;
  [[nodiscard]] bool exists(const std::filesystem::path& path) const override;
  [[nodiscard]] std::optional<std::uint64_t> file_size(const std::filesystem::path& path) const override;
  [[nodiscard]] std::vector<std::string> list(const std::filesystem::path& dir) const override;
  void rename(const std::filesystem::path& from, const std::filesystem::path& to) override;
  bool exchange(const std::filesystem::path& a, const std::filesystem::path& b) override;
  bool remove(const std::filesystem::path& path) override;
  void remove_all(const std::filesystem::path& path) override;
  bool create_directories(const std::filesystem::path& dir) override;
  void sync_directory(const std::filesystem::path& dir) override;
  [[nodiscard]] std::unique_ptr<Lock> lock(const std::filesystem::path& dir) override;

  struct Inode {
    std::string live, durable;
  };
  struct Dir;
  /// A directory entry: a file or a directory.
  struct Entry {
    std::shared_ptr<Inode> file;
    std::shared_ptr<Dir> dir;
  };
  struct Dir {
    std::map<std::string, Entry> live, durable;
  };

 private:
  class MemFile;
  class MemLock;
  // Under mutex_: throws PowerCut when the power is off; counts a mutating call and cuts the
  // power at the armed one.
  void check_power() const;
  void mutate(const char* what, const std::filesystem::path& path);
  [[nodiscard]] const Entry* find(const std::filesystem::path& path) const;
  // The directory holding `path` (which must exist) and the name in it.
  [[nodiscard]] std::pair<Dir*, std::string> parent_of(const std::filesystem::path& path) const;

  mutable std::mutex mutex_;
  std::shared_ptr<Dir> root_;
  std::uint64_t operations_ = 0;
  std::uint64_t cut_at_ = 0;   // the operation count at which the power goes; 0: never
  std::uint64_t fail_at_ = 0;  // the operation count that fails; 0: none
  std::string injected_;
  bool cut_ = false;
  bool exchange_supported_ = true;
  std::set<const Dir*> locked_;
  std::uint64_t epoch_ = 0;  // power_on() count: a lock of an earlier epoch holds nothing
};

}  // namespace ispars::test
