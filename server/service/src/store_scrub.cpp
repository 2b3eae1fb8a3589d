#include "ispars/service/store_scrub.hpp"

#include <algorithm>

#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/scene_catalog.hpp"

namespace ispars::service {

StoreScrub::StoreScrub(std::filesystem::path data_dir, Held held, std::shared_ptr<MemoryBudget> budget,
                       std::chrono::milliseconds period, const FileSystem& fs)
    : data_dir_(std::move(data_dir)),
      held_(std::move(held)),
      budget_(std::move(budget)),
      period_(period),
      fs_(fs),
      thread_([this] { run(); }) {}

StoreScrub::~StoreScrub() { stop(); }

void StoreScrub::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::string StoreScrub::problem(const std::string& scene) const {
  const FilesKey now = key_of(data_dir_ / scene);
  std::lock_guard lock(mutex_);
  const auto it = verdicts_.find(scene);
  return it != verdicts_.end() && it->second.key == now ? it->second.problem : std::string();
}

std::uint64_t StoreScrub::passes() const {
  std::lock_guard lock(mutex_);
  return passes_;
}

StoreScrub::FilesKey StoreScrub::key_of(const std::filesystem::path& dir) const {
  FilesKey key;
  for (const char* name : {"snapshot.bin", "journal.old", "journal.log", "head"}) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(dir / name, ec);
    const auto time = ec ? std::filesystem::file_time_type{} : std::filesystem::last_write_time(dir / name, ec);
    key.push_back(ec ? -1 : static_cast<std::int64_t>(size));
    key.push_back(ec ? -1 : static_cast<std::int64_t>(time.time_since_epoch().count()));
  }
  return key;
}

void StoreScrub::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    try {
      pass();
    } catch (const std::exception&) {
      // the data directory unreadable for a moment: the next pass
    }
    lock.lock();
    ++passes_;
    wake_.wait_for(lock, period_, [this] { return stopping_; });
  }
}

void StoreScrub::pass() {
  std::error_code ec;
  std::vector<std::string> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir_, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && valid_scene_name(name) && fs_.exists(entry.path() / "recipe.json")) {
      scenes.push_back(name);
    }
  }
  std::sort(scenes.begin(), scenes.end());
  {
    std::lock_guard lock(mutex_);  // stores gone (dropped, set aside) are forgotten
    std::erase_if(verdicts_, [&](const auto& v) { return !std::binary_search(scenes.begin(), scenes.end(), v.first); });
  }
  for (const std::string& scene : scenes) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    check(scene);
  }
}

void StoreScrub::check(const std::string& scene) {
  const auto held_now = [&] {
    const std::vector<std::string> held = held_();
    return std::find(held.begin(), held.end(), scene) != held.end();
  };
  const std::filesystem::path dir = data_dir_ / scene;
  const FilesKey key = key_of(dir);
  {
    std::lock_guard lock(mutex_);
    if (const auto it = verdicts_.find(scene); it != verdicts_.end() && it->second.key == key) return;  // read already
  }
  if (held_now()) return;  // a session writes it: recovery checked it when it was opened
  // The largest file is held whole while it is read, and its one record copied once more.
  double bytes = 0.0;
  for (std::size_t i = 0; i + 1 < key.size(); i += 2) bytes = std::max(bytes, 2.0 * static_cast<double>(key[i]));
  // Read only while the budget has room for it, and without a lease: background work never makes
  // a build or a tour busy (a build admitted during the read may pass the estimate by this much).
  if (bytes > budget_->total() - budget_->reserved() - budget_->leased()) return;  // the next pass
  std::string problem;
  try {
    problem = store_scrub_problem(dir, fs_);
  } catch (const std::exception& e) {  // a file that cannot be read at all is named too
    problem = e.what();
  }
  // Read while a session opened it, or rewritten meanwhile: this read says nothing.
  if (held_now() || key_of(dir) != key) return;
  std::lock_guard lock(mutex_);
  verdicts_[scene] = {key, std::move(problem)};
}

}  // namespace ispars::service
