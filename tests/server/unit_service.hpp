#pragma once
// A RoadmapService for unit tests: procedural scenes written into a temporary folder, and the
// settings of a small service over it (one build worker, one tour worker).

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <string>

#include "ispars/service/roadmap_service.hpp"
#include "server/service_waits.hpp"

namespace ispars::test {

/// Writes DIR/scenes/NAME.yaml for each of `names`: a procedural tank tower of seed 1.
inline void write_tank_scenes(const std::filesystem::path& dir, std::initializer_list<const char*> names) {
  std::filesystem::create_directories(dir / "scenes");
  for (const char* name : names) {
    std::ofstream(dir / "scenes" / (std::string(name) + ".yaml")) << "procedural: {kind: tank_tower, seed: 1}\n";
  }
}

/// A service `server_id` over DIR/scenes, storing in DIR/data, with one build and one tour worker.
inline service::ServiceSettings unit_service_settings(const std::filesystem::path& dir, const std::string& server_id) {
  service::ServiceSettings s;
  s.server_id = server_id;
  s.scene_dir = dir / "scenes";
  s.data_dir = dir / "data";
  s.build_workers = 1;
  s.tour_workers = 1;
  return s;
}

/// A service "unit" over DIR with scene s0 written and loaded and, when `samples` > 0, built to
/// that many samples (Inspection-SPARS, seed 1) and idle.
inline std::unique_ptr<service::RoadmapService> service_with_s0(const std::filesystem::path& dir,
                                                                std::uint64_t samples) {
  write_tank_scenes(dir, {"s0"});
  auto service =
      std::make_unique<service::RoadmapService>(unit_service_settings(dir, "unit"), service::ServiceEvents{});
  (void)service->load("s0");
  if (samples > 0) {
    BuildRequest r;
    r.samples = samples;
    service->build("s0", r);
    (void)wait_idle(*service, "s0");
  }
  return service;
}

}  // namespace ispars::test
