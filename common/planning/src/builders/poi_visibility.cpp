#include "ispars/builders/poi_visibility.hpp"

#include <vector>

namespace ispars {

PoiSetTable new_poi_visibility(const Scene& widened, const Roadmap& roadmap, PoiId first,
                               const std::function<bool()>& keep_going) {
  PoiSetTable fresh(widened.pois().size() - first);
  std::vector<PoiId> in_range, ids;
  for (VertexId x = 0; x < roadmap.vertex_count(); ++x) {
    if (x % 256 == 0 && keep_going && !keep_going()) {
      throw AdditionStopped("adding the task's POIs was stopped before it changed the roadmap", false);
    }
    const Vec3& q = roadmap.position(x);
    widened.visibility().pois_in_range(q, in_range);
    ids.clear();
    for (const PoiId id : in_range) {
      if (id >= first && widened.visibility().line_of_sight(q, id)) ids.push_back(id - first);
    }
    fresh.append(ids);
  }
  return fresh;
}

void see_new_pois(Roadmap& roadmap, const Scene& widened, PoiId first) {
  if (roadmap.poi_count() < widened.pois().size()) roadmap.widen_pois(widened.pois().size());
  const PoiSetTable fresh = new_poi_visibility(widened, roadmap, first);
  std::vector<PoiId> ids;
  for (VertexId x = 0; x < fresh.rows(); ++x) {
    ids = fresh.ids(x);
    for (PoiId& id : ids) id += first;
    roadmap.add_visible(x, ids);
  }
}

}  // namespace ispars
