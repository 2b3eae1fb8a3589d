#include "ispars/planning/geometry/visibility.hpp"

#include <algorithm>
#include <utility>

#include <nanoflann.hpp>

namespace ispars::planning {

// nanoflann's view of the POI positions.
struct PoiCloud {
  const std::vector<Vec3>* points;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)[i][static_cast<Eigen::Index>(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box& /*box*/) const {
    return false;
  }
};

struct VisibilityOracle::KdTree {
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PoiCloud>, PoiCloud, 3, PoiId>;
  PoiCloud cloud;
  Index index;
  explicit KdTree(const std::vector<Vec3>& points)
      : cloud{&points}, index(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

VisibilityOracle::VisibilityOracle(std::shared_ptr<const EmbreeScene> scene, std::vector<Vec3> pois,
                                   double sensor_range)
    : scene_(std::move(scene)), pois_(std::move(pois)), range_(sensor_range), tree_(std::make_unique<KdTree>(pois_)) {}

VisibilityOracle::~VisibilityOracle() = default;

void VisibilityOracle::pois_in_range(const Vec3& q, std::vector<PoiId>& out) const {
  out.clear();
  if (pois_.empty()) return;
  thread_local std::vector<std::pair<PoiId, double>> found;
  found.clear();
  // Search a hair wider than the range, then decide membership exactly: |p - q| <= range.
  const double search = range_ * range_ * (1.0 + 1e-9) + 1e-12;
  tree_->index.radiusSearch(q.data(), search, found, nanoflann::SearchParams(32, 0.0f, false));
  const double range2 = range_ * range_;
  for (const auto& [id, d2] : found) {
    if ((pois_[id] - q).squaredNorm() <= range2) out.push_back(id);
  }
  std::sort(out.begin(), out.end());
}

namespace {

// An intersect context that carries the sight line in double precision. Embree passes the
// context to the filter, which confirms every candidate hit with the exact crossing: Embree's
// single-precision t can be millimetres off at grazing incidence (seen on the water tower,
// where the POI's own triangle was "hit" 3.7 mm before the POI), so it only proposes.
struct SightContext {
  RTCIntersectContext base;  // must stay first: Embree sees only this part
  const EmbreeScene* scene;
  Vec3 origin;
  Vec3 direction;
  double s_end;
};

void confirm_hit_exactly(const RTCFilterFunctionNArguments* args) {
  const auto* sight = reinterpret_cast<const SightContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const auto crossing = ray_plane_crossing(sight->origin, sight->direction, sight->scene->triangle(prim));
    const bool hit = crossing && crossing->s >= 0.0 && crossing->s <= sight->s_end && crossing->margin >= 0.0;
    if (!hit) args->valid[i] = 0;
  }
}

// Casts q -> p, stopping kPoiStandoff short of p; true when nothing blocks it.
bool sight_line_clear(const EmbreeScene& scene, const Vec3& q, const Vec3& p) {
  const Vec3 d = p - q;
  const double length = d.norm();
  if (length <= kPoiStandoff) return true;
  SightContext context;
  rtcInitIntersectContext(&context.base);
  context.base.filter = confirm_hit_exactly;
  context.scene = &scene;
  context.origin = q;
  context.direction = d;
  context.s_end = 1.0 - kPoiStandoff / length;

  RTCRay ray;
  ray.org_x = static_cast<float>(q.x());
  ray.org_y = static_cast<float>(q.y());
  ray.org_z = static_cast<float>(q.z());
  ray.tnear = 0.0f;
  ray.dir_x = static_cast<float>(d.x());
  ray.dir_y = static_cast<float>(d.y());
  ray.dir_z = static_cast<float>(d.z());
  ray.time = 0.0f;
  // The direction is unnormalised, so t = 1 is the POI. Embree's float t may be a little off, so
  // let it look slightly past the exact end; the filter enforces the exact span.
  ray.tfar = static_cast<float>(std::min(1.0, context.s_end + 1e-4));
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  rtcOccluded1(scene.handle(), &context.base, &ray);
  return ray.tfar >= 0.0f;  // Embree sets tfar to -inf on a confirmed hit
}

}  // namespace

bool VisibilityOracle::line_of_sight(const Vec3& q, PoiId id) const {
  counters_.add_rays(1);
  return sight_line_clear(*scene_, q, pois_[id]);
}

void VisibilityOracle::visible_pois(const Vec3& q, std::vector<PoiId>& out) const {
  thread_local std::vector<PoiId> candidates;
  pois_in_range(q, candidates);
  out.clear();
  counters_.add_rays(candidates.size());
  for (const PoiId id : candidates) {
    if (sight_line_clear(*scene_, q, pois_[id])) out.push_back(id);
  }
}

std::vector<PoiId> VisibilityOracle::visible_pois(const Vec3& q) const {
  std::vector<PoiId> out;
  visible_pois(q, out);
  return out;
}

}  // namespace ispars::planning
