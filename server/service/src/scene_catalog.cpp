#include "ispars/service/scene_catalog.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"

namespace ispars::service {
namespace {

// Whether `path`, with every symlink followed, lies inside `dir` (also resolved).
bool inside_directory(const std::filesystem::path& dir, const std::filesystem::path& path) {
  std::error_code ec;
  const auto real_dir = std::filesystem::weakly_canonical(dir, ec);
  if (ec) return false;
  const auto real = std::filesystem::weakly_canonical(path, ec);
  if (ec) return false;
  const auto rel = real.lexically_relative(real_dir);
  return !rel.empty() && *rel.begin() != ".." && !rel.is_absolute();
}

}  // namespace

bool valid_scene_name(std::string_view name) {
  if (name.empty() || name.size() > 64 || name.front() == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

std::filesystem::path scene_file(const std::filesystem::path& scene_dir, std::string_view name) {
  if (!valid_scene_name(name)) {
    std::string shown(name.substr(0, 80));
    for (char& c : shown) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    }
    throw params::InputError(
        "request", "scene",
        fmt::format("'{}' is not a scene name (1-64 of A-Z a-z 0-9 _ - ., not starting with '.')", shown));
  }
  const std::filesystem::path file = scene_dir / (std::string(name) + ".yaml");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw params::InputError("request", "scene", fmt::format("no scene '{}' in the daemon's scene directory", name));
  }
  if (!inside_directory(scene_dir, file)) {
    throw params::InputError("request", "scene", fmt::format("scene '{}' resolves outside the scene directory", name));
  }
  return file;
}

std::vector<std::string> list_scene_names(const std::filesystem::path& scene_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(scene_dir, ec)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    if (valid_scene_name(name) && entry.is_regular_file(ec)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

scene_files::SceneConfig load_scene_config(const std::filesystem::path& scene_dir, std::string_view name) {
  scene_files::SceneConfig config = scene_files::parse_scene_config(scene_file(scene_dir, name));
  const auto check = [&](const std::filesystem::path& referenced, const char* key) {
    if (referenced.empty() || inside_directory(scene_dir, referenced)) return;
    throw params::InputError(
        "request", "scene",
        fmt::format("scene '{}': {} '{}' is outside the scene directory (a scene file may name only "
                    "files inside it)",
                    name, key, referenced.string()));
  };
  check(config.mesh, "mesh");
  check(config.pois.file, "pois.file");
  return config;
}

}  // namespace ispars::service
