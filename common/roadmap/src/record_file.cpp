#include "ispars/roadmap/record_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace ispars {
namespace {

static_assert(std::endian::native == std::endian::little, "record files are little-endian");

constexpr std::uint32_t kLengthEscape = 0xFFFFFFFFu;  // a u64 length follows the checksum

// Appends `bytes` to `file` in pieces of at most 64 MiB, asking `keep_going` between.
void write_pieces(FileSystem::File& file, std::string_view bytes, const std::filesystem::path& path,
                  const std::function<bool()>& keep_going) {
  constexpr std::size_t kPiece = std::size_t{64} << 20;
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    if (keep_going && !keep_going()) throw RecordWriteStopped("writing " + path.string() + " was stopped");
    file.append(bytes.substr(at, std::min(kPiece, bytes.size() - at)));
  }
}

}  // namespace

std::string record_header(std::uint64_t size, std::uint32_t crc, RecordLayout layout) {
  std::string header;
  if (layout == RecordLayout::checked) {
    put_bytes(header, size);
    put_bytes(header, crc);
    put_bytes(header, crc32(header.data(), header.size()));
  } else if (size > kLegacyRecordLimit) {
    put_bytes(header, kLengthEscape);
    put_bytes(header, crc);
    put_bytes(header, size);
  } else {
    put_bytes(header, static_cast<std::uint32_t>(size));
    put_bytes(header, crc);
  }
  return header;
}

std::uint32_t crc32(const void* data, std::size_t size) {
  return static_cast<std::uint32_t>(::crc32_z(0, static_cast<const Bytef*>(data), size));
}

std::string_view ByteReader::bytes(std::size_t size) {
  if (remaining() < size) throw std::runtime_error("payload is truncated");
  const std::string_view out = data_.substr(at_, size);
  at_ += size;
  return out;
}

void ByteReader::read(void* out, std::size_t size) {
  if (remaining() < size) throw std::runtime_error("payload is truncated");
  std::memcpy(out, data_.data() + at_, size);
  at_ += size;
}

namespace {

// One record's frame as read at some offset: its header's size and the payload it names, or
// what is wrong with it.
struct Frame {
  std::size_t header = 0;
  std::uint64_t length = 0;
  std::string problem;       // empty: the header is whole and the payload is in the file and intact
  bool payload_bad = false;  // the header is sound but the payload fails its checksum
};

Frame read_frame(std::string_view data, std::size_t at, RecordLayout layout) {
  Frame f;
  const std::size_t left = data.size() - at;
  const std::size_t minimum = layout == RecordLayout::checked ? 16 : 8;
  if (left < minimum) {
    f.problem = "incomplete record header";
    return f;
  }
  std::uint32_t checksum = 0;
  if (layout == RecordLayout::checked) {
    std::uint32_t header_checksum = 0;
    std::memcpy(&f.length, data.data() + at, 8);
    std::memcpy(&checksum, data.data() + at + 8, 4);
    std::memcpy(&header_checksum, data.data() + at + 12, 4);
    if (crc32(data.data() + at, 12) != header_checksum) {
      f.problem = "record header checksum mismatch";
      return f;
    }
    f.header = 16;
  } else {
    std::uint32_t short_length = 0;
    std::memcpy(&short_length, data.data() + at, 4);
    std::memcpy(&checksum, data.data() + at + 4, 4);
    f.length = short_length;
    f.header = 8;
    if (short_length == kLengthEscape && layout == RecordLayout::escaped) {
      if (left < 16) {
        f.problem = "incomplete record header";
        return f;
      }
      std::memcpy(&f.length, data.data() + at + 8, 8);
      f.header = 16;
    }
  }
  if (f.length > left - f.header) {
    f.problem = "record runs past the end of the file";
  } else if (crc32(data.data() + at + f.header, f.length) != checksum) {
    f.problem = "record checksum mismatch";
    f.payload_bad = true;
  }
  return f;
}

// Whether a whole, intact format 03 record starts anywhere in data[from, end). A header checksum
// is 12 bytes of CRC per offset, so the scan is linear; a false match (2^-32 per offset before the
// payload's own checksum) would only make a torn tail read as damage, never the reverse.
bool valid_record_after(std::string_view data, std::size_t from) {
  for (std::size_t at = from; at + 16 <= data.size(); ++at) {
    if (read_frame(data, at, RecordLayout::checked).problem.empty()) return true;
  }
  return false;
}

// Whether the bad record at `at` (frame `f`) is damage rather than a crash's torn last record.
bool is_damage(std::string_view data, std::size_t at, const Frame& f, RecordLayout layout) {
  // A record whose payload fails its checksum with bytes after it was whole once: appends are
  // sequential and fsync'ed, so the record after it was only begun once it was complete.
  if (f.payload_bad && at + f.header + f.length < data.size()) return true;
  // In format 03 a torn append is the last thing in the file: any valid record after it is not.
  return layout == RecordLayout::checked && valid_record_after(data, at + 1);
}

}  // namespace

