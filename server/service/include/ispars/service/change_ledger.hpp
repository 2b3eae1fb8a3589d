#pragma once
// The change requests this daemon began and answered, kept on disk (DATA_DIR/.changes.log), so a
// client's retry of one, sent again to the daemon after it restarted, is answered and not done
// twice (an EXTEND is relative: done again, it would extend twice).

#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ispars/roadmap/file_system.hpp"

namespace ispars::service {

/// The answer a change request got: what its retry is told.
struct LedgerAnswer {
  bool ok = false;
  std::string error;    ///< When not ok.
  std::string message;  ///< When ok.
};

/// One change request: begun (durable before it changed anything), and its answer once sent.
struct LedgerEntry {
  std::string client;
  std::uint64_t seq = 0;
  std::string operation;  ///< Its name on the wire ("EXTEND").
  std::string scene;
  std::optional<LedgerAnswer> answer;
};

/// An append-only file of sealed one-line records, one "begun" and one "answered" per change.
/// `begin` is fsync'ed before the change is made; an answer is not (lost at a power cut, the
/// retry is told the request was interrupted, never run again). The file keeps at least the last
/// `keep` requests and is rewritten (atomically) when it holds four times as many records. A record
/// that fails its seal is skipped and named in damage(), and the file is copied whole to
/// .changes.log.damaged before any rewrite; an unended last line (an answer torn by a power cut)
/// is not damage (torn_tail()): it is ended and marked as a tear. Safe from many threads.
class ChangeLedger {
 public:
  /// Opens (or creates) `data_dir`/.changes.log and reads it. Throws std::runtime_error naming
  /// the file when it cannot be opened or read.
  explicit ChangeLedger(const std::filesystem::path& data_dir, FileSystem& fs = disk(), std::size_t keep = 4096);

  /// A request found in the file at open (begun in an earlier run of the daemon), or nothing.
  /// A request begun and never answered comes back with its answer unset.
  [[nodiscard]] std::optional<LedgerEntry> from_before(const std::string& client, std::uint64_t seq) const;
  /// Records that `client`'s request `seq` begins, durably. Throws std::runtime_error naming the
  /// file when it cannot be written: the change must then not be made.
  void begin(const std::string& client, std::uint64_t seq, const std::string& operation, const std::string& scene);
  /// Records the answer of a request begun and not yet answered (not synced); anything else is
  /// ignored. Errors are logged, not thrown.
  void answer(const std::string& client, std::uint64_t seq, const LedgerAnswer& answer);

  /// Records at open that failed their seal: "FILE: record at byte N fails its checksum".
  [[nodiscard]] const std::vector<std::string>& damage() const { return damage_; }
  /// Whether the file ended in a torn record at open.
  [[nodiscard]] bool torn_tail() const { return torn_at_.has_value(); }
  /// Requests read at open.
  [[nodiscard]] std::size_t recovered() const { return before_.size(); }
  /// The file.
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  using Key = std::pair<std::string, std::uint64_t>;
  void read_existing();
  void append(const std::string& line, bool sync);  // under mutex_
  void compact();                                   // under mutex_
  [[nodiscard]] std::filesystem::path aside_path() const { return path_.string() + ".damaged"; }
  std::filesystem::path path_;
  FileSystem& fs_;
  std::size_t keep_;
  mutable std::mutex mutex_;
  std::unique_ptr<FileSystem::File> file_;
  std::map<Key, LedgerEntry> before_;  // from earlier runs, read at open
  std::deque<LedgerEntry> recent_;     // the newest requests (earlier runs' included), for a rewrite
  std::size_t records_ = 0;            // records in the file
  std::vector<std::string> damage_;
  std::optional<std::uint64_t> torn_at_;  // the offset of a torn last line at open
};

}  // namespace ispars::service
