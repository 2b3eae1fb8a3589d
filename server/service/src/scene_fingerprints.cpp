#include "ispars/service/scene_fingerprints.hpp"

#include <fmt/format.h>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/scene/scene_fingerprint.hpp"
#include "ispars/service/scene_catalog.hpp"

namespace ispars::service {
namespace {

// Size and modification time of each file, or "-" for one that is missing.
std::string stamp_of(std::initializer_list<std::filesystem::path> files) {
  std::string out;
  for (const auto& f : files) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(f, ec);
    const auto time = ec ? std::filesystem::file_time_type{} : std::filesystem::last_write_time(f, ec);
    out += ec ? std::string("-;") : fmt::format("{}:{};", size, time.time_since_epoch().count());
  }
  return out;
}

}  // namespace

CurrentFingerprint SceneFingerprints::of(const std::string& name) {
  // The YAML first: the mesh and POI file it names are stamped as it names them now.
  std::string stamp;
  scene_files::SceneConfig config;
  try {
    stamp = stamp_of({scene_file(scene_dir_, name)});
    config = load_scene_config(scene_dir_, name);
  } catch (const std::exception& e) {
    return {"", fmt::format("this daemon's scene file does not load: {}", e.what())};
  }
  stamp += stamp_of({config.mesh, config.pois.file});
  {
    std::lock_guard lock(mutex_);
    if (const auto it = known_.find(name); it != known_.end() && it->second.stamp == stamp) return it->second.value;
  }
  CurrentFingerprint value;
  try {
    value.fingerprint = scene_fingerprint(planning::Scene::build(config));
  } catch (const std::exception& e) {
    value.problem = fmt::format("this daemon's scene file does not load: {}", e.what());
  }
  std::lock_guard lock(mutex_);
  known_[name] = {stamp, value};
  return value;
}

}  // namespace ispars::service
