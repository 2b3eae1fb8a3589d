#pragma once
// Crash-safe files: an append-only file of checksummed records, and whole-file atomic writes.
//
// A record file is a magic string, then records, little-endian. The current layout (format 03)
// gives each record a header checked on its own: [u64 payload length][u32 CRC-32 of the payload]
// [u32 CRC-32 of those 12 bytes][payload]. Older layouts are still read and appended to: format 02
// [u32 length][u32 CRC-32][payload] (a length of 4 GiB or more escaped as [u32 0xFFFFFFFF][u32
// CRC-32][u64 length]), and format 01, the same without the escape. Appends are fsync'ed.
//
// A reader accepts every whole record its check accepts and stops at the first one that is not.
// Only an incomplete last record is what a crash while appending leaves (a torn tail); anything
// else is damage, to be left as it is and reported. In format 03 a bad record is a torn tail only
// if no valid record starts anywhere after it (a scan, cheap thanks to the header checksums); in
// formats 01 and 02 a length that runs past the end cannot be told from a torn append, so it is
// read as one. A writer never cuts bytes off a file without first copying them aside.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/roadmap/file_system.hpp"

namespace ispars {

/// How the records of a file are framed (see the file comment).
enum class RecordLayout : std::uint8_t {
  plain,    ///< format 01: [u32 length][u32 CRC]
  escaped,  ///< format 02: as plain, lengths of 4 GiB and more escaped to a u64
  checked,  ///< format 03: [u64 length][u32 CRC][u32 header CRC]
};

/// One magic a file of a format may start with, and the layout of the records after it.
struct RecordMagic {
  std::string_view magic;
  RecordLayout layout = RecordLayout::checked;
};

/// Which record files a reader or writer takes: the magic new files start with (first), then the
/// older magics still read and appended to, each with its own layout.
struct RecordFormat {
  RecordFormat(std::initializer_list<RecordMagic> magics) : versions(magics) {}
  RecordFormat(const char* magic) : versions{{magic, RecordLayout::checked}} {}  // NOLINT: a literal is a format
  /// The magic new files get.
  [[nodiscard]] std::string_view magic() const { return versions.front().magic; }
  std::vector<RecordMagic> versions;
};

/// The largest payload a record of a format 01 file holds (a 32-bit length, less the escape).
inline constexpr std::uint64_t kLegacyRecordLimit = 0xFFFFFFFEu;

/// The header of a record of `size` bytes with checksum `crc` in `layout` (16 bytes in format 03).
[[nodiscard]] std::string record_header(std::uint64_t size, std::uint32_t crc,
                                        RecordLayout layout = RecordLayout::checked);

/// CRC-32 (IEEE 802.3), zlib's.
[[nodiscard]] std::uint32_t crc32(const void* data, std::size_t size);

/// Checks one record's payload in sequence; returns an empty string to accept it, else what is
/// wrong (reading stops there, and the file is damaged: see RecordReplay::damaged).
using RecordCheck = std::function<std::string(const std::string& payload)>;

/// What reading a record file found.
struct RecordReplay {
  std::vector<std::string> payloads;  ///< Every accepted record, in order (unless only counted).
  std::size_t records = 0;            ///< How many records were accepted.
  std::uint64_t valid_bytes = 0;      ///< Length of the valid prefix of the file.
  bool torn_tail = false;             ///< Bytes follow the valid prefix.
  std::string tail_problem;           ///< What was wrong with them.
  /// The bytes after the valid prefix are not what a crash while appending leaves (an incomplete
  /// last record): a valid record follows the bad one (format 03), a record with more bytes after
  /// it fails its payload checksum, or a whole record was refused by the check. Such a file must
  /// be left as it is and reported, never cut.
  bool damaged = false;
  RecordLayout layout = RecordLayout::checked;  ///< The layout of the file's records.
};

/// Whether read_record_file keeps each accepted payload or only counts it (its check has used it:
/// a journal folded or replayed commit by commit need not hold them all at once).
enum class RecordKeep { payloads, count };

/// Thrown by read_record_file when a file starts with none of its format's magics.
struct RecordMagicMismatch : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads a record file (a missing or empty file has no records). Throws RecordMagicMismatch when
/// the file exists but starts with none of the format's magics.
[[nodiscard]] RecordReplay read_record_file(const std::filesystem::path& path, const RecordFormat& format,
                                            const RecordCheck& check, const FileSystem& fs = disk(),
                                            RecordKeep keep = RecordKeep::payloads);

/// Appends records to a file, durably.
class RecordFileWriter {
 public:
  /// Opens `path` for appending after its first `valid_bytes` bytes (from read_record_file), so new
  /// records never follow garbage. Bytes after them are first copied, durably, to a new file
  /// `PATH.torn.N` beside it (see set_aside()), then cut off; when the copy fails, this throws and
  /// the file is left whole. Creates the file (with the format's current magic) when missing or
  /// when `valid_bytes` is shorter than a magic.
  RecordFileWriter(const std::filesystem::path& path, const RecordFormat& format, std::uint64_t valid_bytes,
                   FileSystem& fs = disk());
  ~RecordFileWriter();
  RecordFileWriter(const RecordFileWriter&) = delete;
  RecordFileWriter& operator=(const RecordFileWriter&) = delete;

