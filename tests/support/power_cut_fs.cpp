#include "support/power_cut_fs.hpp"

#include <random>
#include <utility>

namespace ispars::test {

using Entry = PowerCutFileSystem::Entry;
using Dir = PowerCutFileSystem::Dir;
using Inode = PowerCutFileSystem::Inode;

namespace {

std::runtime_error missing(const std::filesystem::path& path) {
  return std::runtime_error("no such file or directory: " + path.string());
}

}  // namespace

class PowerCutFileSystem::MemFile final : public FileSystem::File {
 public:
  MemFile(PowerCutFileSystem& fs, std::shared_ptr<Inode> inode, std::filesystem::path path)
      : fs_(fs), inode_(std::move(inode)), path_(std::move(path)) {}
  void append(std::string_view bytes) override {
    std::lock_guard lock(fs_.mutex_);
    fs_.mutate("write", path_);
    inode_->live.append(bytes);
  }
  void truncate(std::uint64_t size) override {
    std::lock_guard lock(fs_.mutex_);
    fs_.mutate("truncate", path_);
    if (size < inode_->live.size()) inode_->live.resize(size);
  }
  void sync() override {
    std::lock_guard lock(fs_.mutex_);
    fs_.mutate("fsync", path_);
    inode_->durable = inode_->live;
  }
  [[nodiscard]] std::uint64_t size() const override {
    std::lock_guard lock(fs_.mutex_);
    fs_.check_power();
    return inode_->live.size();
  }
  [[nodiscard]] std::string read(std::uint64_t offset, std::size_t count) const override {
    std::lock_guard lock(fs_.mutex_);
    fs_.check_power();
    if (offset >= inode_->live.size()) return {};
    return inode_->live.substr(offset, count);
  }

 private:
  PowerCutFileSystem& fs_;
  std::shared_ptr<Inode> inode_;
  std::filesystem::path path_;
};

class PowerCutFileSystem::MemLock final : public FileSystem::Lock {
 public:
  MemLock(PowerCutFileSystem& fs, const Dir* dir) : fs_(fs), dir_(dir), epoch_(fs.epoch_) {}
  ~MemLock() override {
    std::lock_guard lock(fs_.mutex_);
    if (fs_.epoch_ == epoch_) fs_.locked_.erase(dir_);  // else it went with the power
  }
  MemLock(const MemLock&) = delete;
  MemLock& operator=(const MemLock&) = delete;

