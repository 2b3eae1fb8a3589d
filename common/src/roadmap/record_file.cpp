#include "ispars/roadmap/record_file.hpp"

#include <fcntl.h>
#include <zlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace ispars {
namespace {

static_assert(std::endian::native == std::endian::little, "record files are little-endian");

std::string system_error(const std::string& what, const std::filesystem::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
}

void write_all(int fd, const char* data, std::size_t size, const std::filesystem::path& path) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(system_error("cannot write", path));
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

constexpr std::uint32_t kLengthEscape = 0xFFFFFFFFu;  // a u64 length follows the checksum

// Writes `size` bytes at the end of `fd` in pieces of at most 64 MiB, asking `keep_going` between.
void write_pieces(int fd, std::string_view bytes, const std::filesystem::path& path,
                  const std::function<bool()>& keep_going) {
  constexpr std::size_t kPiece = std::size_t{64} << 20;
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    if (keep_going && !keep_going()) throw RecordWriteStopped("writing " + path.string() + " was stopped");
    const std::size_t n = std::min(kPiece, bytes.size() - at);
    write_all(fd, bytes.data() + at, n, path);
  }
}

}  // namespace

std::string record_header(std::uint64_t size, std::uint32_t crc) {
  std::string header;
  if (size > kLegacyRecordLimit) {
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

RecordReplay read_record_file(const std::filesystem::path& path, const RecordFormat& format,
                              const RecordCheck& check) {
  RecordReplay replay;
  std::ifstream file(path, std::ios::binary);
  if (!file) return replay;  // no file yet
  const std::string data((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (data.empty()) return replay;
  const auto starts_with = [&](std::string_view magic) {
    return !magic.empty() && data.size() >= magic.size() && data.compare(0, magic.size(), magic) == 0;
  };
  replay.legacy = starts_with(format.legacy_magic);
  if (!replay.legacy && !starts_with(format.magic)) {
    if (data.size() < format.magic.size() && format.magic.compare(0, data.size(), data) == 0) {
      replay.torn_tail = true;  // a crash while writing the magic itself
      replay.tail_problem = "incomplete file header";
      return replay;
    }
    throw std::runtime_error(path.string() + " is not a " + std::string(format.magic) + " file (bad magic)");
  }
  std::size_t at = replay.legacy ? format.legacy_magic.size() : format.magic.size();
  replay.valid_bytes = at;
  while (at < data.size()) {
    const std::size_t left = data.size() - at;
    if (left < 8) {
      replay.tail_problem = "incomplete record header";
      break;
    }
    std::uint32_t short_length = 0;
    std::uint32_t checksum = 0;
    std::memcpy(&short_length, data.data() + at, 4);
    std::memcpy(&checksum, data.data() + at + 4, 4);
    std::uint64_t length = short_length;
    std::size_t header = 8;
    if (short_length == kLengthEscape && !replay.legacy) {
      if (left < 16) {
        replay.tail_problem = "incomplete record header";
        break;
      }
      std::memcpy(&length, data.data() + at + 8, 8);
      header = 16;
    }
    if (length > left - header) {
      replay.tail_problem = "record runs past the end of the file";
      break;
    }
    std::string payload = data.substr(at + header, length);
    if (crc32(payload.data(), payload.size()) != checksum) {
      // The last record may be torn (its pages not all written before a crash); one with more
      // bytes after it was complete once, and has been damaged since.
      replay.damaged = at + header + length < data.size();
      replay.tail_problem = "record checksum mismatch";
      break;
    }
    if (std::string problem = check(payload); !problem.empty()) {
      replay.damaged = true;  // a whole, intact record that cannot be used
      replay.tail_problem = std::move(problem);
      break;
    }
    replay.payloads.push_back(std::move(payload));
    at += header + length;
    replay.valid_bytes = at;
  }
  replay.torn_tail = replay.valid_bytes < data.size();
  return replay;
}

RecordFileWriter::RecordFileWriter(const std::filesystem::path& path, const RecordFormat& format,
                                   std::uint64_t valid_bytes)
    : path_(path) {
  const std::string_view magic = format.magic;
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(system_error("cannot open", path));
  if (valid_bytes >= magic.size() && !format.legacy_magic.empty()) {
    std::string head(format.legacy_magic.size(), '\0');
    legacy_ = ::pread(fd_, head.data(), head.size(), 0) == static_cast<ssize_t>(head.size()) &&
              head == format.legacy_magic;
  }
  if (valid_bytes < magic.size()) {
    // New (or torn inside its header): start over with just the magic.
    if (::ftruncate(fd_, 0) != 0) throw std::runtime_error(system_error("cannot truncate", path));
    write_all(fd_, magic.data(), magic.size(), path);
    size_ = magic.size();
  } else {
    if (::ftruncate(fd_, static_cast<off_t>(valid_bytes)) != 0) {
      throw std::runtime_error(system_error("cannot cut the torn tail of", path));
    }
    size_ = valid_bytes;
  }
  if (::lseek(fd_, 0, SEEK_END) < 0) throw std::runtime_error(system_error("cannot seek", path));
  if (::fsync(fd_) != 0) throw std::runtime_error(system_error("cannot fsync", path));
  fsync_directory_of(path);
}

RecordFileWriter::~RecordFileWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void RecordFileWriter::append(std::string_view payload) {
  if (broken_) {
    throw std::runtime_error(path_.string() + " ends in a partial record that could not be cut off; no more records "
                             "are appended to it");
  }
  if (legacy_ && payload.size() > kLegacyRecordLimit) {
    throw std::runtime_error("record of " + std::to_string(payload.size()) + " bytes exceeds the 4 GiB record limit of " +
                             path_.string() + " (an older format; a compaction starts a file without the limit)");
  }
  const std::string header = record_header(payload.size(), crc32(payload.data(), payload.size()));
  try {
    write_all(fd_, header.data(), header.size(), path_);
    write_pieces(fd_, payload, path_, {});
    if (::fsync(fd_) != 0) throw std::runtime_error(system_error("cannot fsync", path_));
  } catch (...) {
    // Back to the last whole record, so that a later append (after space is freed) never follows
    // a partial one.
    if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0 || ::lseek(fd_, 0, SEEK_END) < 0) broken_ = true;
    throw;
  }
  size_ += header.size() + payload.size();
}

namespace {

// Writes a temporary file beside `path` with `write`, fsyncs it and renames it over `path`.
template <class Write>
void replace_atomically(const std::filesystem::path& path, const Write& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(system_error("cannot create", tmp));
  try {
    write(fd, tmp);
    if (::fsync(fd) != 0) throw std::runtime_error(system_error("cannot fsync", tmp));
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string error = system_error("cannot rename onto", path);
    ::unlink(tmp.c_str());
    throw std::runtime_error(error);
  }
  fsync_directory_of(path);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  replace_atomically(path, [&](int fd, const std::filesystem::path& tmp) { write_all(fd, bytes.data(), bytes.size(), tmp); });
}

void write_record_file_atomically(const std::filesystem::path& path, const RecordFormat& format,
                                  std::string_view payload, const std::function<bool()>& keep_going) {
  replace_atomically(path, [&](int fd, const std::filesystem::path& tmp) {
    const std::string head = std::string(format.magic) + record_header(payload.size(), crc32(payload.data(), payload.size()));
    write_all(fd, head.data(), head.size(), tmp);
    write_pieces(fd, payload, tmp, keep_going);
  });
}

void fsync_directory_of(const std::filesystem::path& path) {
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace ispars
