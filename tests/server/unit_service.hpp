#pragma once
// A RoadmapService for unit tests: procedural scenes written into a temporary folder, and the
// settings of a small service over it (one build worker, one tour worker).

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "ispars/service/roadmap_service.hpp"

namespace ispars::test {

/// Writes DIR/scenes/NAME.yaml for each of `names`: a procedural tank tower of seed 1.
inline void write_tank_scenes(const std::filesystem::path& dir, std::initializer_list<const char*> names) {
  std::filesystem::create_directories(dir / "scenes");
  for (const char* name : names) {
    std::ofstream(dir / "scenes" / (std::string(name) + ".yaml")) << "procedural: {kind: tank_tower, seed: 1}\n";
  }
}

/// A service `server_id` over DIR/scenes, storing in DIR/data, with one build and one tour worker.
inline ServiceSettings unit_service_settings(const std::filesystem::path& dir, const std::string& server_id) {
  ServiceSettings s;
  s.server_id = server_id;
  s.scene_dir = dir / "scenes";
  s.data_dir = dir / "data";
  s.build_workers = 1;
  s.tour_workers = 1;
  return s;
}

}  // namespace ispars::test
