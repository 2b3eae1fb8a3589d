#include "ispars/planning/builders/poi_visibility.hpp"

#include <algorithm>
#include <thread>
#include <vector>

namespace ispars::planning {

PoiSetTable new_poi_visibility(const Scene& widened, const Roadmap& roadmap, PoiId first,
                               const std::function<bool()>& keep_going, unsigned threads) {
  PoiSetTable fresh(widened.pois().size() - first);
  const VisibilityOracle& chi = widened.visibility();
  const std::size_t workers = std::max(1U, threads);
  const std::size_t block = 256 * workers;  // 256 vertices a thread between two asks
  std::vector<std::vector<PoiId>> rows(block);
  const auto find = [&](std::size_t begin, std::size_t end, std::size_t from) {
    std::vector<PoiId> in_range;
    for (std::size_t x = begin + from; x < end; x += workers) {
      const Vec3& q = roadmap.position(static_cast<VertexId>(x));
      std::vector<PoiId>& ids = rows[x - begin];
      ids.clear();
      chi.pois_in_range(q, in_range);
      for (const PoiId id : in_range) {
        if (id >= first && chi.line_of_sight(q, id)) ids.push_back(id - first);
      }
    }
  };
  for (std::size_t begin = 0; begin < roadmap.vertex_count(); begin += block) {
    if (keep_going && !keep_going()) {
      throw AdditionStopped("adding the task's POIs was stopped before it changed the roadmap", false);
    }
    const std::size_t end = std::min<std::size_t>(begin + block, roadmap.vertex_count());
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < workers && begin + t < end; ++t) pool.emplace_back(find, begin, end, t);
    find(begin, end, 0);
    for (std::thread& t : pool) t.join();
    for (std::size_t x = begin; x < end; ++x) fresh.append(rows[x - begin]);
  }
  return fresh;
}

void see_new_pois(Roadmap& roadmap, const Scene& widened, PoiId first, unsigned threads) {
  if (roadmap.poi_count() < widened.pois().size()) roadmap.widen_pois(widened.pois().size());
  const PoiSetTable fresh = new_poi_visibility(widened, roadmap, first, {}, threads);
  std::vector<PoiId> ids;
  for (VertexId x = 0; x < fresh.rows(); ++x) {
    ids = fresh.ids(x);
    for (PoiId& id : ids) id += first;
    roadmap.add_visible(x, ids);
  }
}

}  // namespace ispars::planning
