#include "ispars/service/scene_catalog.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "ispars/input_error.hpp"

namespace ispars {

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
    throw InputError("request", "scene",
                     fmt::format("'{}' is not a scene name (1-64 of A-Z a-z 0-9 _ - ., not starting with '.')",
                                 shown));
  }
  const std::filesystem::path file = scene_dir / (std::string(name) + ".yaml");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError("request", "scene", fmt::format("no scene '{}' in the daemon's scene directory", name));
  }
  const auto dir = std::filesystem::weakly_canonical(scene_dir, ec);
  const auto real = std::filesystem::weakly_canonical(file, ec);
  const auto rel = real.lexically_relative(dir);
  if (ec || rel.empty() || *rel.begin() == "..") {
    throw InputError("request", "scene", fmt::format("scene '{}' resolves outside the scene directory", name));
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

}  // namespace ispars