 private:
  PowerCutFileSystem& fs_;
  const Dir* dir_;
  std::uint64_t epoch_;
};

PowerCutFileSystem::PowerCutFileSystem() : root_(std::make_shared<Dir>()) {}
PowerCutFileSystem::~PowerCutFileSystem() = default;

void PowerCutFileSystem::cut_at(std::uint64_t n) {
  std::lock_guard lock(mutex_);
  cut_at_ = n == 0 ? 0 : operations_ + n;
}

std::uint64_t PowerCutFileSystem::operations() const {
  std::lock_guard lock(mutex_);
  return operations_;
}

bool PowerCutFileSystem::is_cut() const {
  std::lock_guard lock(mutex_);
  return cut_;
}

void PowerCutFileSystem::set_exchange_supported(bool supported) {
  std::lock_guard lock(mutex_);
  exchange_supported_ = supported;
}

void PowerCutFileSystem::check_power() const {
  if (cut_) throw PowerCut();
}

void PowerCutFileSystem::mutate(const char* what, const std::filesystem::path& path) {
  check_power();
  ++operations_;
  if (cut_at_ != 0 && operations_ >= cut_at_) {
    cut_ = true;
    throw PowerCut();
  }
  if (fail_at_ != 0 && operations_ == fail_at_) {
    injected_ = std::string("cannot ") + what + " " + path.string() + ": injected I/O error";
    throw std::runtime_error(injected_);
  }
}

std::string PowerCutFileSystem::injected() const {
  std::lock_guard lock(mutex_);
  return injected_;
}

void PowerCutFileSystem::fail_at(std::uint64_t n) {
  std::lock_guard lock(mutex_);
  fail_at_ = n == 0 ? 0 : operations_ + n;
}

void PowerCutFileSystem::power_on(std::optional<std::uint64_t> torn_seed) {
  std::lock_guard lock(mutex_);
  std::mt19937_64 random(torn_seed.value_or(0));
  std::set<const void*> seen;  // a directory or file reached twice (a rename between two
                               // directories synced at different times) is restored once
  const auto restore_file = [&](Inode& f) {
    if (!seen.insert(&f).second) return;
    const bool appended = f.live.size() > f.durable.size() && f.live.compare(0, f.durable.size(), f.durable) == 0;
    if (torn_seed && appended) {
      const std::size_t extra = f.live.size() - f.durable.size();
      f.live.resize(f.durable.size() + static_cast<std::size_t>(random() % (extra + 1)));
    } else {
      f.live = f.durable;
    }
    f.durable = f.live;
  };
  const auto restore_dir = [&](auto& self, Dir& d) -> void {
    if (!seen.insert(&d).second) return;
    d.live = d.durable;
    for (auto& [name, entry] : d.live) {
      if (entry.file) restore_file(*entry.file);
      if (entry.dir) self(self, *entry.dir);
    }
  };
  restore_dir(restore_dir, *root_);
  cut_ = false;
  cut_at_ = 0;
  fail_at_ = 0;     // an armed failure that never struck is not carried past the restart
  locked_.clear();  // the processes that held them are gone
  ++epoch_;
}

const Entry* PowerCutFileSystem::find(const std::filesystem::path& path) const {
  const Dir* dir = root_.get();
  const Entry* entry = nullptr;
  for (const auto& part : path.relative_path()) {
    if (part.empty() || part == ".") continue;
    if (dir == nullptr) return nullptr;
    const auto it = dir->live.find(part.string());
    if (it == dir->live.end()) return nullptr;
    entry = &it->second;
    dir = entry->dir.get();
  }
  return entry;  // nullptr for "/" itself
}

std::pair<Dir*, std::string> PowerCutFileSystem::parent_of(const std::filesystem::path& path) const {
  const std::filesystem::path parent = path.parent_path();
  Dir* dir = root_.get();
  if (parent.has_relative_path()) {
    const Entry* e = find(parent);
    if (e == nullptr || !e->dir) throw missing(parent);
    dir = e->dir.get();
  }
  return {dir, path.filename().string()};
}

std::unique_ptr<FileSystem::File> PowerCutFileSystem::open(const std::filesystem::path& path, Open how) {
  std::lock_guard lock(mutex_);
  check_power();
  auto [dir, name] = parent_of(path);
  const auto it = dir->live.find(name);
  if (it != dir->live.end()) {
    if (!it->second.file) throw std::runtime_error("is a directory: " + path.string());
    if (how == Open::new_only) return nullptr;
    if (how == Open::truncated) {
      mutate("truncate", path);
      it->second.file->live.clear();
    }
    return std::make_unique<MemFile>(*this, it->second.file, path);
  }
  mutate("create", path);
  auto inode = std::make_shared<Inode>();
  dir->live[name] = Entry{inode, nullptr};
  return std::make_unique<MemFile>(*this, inode, path);
}

std::optional<std::string> PowerCutFileSystem::read(const std::filesystem::path& path) const {
  std::lock_guard lock(mutex_);
  check_power();
  const Entry* e = find(path);
  if (e == nullptr || !e->file) return std::nullopt;
  return e->file->live;
}

bool PowerCutFileSystem::exists(const std::filesystem::path& path) const {
  std::lock_guard lock(mutex_);
  check_power();
  return !path.has_relative_path() || find(path) != nullptr;
}

std::optional<std::uint64_t> PowerCutFileSystem::file_size(const std::filesystem::path& path) const {
  std::lock_guard lock(mutex_);
  check_power();
  const Entry* e = find(path);
  if (e == nullptr || !e->file) return std::nullopt;
  return e->file->live.size();
}

std::vector<std::string> PowerCutFileSystem::list(const std::filesystem::path& dir) const {
  std::lock_guard lock(mutex_);
  check_power();
  const Dir* d = root_.get();
  if (dir.has_relative_path()) {
    const Entry* e = find(dir);
    if (e == nullptr || !e->dir) return {};
    d = e->dir.get();
  }
  std::vector<std::string> names;
  for (const auto& [name, entry] : d->live) names.push_back(name);
  return names;
}

void PowerCutFileSystem::rename(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::lock_guard lock(mutex_);
  check_power();
  auto [from_dir, from_name] = parent_of(from);
  auto [to_dir, to_name] = parent_of(to);
  const auto it = from_dir->live.find(from_name);
  if (it == from_dir->live.end()) throw missing(from);
  if (const auto target = to_dir->live.find(to_name); target != to_dir->live.end()) {
    if (target->second.dir && !target->second.dir->live.empty()) {
      throw std::runtime_error("cannot rename onto a directory that is not empty: " + to.string());
    }
    if (static_cast<bool>(target->second.dir) != static_cast<bool>(it->second.dir)) {
      throw std::runtime_error("cannot rename a file onto a directory, or back: " + to.string());
    }
  }
  mutate("rename onto", to);
  Entry moved = it->second;
  from_dir->live.erase(it);
  to_dir->live[to_name] = std::move(moved);
}

bool PowerCutFileSystem::exchange(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::lock_guard lock(mutex_);
  check_power();
  if (!exchange_supported_) return false;
  auto [a_dir, a_name] = parent_of(a);
  auto [b_dir, b_name] = parent_of(b);
  const auto ia = a_dir->live.find(a_name);
  const auto ib = b_dir->live.find(b_name);
  if (ia == a_dir->live.end()) throw missing(a);
  if (ib == b_dir->live.end()) throw missing(b);
  mutate("exchange", b);
  std::swap(ia->second, ib->second);
  return true;
}

bool PowerCutFileSystem::remove(const std::filesystem::path& path) {
  std::lock_guard lock(mutex_);
  check_power();
  if (find(path) == nullptr) return false;  // as the disk's remove(): nothing there, parent or not
  auto [dir, name] = parent_of(path);
  const auto it = dir->live.find(name);
  if (it == dir->live.end()) return false;
  if (it->second.dir && !it->second.dir->live.empty()) {
    throw std::runtime_error("directory not empty: " + path.string());
  }
  mutate("remove", path);
  dir->live.erase(it);
  return true;
}

void PowerCutFileSystem::remove_all(const std::filesystem::path& path) {
  std::lock_guard lock(mutex_);
  check_power();
  const std::filesystem::path parent = path.parent_path();
  const Entry* p = parent.has_relative_path() ? find(parent) : nullptr;
  if (parent.has_relative_path() && (p == nullptr || !p->dir)) return;
  Dir* dir = p ? p->dir.get() : root_.get();
  const auto it = dir->live.find(path.filename().string());
  if (it == dir->live.end()) return;
  mutate("remove", path);
  dir->live.erase(it);
}

bool PowerCutFileSystem::create_directories(const std::filesystem::path& path) {
  std::lock_guard lock(mutex_);
  check_power();
  Dir* dir = root_.get();
  bool made = false;
  for (const auto& part : path.relative_path()) {
    if (part.empty() || part == ".") continue;
    auto it = dir->live.find(part.string());
    if (it == dir->live.end()) {
      mutate("create the directory", path);
      it = dir->live.emplace(part.string(), Entry{nullptr, std::make_shared<Dir>()}).first;
      made = true;
    } else if (!it->second.dir) {
      throw std::runtime_error("not a directory: " + path.string());
    } else {
      made = false;
    }
    dir = it->second.dir.get();
  }
  return made;
}

void PowerCutFileSystem::sync_directory(const std::filesystem::path& path) {
  std::lock_guard lock(mutex_);
  check_power();
  Dir* dir = root_.get();
  if (path.has_relative_path()) {
    const Entry* e = find(path);
    if (e == nullptr || !e->dir) throw missing(path);
    dir = e->dir.get();
  }
  mutate("fsync the directory", path);
  dir->durable = dir->live;
}

std::unique_ptr<FileSystem::Lock> PowerCutFileSystem::lock(const std::filesystem::path& path) {
  std::lock_guard lock(mutex_);
  check_power();
  const Entry* e = find(path);
  if (e == nullptr || !e->dir) throw missing(path);
  if (!locked_.insert(e->dir.get()).second) return nullptr;
  return std::make_unique<MemLock>(*this, e->dir.get());
}

}  // namespace ispars::test
