#include "ispars/service/published_roadmap.hpp"

#include <utility>

namespace ispars::service {

PublishedRoadmap make_published(std::shared_ptr<const Roadmap> roadmap, std::uint64_t generation,
                                std::uint64_t samples) {
  PublishedRoadmap p{std::move(roadmap), generation, samples};
  p.pois_covered = p.roadmap->covered_pois();
  p.pois_covered_root = p.roadmap->vertex_count() > 0 ? p.roadmap->covered_pois_in_component_of(0) : 0;
  return p;
}

}  // namespace ispars::service
