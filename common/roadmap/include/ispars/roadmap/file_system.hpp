#pragma once
// The file operations a durable store makes, behind one small interface, so that a test can stand
// in for the disk: tests/support's PowerCutFileSystem remembers what was made durable (fsync of a
// file, fsync of a directory) and drops everything else at a chosen moment, as a power cut would.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ispars {

/// A file system as a store uses it. Every failure throws std::runtime_error naming the path and
/// the reason. Nothing a call changes is durable until the file's sync() (its bytes) and its
/// directory's sync_directory() (its name: a creation, a rename or a removal in that directory).
class FileSystem {
 public:
  /// An open file, written at its end.
  class File {
   public:
    virtual ~File() = default;
    virtual void append(std::string_view bytes) = 0;
    /// Cuts the file to `size` bytes (no longer than it is).
    virtual void truncate(std::uint64_t size) = 0;
    /// fsync: the file's bytes are durable when this returns.
    virtual void sync() = 0;
    [[nodiscard]] virtual std::uint64_t size() const = 0;
    /// Up to `count` bytes from `offset` (fewer at the end of the file).
    [[nodiscard]] virtual std::string read(std::uint64_t offset, std::size_t count) const = 0;
  };
  /// How open() treats the file at the path.
  enum class Open {
    existing_or_new,  ///< as it is, created empty when missing
    truncated,        ///< emptied, created when missing
    new_only,         ///< created; nullptr when the path exists
  };
  /// Held while a directory is locked against a second writer (in this process or another).
  class Lock {
   public:
    virtual ~Lock() = default;
  };

  virtual ~FileSystem() = default;
  virtual std::unique_ptr<File> open(const std::filesystem::path& path, Open how) = 0;
  /// The whole file; nullopt when there is no file at the path.
  [[nodiscard]] virtual std::optional<std::string> read(const std::filesystem::path& path) const = 0;
  [[nodiscard]] virtual bool exists(const std::filesystem::path& path) const = 0;
  /// The size of the file at the path; nullopt when there is none.
  [[nodiscard]] virtual std::optional<std::uint64_t> file_size(const std::filesystem::path& path) const = 0;
  /// The names in a directory (empty when it is missing), sorted.
  [[nodiscard]] virtual std::vector<std::string> list(const std::filesystem::path& dir) const = 0;
  /// Renames a file or a directory, replacing a file (or an empty directory) at `to`.
  virtual void rename(const std::filesystem::path& from, const std::filesystem::path& to) = 0;
  /// Swaps two paths in one step; false (and nothing changed) when the file system cannot.
  virtual bool exchange(const std::filesystem::path& a, const std::filesystem::path& b) = 0;
  /// Removes a file or an empty directory; false when there was none.
  virtual bool remove(const std::filesystem::path& path) = 0;
  /// Removes a file or a directory with everything in it (nothing when missing).
  virtual void remove_all(const std::filesystem::path& path) = 0;
  /// Creates a directory and its missing parents; true when it made the last one.
  virtual bool create_directories(const std::filesystem::path& dir) = 0;
  /// fsync of a directory: creations, renames and removals in it are durable when this returns.
  virtual void sync_directory(const std::filesystem::path& dir) = 0;
  /// Locks `dir` against a second writer; nullptr when another holds it.
  [[nodiscard]] virtual std::unique_ptr<Lock> lock(const std::filesystem::path& dir) = 0;
};

/// The machine's file systems (POSIX calls; the lock is flock).
[[nodiscard]] FileSystem& disk();

}  // namespace ispars
