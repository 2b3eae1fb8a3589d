#pragma once
// Scene names and scene files as the service accepts them: resolved only inside one scene
// directory, and naming only files inside it.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/scene_files/scene_config.hpp"

namespace ispars::service {

/// Checks a scene name and returns its file, scene_dir/NAME.yaml. A name is 1 to 64 letters,
/// digits, '_', '-' or '.', not starting with '.'; so no path separator or ".." can reach outside
/// the directory, and the file (after following symlinks) must lie inside it. Throws InputError
/// (file "request", field "scene") naming what is wrong.
[[nodiscard]] std::filesystem::path scene_file(const std::filesystem::path& scene_dir, std::string_view name);

/// The names of the scenes in a directory (its valid NAME.yaml files), sorted.
[[nodiscard]] std::vector<std::string> list_scene_names(const std::filesystem::path& scene_dir);

/// The scene file of `name` (see scene_file), parsed, with every file it names (mesh, POI file)
/// checked to lie inside the scene directory after following symlinks: an absolute path, a
/// "../" or a symlink out is refused (InputError, field "scene", naming the key and the path).
[[nodiscard]] scene_files::SceneConfig load_scene_config(const std::filesystem::path& scene_dir, std::string_view name);

/// Whether `name` is a valid scene name (see scene_file).
[[nodiscard]] bool valid_scene_name(std::string_view name);

}  // namespace ispars::service
