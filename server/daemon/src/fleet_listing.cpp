#include "ispars/server/fleet_listing.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/service/scene_catalog.hpp"

namespace ispars::server {

FleetListing::FleetListing(std::filesystem::path scene_dir, std::filesystem::path data_dir)
    : scene_dir_(std::move(scene_dir)), data_dir_(std::move(data_dir)), fingerprints_(scene_dir_) {}

bool FleetListing::refresh(const std::optional<std::vector<std::string>>& loaded,
                           const std::function<std::string(const std::string&)>& scrubbed) {
  std::vector<std::string> available = service::list_scene_names(scene_dir_);
  service::StoredListing listing;
  if (loaded) listing = service::list_stored_roadmaps(data_dir_, *loaded, &fingerprints_, scrubbed);
  const auto same = [](const std::vector<service::ServedRoadmap>& a, const std::vector<service::ServedRoadmap>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                      [](const service::ServedRoadmap& x, const service::ServedRoadmap& y) {
                        return x.scene == y.scene && x.generation == y.generation && x.samples == y.samples &&
                               x.task_events == y.task_events;
                      });
  };
  std::lock_guard lock(mutex_);
  std::map<std::string, std::string> unservable;
  for (const service::UnservableStore& u : listing.unservable) {
    auto& note = notes_[u.scene];
    if (note != u.why) spdlog::warn("scene '{}': {}", u.scene, u.why);
    note = u.why;
    unservable[u.scene] = u.why;
  }
  for (const auto& [scene, why] : unservable_) {  // servable again (a scene file restored): its note goes
    if (!unservable.contains(scene) && notes_[scene] == why) notes_.erase(scene);
  }
  unservable_ = std::move(unservable);
  if (available == available_ && listing.scenes == stored_ && same(listing.served, stored_roadmaps_)) return false;
  available_ = std::move(available);
  stored_ = std::move(listing.scenes);
  stored_roadmaps_ = std::move(listing.served);
  return true;
}

void FleetListing::describe(msg::DaemonInfo& info, std::vector<service::ServedRoadmap> held) const {
  std::lock_guard lock(mutex_);
  for (const std::string& name : available_) info.available().push_back(name);
  for (const std::string& name : stored_) info.stored().push_back(name);
  for (const service::ServedRoadmap& r : stored_roadmaps_) {
    const bool is_held =
        std::any_of(held.begin(), held.end(), [&](const service::ServedRoadmap& h) { return h.scene == r.scene; });
    if (!is_held) held.push_back(r);  // a scene loaded since the listing: the live figures count
  }
  for (const service::ServedRoadmap& r : held) {
    msg::StoredRoadmap m;
    m.scene(r.scene);
    m.generation(r.generation);
    m.samples(r.samples);
    m.target(r.target);
    m.task_events(r.task_events);
    m.builder_version(kBuilderVersion);
    m.fingerprint(r.fingerprint.substr(0, 64));
    if (const auto h = handed_over_.find(r.scene); h != handed_over_.end() && !r.held) {
      m.yielded_to(h->second.to);
      m.target(std::max(r.samples, h->second.accepted));
      m.task_events(std::max(r.task_events, h->second.task_events));
    }
    info.roadmaps().push_back(std::move(m));
  }
  const auto now = std::chrono::steady_clock::now();
  for (const auto& [scene, until] : declined_) {
    if (until > now) info.declined().push_back(scene);
  }
}

void FleetListing::hand_over(const std::string& scene, Handover handover, const std::string& note) {
  std::lock_guard lock(mutex_);
  handed_over_[scene] = std::move(handover);
  notes_[scene] = note;
}

void FleetListing::held_again(const std::string& scene) {
  std::lock_guard lock(mutex_);
  handed_over_.erase(scene);
  declined_.erase(scene);
}

void FleetListing::decline(const std::string& scene, std::chrono::steady_clock::time_point until) {
  std::lock_guard lock(mutex_);
  std::erase_if(declined_, [now = std::chrono::steady_clock::now()](const auto& d) { return d.second <= now; });
  declined_[scene] = until;
}

std::vector<std::pair<std::string, std::string>> FleetListing::handed_over() const {
  std::lock_guard lock(mutex_);
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [scene, h] : handed_over_) out.emplace_back(scene, h.to);
  return out;
}

std::vector<std::string> FleetListing::unservable() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [scene, why] : unservable_) out.push_back(scene);
  return out;
}

std::size_t FleetListing::declined_now() const {
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  return static_cast<std::size_t>(
      std::count_if(declined_.begin(), declined_.end(), [&](const auto& d) { return d.second > now; }));
}

void FleetListing::set_note(const std::string& scene, const std::string& note) {
  std::lock_guard lock(mutex_);
  notes_[scene] = note;
}

std::string FleetListing::note(const std::string& scene) const {
  std::lock_guard lock(mutex_);
  const auto it = notes_.find(scene);
  return it == notes_.end() ? std::string() : it->second;
}

}  // namespace ispars::server