RecordReplay read_record_file(const std::filesystem::path& path, const RecordFormat& format, const RecordCheck& check,
                              const FileSystem& fs, RecordKeep keep) {
  RecordReplay replay;
  const std::optional<std::string> file = fs.read(path);
  if (!file || file->empty()) return replay;  // no file yet
  const std::string& data = *file;
  const RecordMagic* found = nullptr;
  for (const RecordMagic& m : format.versions) {
    if (!m.magic.empty() && data.size() >= m.magic.size() && data.compare(0, m.magic.size(), m.magic) == 0) {
      found = &m;
      break;
    }
  }
  if (found == nullptr) {
    const std::string_view magic = format.magic();
    if (data.size() < magic.size() && magic.compare(0, data.size(), data) == 0) {
      replay.torn_tail = true;  // a crash while writing the magic itself
      replay.tail_problem = "incomplete file header";
      return replay;
    }
    throw RecordMagicMismatch(path.string() + " is not a " + std::string(magic) + " file (bad magic)");
  }
  replay.layout = found->layout;
  std::size_t at = found->magic.size();
  replay.valid_bytes = at;
  while (at < data.size()) {
    const Frame f = read_frame(data, at, replay.layout);
    if (!f.problem.empty()) {
      replay.damaged = is_damage(data, at, f, replay.layout);
      replay.tail_problem = f.problem;
      break;
    }
    std::string payload = data.substr(at + f.header, f.length);
    if (std::string problem = check(payload); !problem.empty()) {
      replay.damaged = true;  // a whole, intact record that cannot be used
      replay.tail_problem = std::move(problem);
      break;
    }
    if (keep == RecordKeep::payloads) replay.payloads.push_back(std::move(payload));
    ++replay.records;
    at += f.header + f.length;
    replay.valid_bytes = at;
  }
  replay.torn_tail = replay.valid_bytes < data.size();
  return replay;
}

namespace {

// Copies bytes [keep, end) of `file` (at `path`) to a new file `path.torn.N` (the first N free),
// durably; returns its path. A copy that fails is removed.
std::filesystem::path copy_tail_aside(FileSystem& fs, const FileSystem::File& file, const std::filesystem::path& path,
                                      std::uint64_t keep, std::uint64_t end) {
  std::filesystem::path aside;
  std::unique_ptr<FileSystem::File> out;
  for (int n = 1; !out; ++n) {
    aside = path;
    aside += ".torn." + std::to_string(n);
    out = fs.open(aside, FileSystem::Open::new_only);
  }
  try {
    constexpr std::size_t kPiece = std::size_t{1} << 20;
    for (std::uint64_t at = keep; at < end;) {
      const std::string piece = file.read(at, static_cast<std::size_t>(std::min<std::uint64_t>(kPiece, end - at)));
      if (piece.empty()) throw std::runtime_error("cannot read " + path.string() + ": it ended early");
      out->append(piece);
      at += piece.size();
    }
    out->sync();
  } catch (...) {
    out.reset();
    fs.remove(aside);
    throw;
  }
  fsync_directory_of(aside, fs);
  return aside;
}

}  // namespace