  /// Appends one record and fsyncs; when this returns, the record survives a crash. When the
  /// write or the fsync fails (a full disk, say), the file is cut back to its last record and the
  /// error thrown: a later append still follows a whole record. When even that cut fails, every
  /// later append throws too (the file keeps its partial tail, which a reader sees as torn).
  /// A payload of 4 GiB or more in a format 01 file throws, naming the limit.
  void append(std::string_view payload);
  /// Size of the file in bytes.
  [[nodiscard]] std::uint64_t size() const { return file_->size(); }
  /// Where the bytes cut off on opening were copied; empty when nothing was cut.
  [[nodiscard]] const std::filesystem::path& set_aside() const { return set_aside_; }

 private:
  std::filesystem::path path_;
  std::unique_ptr<FileSystem::File> file_;
  std::filesystem::path set_aside_;
  RecordLayout layout_ = RecordLayout::checked;
  bool broken_ = false;  // a failed append could not be undone
};

/// Thrown by write_record_file_atomically when its `keep_going` said stop.
struct RecordWriteStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Replaces `path` atomically with a file of the format's current magic holding `payload` as its
/// one record, written in pieces of at most 64 MiB (no copy of the payload is made). Between
/// pieces `keep_going` (when given) is asked; a false removes the temporary file and throws
/// RecordWriteStopped. Other failures remove it too, and throw std::runtime_error.
void write_record_file_atomically(const std::filesystem::path& path, const RecordFormat& format,
                                  std::string_view payload, const std::function<bool()>& keep_going = {},
                                  FileSystem& fs = disk());

/// Replaces `path` with `bytes` atomically: writes a temporary file beside it, fsyncs it, renames
/// it over `path` and fsyncs the directory. Readers see the old file or the new one, never a mix.
/// On failure the temporary file is removed (a full disk keeps no half-written copy).
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes, FileSystem& fs = disk());

/// fsyncs the directory holding `path`, making a rename or creation in it durable. Throws
/// std::runtime_error naming the directory when it cannot be opened or fsync'ed.
void fsync_directory_of(const std::filesystem::path& path, FileSystem& fs = disk());

/// Appends the bytes of a trivially copyable value to a byte string (little-endian machines).
template <class T>
void put_bytes(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// Reads fixed-size values from a byte string, throwing std::runtime_error on any overrun.
class ByteReader {
 public:
  explicit ByteReader(std::string_view data) : data_(data) {}
  template <class T>
  T get() {
    T value;
    read(&value, sizeof(T));
    return value;
  }
  /// The next `size` bytes.
  std::string_view bytes(std::size_t size);
  [[nodiscard]] bool done() const { return at_ == data_.size(); }
  [[nodiscard]] std::size_t remaining() const { return data_.size() - at_; }

 private:
  void read(void* out, std::size_t size);
  std::string_view data_;
  std::size_t at_ = 0;
};

}  // namespace ispars
