#include "ispars/roadmap/record_file.hpp"

#include <fcntl.h>
#include <zlib.h>
#include <unistd.h>

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

std::string record_bytes(const std::string& payload) {
  if (payload.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::runtime_error("record of " + std::to_string(payload.size()) + " bytes exceeds the 4 GiB record limit");
  }
  std::string record;
  record.reserve(payload.size() + 8);
  put_bytes(record, static_cast<std::uint32_t>(payload.size()));
  put_bytes(record, crc32(payload.data(), payload.size()));
  record += payload;
  return record;
}

}  // namespace

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

RecordReplay read_record_file(const std::filesystem::path& path, std::string_view magic,
                              const RecordCheck& check) {
  RecordReplay replay;
  std::ifstream file(path, std::ios::binary);
  if (!file) return replay;  // no file yet
  const std::string data((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (data.empty()) return replay;
  if (data.size() < magic.size() || data.compare(0, magic.size(), magic) != 0) {
    if (data.size() < magic.size() && magic.compare(0, data.size(), data) == 0) {
      replay.torn_tail = true;  // a crash while writing the magic itself
      replay.tail_problem = "incomplete file header";
      return replay;
    }
    throw std::runtime_error(path.string() + " is not a " + std::string(magic) + " file (bad magic)");
  }
  std::size_t at = magic.size();
  replay.valid_bytes = at;
  while (at < data.size()) {
    const std::size_t left = data.size() - at;
    if (left < 8) {
      replay.tail_problem = "incomplete record header";
      break;
    }
    std::uint32_t length = 0;
    std::uint32_t checksum = 0;
    std::memcpy(&length, data.data() + at, 4);
    std::memcpy(&checksum, data.data() + at + 4, 4);
    if (length > left - 8) {
      replay.tail_problem = "record runs past the end of the file";
      break;
    }
    std::string payload = data.substr(at + 8, length);
    if (crc32(payload.data(), payload.size()) != checksum) {
      // The last record may be torn (its pages not all written before a crash); one with more
      // bytes after it was complete once, and has been damaged since.
      replay.damaged = at + 8 + length < data.size();
      replay.tail_problem = "record checksum mismatch";
      break;
    }
    if (std::string problem = check(payload); !problem.empty()) {
      replay.damaged = true;  // a whole, intact record that cannot be used
      replay.tail_problem = std::move(problem);
      break;
    }
    replay.payloads.push_back(std::move(payload));
    at += 8 + length;
    replay.valid_bytes = at;
  }
  replay.torn_tail = replay.valid_bytes < data.size();
  return replay;
}

RecordFileWriter::RecordFileWriter(const std::filesystem::path& path, std::string_view magic,
                                   std::uint64_t valid_bytes)
    : path_(path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(system_error("cannot open", path));
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

void RecordFileWriter::append(const std::string& payload) {
  if (broken_) {
    throw std::runtime_error(path_.string() + " ends in a partial record that could not be cut off; no more records "
                             "are appended to it");
  }
  const std::string record = record_bytes(payload);
  try {
    write_all(fd_, record.data(), record.size(), path_);
    if (::fsync(fd_) != 0) throw std::runtime_error(system_error("cannot fsync", path_));
  } catch (...) {
    // Back to the last whole record, so that a later append (after space is freed) never follows
    // a partial one.
    if (::ftruncate(fd_, static_cast<off_t>(size_)) != 0 || ::lseek(fd_, 0, SEEK_END) < 0) broken_ = true;
    throw;
  }
  size_ += record.size();
}

std::string single_record_file(std::string_view magic, const std::string& payload) {
  return std::string(magic) + record_bytes(payload);
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(system_error("cannot create", tmp));
  try {
    write_all(fd, bytes.data(), bytes.size(), tmp);
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

void fsync_directory_of(const std::filesystem::path& path) {
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace ispars