RecordFileWriter::RecordFileWriter(const std::filesystem::path& path, const RecordFormat& format,
                                   std::uint64_t valid_bytes, FileSystem& fs)
    : path_(path), file_(fs.open(path, FileSystem::Open::existing_or_new)) {
  const std::string_view magic = format.magic();
  layout_ = format.versions.front().layout;
  for (const RecordMagic& m : format.versions) {
    if (valid_bytes >= m.magic.size() && file_->read(0, m.magic.size()) == m.magic) {
      layout_ = m.layout;
      break;
    }
  }
  const std::uint64_t end = file_->size();
  const std::uint64_t keep = valid_bytes < magic.size() ? 0 : valid_bytes;
  if (end > keep) {
    set_aside_ = copy_tail_aside(fs, *file_, path_, keep, end);
    file_->truncate(keep);
  }
  if (keep == 0) {
    // New (or torn inside its header): start over with just the magic.
    layout_ = format.versions.front().layout;
    file_->append(magic);
  }
  file_->sync();
  fsync_directory_of(path_, fs);
}

RecordFileWriter::~RecordFileWriter() = default;

void RecordFileWriter::append(std::string_view payload) {
  if (broken_) {
    throw std::runtime_error(path_.string() +
                             " ends in a partial record that could not be cut off; no more records "
                             "are appended to it");
  }
  if (layout_ == RecordLayout::plain && payload.size() > kLegacyRecordLimit) {
    throw std::runtime_error("record of " + std::to_string(payload.size()) +
                             " bytes exceeds the 4 GiB record limit of " + path_.string() +
                             " (an older format; a compaction starts a file without the limit)");
  }
  const std::string header = record_header(payload.size(), crc32(payload.data(), payload.size()), layout_);
  const std::uint64_t whole = file_->size();
  try {
    file_->append(header);
    write_pieces(*file_, payload, path_, {});
    file_->sync();
  } catch (...) {
    // Back to the last whole record, so that a later append (after space is freed) never follows
    // a partial one.
    try {
      file_->truncate(whole);
    } catch (const std::exception&) {
      broken_ = true;
    }
    throw;
  }
}

namespace {

// Writes a temporary file beside `path` with `write`, fsyncs it, renames it over `path` and
// fsyncs the directory. A failure removes the temporary file.
template <class Write>
void replace_atomically(const std::filesystem::path& path, FileSystem& fs, const Write& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  try {
    {
      const std::unique_ptr<FileSystem::File> file = fs.open(tmp, FileSystem::Open::truncated);
      write(*file, tmp);
      file->sync();
    }
    fs.rename(tmp, path);
  } catch (...) {
    try {
      fs.remove(tmp);
    } catch (const std::exception&) {  // the first failure is the one to report
    }
    throw;
  }
  fsync_directory_of(path, fs);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes, FileSystem& fs) {
  replace_atomically(path, fs, [&](FileSystem::File& file, const std::filesystem::path&) { file.append(bytes); });
}

void write_record_file_atomically(const std::filesystem::path& path, const RecordFormat& format,
                                  std::string_view payload, const std::function<bool()>& keep_going, FileSystem& fs) {
  replace_atomically(path, fs, [&](FileSystem::File& file, const std::filesystem::path& tmp) {
    file.append(std::string(format.magic()) +
                record_header(payload.size(), crc32(payload.data(), payload.size()), format.versions.front().layout));
    write_pieces(file, payload, tmp, keep_going);
  });
}

void fsync_directory_of(const std::filesystem::path& path, FileSystem& fs) {
  fs.sync_directory(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
}

}  // namespace ispars
