#include "ispars/roadmap/file_system.hpp"

#include <fcntl.h>
#include <stdio.h>  // renameat2
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace ispars {
namespace {

std::string os_error(const std::string& what, const std::filesystem::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
}

class DiskFile final : public FileSystem::File {
 public:
  DiskFile(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) {
      const std::string error = os_error("cannot stat", path_);
      ::close(fd_);
      throw std::runtime_error(error);
    }
    size_ = static_cast<std::uint64_t>(st.st_size);
  }
  ~DiskFile() override { ::close(fd_); }
  DiskFile(const DiskFile&) = delete;
  DiskFile& operator=(const DiskFile&) = delete;

  void append(std::string_view bytes) override {
    while (!bytes.empty()) {
      const ssize_t n = ::pwrite(fd_, bytes.data(), bytes.size(), static_cast<off_t>(size_));
      if (n < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error(os_error("cannot write", path_));
      }
      bytes.remove_prefix(static_cast<std::size_t>(n));
      size_ += static_cast<std::uint64_t>(n);
    }
  }
  void truncate(std::uint64_t size) override {
    if (::ftruncate(fd_, static_cast<off_t>(size)) != 0) throw std::runtime_error(os_error("cannot truncate", path_));
    size_ = size;
  }
  void sync() override {
    if (::fsync(fd_) != 0) throw std::runtime_error(os_error("cannot fsync", path_));
  }
  [[nodiscard]] std::uint64_t size() const override { return size_; }
  [[nodiscard]] std::string read(std::uint64_t offset, std::size_t count) const override {
    std::string out(count, '\0');
    std::size_t got = 0;
    while (got < count) {
      const ssize_t n = ::pread(fd_, out.data() + got, count - got, static_cast<off_t>(offset + got));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw std::runtime_error(os_error("cannot read", path_));
      if (n == 0) break;
      got += static_cast<std::size_t>(n);
    }
    out.resize(got);
    return out;
  }

 private:
  int fd_;
  std::filesystem::path path_;
  std::uint64_t size_ = 0;  // a write past a failed one starts where the file ends
};

class DiskLock final : public FileSystem::Lock {
 public:
  explicit DiskLock(int fd) : fd_(fd) {}
  ~DiskLock() override { ::close(fd_); }
  DiskLock(const DiskLock&) = delete;
  DiskLock& operator=(const DiskLock&) = delete;

 private:
  int fd_;
};

class Disk final : public FileSystem {
 public:
  std::unique_ptr<File> open(const std::filesystem::path& path, Open how) override {
    int flags = O_RDWR | O_CREAT | O_CLOEXEC;
    if (how == Open::truncated) flags |= O_TRUNC;
    if (how == Open::new_only) flags |= O_EXCL;
    const int fd = ::open(path.c_str(), flags, 0644);
    if (fd < 0) {
      if (how == Open::new_only && errno == EEXIST) return nullptr;
      throw std::runtime_error(os_error("cannot open", path));
    }
    return std::make_unique<DiskFile>(fd, path);
  }
  [[nodiscard]] std::optional<std::string> read(const std::filesystem::path& path) const override {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw std::runtime_error(os_error("cannot read", path));
    return bytes;
  }
  [[nodiscard]] bool exists(const std::filesystem::path& path) const override { return std::filesystem::exists(path); }
  [[nodiscard]] std::optional<std::uint64_t> file_size(const std::filesystem::path& path) const override {
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) return std::nullopt;
    return size;
  }
  [[nodiscard]] std::vector<std::string> list(const std::filesystem::path& dir) const override {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }
  void rename(const std::filesystem::path& from, const std::filesystem::path& to) override {
    if (::rename(from.c_str(), to.c_str()) != 0) {
      throw std::runtime_error(os_error("cannot rename " + from.string() + " to", to));
    }
  }
  bool exchange(const std::filesystem::path& a, const std::filesystem::path& b) override {
    if (::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0) return true;
    if (errno == EINVAL || errno == ENOSYS) return false;
    throw std::runtime_error(os_error("cannot exchange " + a.string() + " with", b));
  }
  bool remove(const std::filesystem::path& path) override { return std::filesystem::remove(path); }
  void remove_all(const std::filesystem::path& path) override { std::filesystem::remove_all(path); }
  bool create_directories(const std::filesystem::path& dir) override {
    return std::filesystem::create_directories(dir);
  }
  void sync_directory(const std::filesystem::path& dir) override {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(os_error("cannot open the directory", dir));
    const bool synced = ::fsync(fd) == 0;
    const std::string error = synced ? std::string() : os_error("cannot fsync the directory", dir);
    ::close(fd);
    if (!synced) throw std::runtime_error(error);
  }
  [[nodiscard]] std::unique_ptr<Lock> lock(const std::filesystem::path& dir) override {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(os_error("cannot open the directory", dir));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const bool held = errno == EWOULDBLOCK;
      const std::string error = os_error("cannot lock", dir);
      ::close(fd);
      if (held) return nullptr;
      throw std::runtime_error(error);
    }
    return std::make_unique<DiskLock>(fd);
  }
};

}  // namespace

FileSystem& disk() {
  static Disk instance;
  return instance;
}

}  // namespace ispars
