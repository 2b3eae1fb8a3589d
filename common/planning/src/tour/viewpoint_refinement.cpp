#include "ispars/planning/tour/viewpoint_refinement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

constexpr double kGain = 1e-9;          // a change must shorten the path by more than this
constexpr std::size_t kChordSteps = 4;  // the first draws of a stop: toward its neighbours' chord

// The path's stops with the targets each sees (indices into `targets`), and how many stops see
// each target.
class RefinedPath {
 public:
  RefinedPath(const Scene& scene, std::span<const PoiId> targets, std::vector<Vec3>& stops)
      : scene_(scene), targets_(targets), stops_(stops), count_(targets.size(), 0) {
    for (const Vec3& q : stops_) sees_.push_back(seen_targets(q));
    for (std::size_t i = 0; i + 1 < stops_.size(); ++i) add(sees_[i]);
    for (std::size_t t = 0; t < count_.size(); ++t) {
      if (count_[t] == 0) {
        throw std::invalid_argument(fmt::format("refine_viewpoints: target POI {} is seen by no stop", targets_[t]));
      }
    }
  }

  // Moves or drops stop i (never the root at 0 and at the end) when that shortens the path.
  void improve_stop(std::size_t i, const RefineOptions& o, scene_files::Rng& rng, RefineResult& r) {
    const Vec3 a = stops_[i - 1], s = stops_[i], b = stops_[i + 1];
    std::vector<std::uint32_t> only;  // the targets no other stop sees
    for (const auto t : sees_[i]) {
      if (count_[t] == 1) only.push_back(t);
    }
    if (only.empty() && joinable(a, b, r)) {
      remove(sees_[i]);
      stops_.erase(stops_.begin() + static_cast<std::ptrdiff_t>(i));
      sees_.erase(sees_.begin() + static_cast<std::ptrdiff_t>(i));
      ++r.dropped;
      return;
    }
    double best_cost = (s - a).norm() + (b - s).norm();
    if (best_cost - (b - a).norm() <= kGain) return;  // already straight
    std::optional<Vec3> best;
    for (std::size_t k = 0; k < o.draws; ++k) {
      const Vec3 q = candidate(a, b, best ? *best : s, best_cost, k, rng);
      const double cost = (q - a).norm() + (b - q).norm();
      if (cost >= best_cost - kGain || !scene_.config().bounds.contains(q) || !scene_.point_valid(q)) continue;
      if (!sees_all(q, only, r) || !joinable(a, q, r) || !joinable(q, b, r)) continue;
      best = q;
      best_cost = cost;
    }
    if (!best) return;
    std::vector<std::uint32_t> now = seen_targets(*best);
    ++r.visibility_queries;
    if (!std::includes(now.begin(), now.end(), only.begin(), only.end())) return;  // at the range's very edge
    remove(sees_[i]);
    add(now);
    stops_[i] = *best;
    sees_[i] = std::move(now);
    ++r.moved;
  }

  // 2-opt over the stops: reverses stops i+1 .. j when the two new segments are shorter and valid.
  void two_opt(RefineResult& r) {
    const std::size_t n = stops_.size();
    for (std::size_t i = 0; i + 3 < n; ++i) {
      for (std::size_t j = i + 2; j + 1 < n; ++j) {
        const double before = (stops_[i + 1] - stops_[i]).norm() + (stops_[j + 1] - stops_[j]).norm();
        const double after = (stops_[j] - stops_[i]).norm() + (stops_[j + 1] - stops_[i + 1]).norm();
        if (after >= before - kGain) continue;
        if (!joinable(stops_[i], stops_[j], r) || !joinable(stops_[i + 1], stops_[j + 1], r)) continue;
        std::reverse(stops_.begin() + static_cast<std::ptrdiff_t>(i + 1),
                     stops_.begin() + static_cast<std::ptrdiff_t>(j + 1));
        std::reverse(sees_.begin() + static_cast<std::ptrdiff_t>(i + 1),
                     sees_.begin() + static_cast<std::ptrdiff_t>(j + 1));
        ++r.reversed;
      }
    }
  }

  [[nodiscard]] std::size_t size() const { return stops_.size(); }

 private:
  std::vector<std::uint32_t> seen_targets(const Vec3& q) const {
    std::vector<std::uint32_t> local;
    for (const PoiId p : scene_.visibility().visible_pois(q)) {
      const auto it = std::lower_bound(targets_.begin(), targets_.end(), p);
      if (it != targets_.end() && *it == p) local.push_back(static_cast<std::uint32_t>(it - targets_.begin()));
    }
    return local;
  }
  bool sees_all(const Vec3& q, const std::vector<std::uint32_t>& only, RefineResult& r) const {
    const VisibilityOracle& vis = scene_.visibility();
    for (const auto t : only) {
      const PoiId p = targets_[t];
      if ((vis.pois()[p] - q).norm() > vis.sensor_range()) return false;
    }
    ++r.visibility_queries;
    return std::all_of(only.begin(), only.end(), [&](std::uint32_t t) { return vis.line_of_sight(q, targets_[t]); });
  }
  bool joinable(const Vec3& a, const Vec3& b, RefineResult& r) const {
    if (a == b) return true;
    ++r.segments_checked;
    return scene_.segment_valid(a, b);
  }
  // Draw k of a stop at `at` between a and b, shorter than c: first straight toward the chord a-b
  // (all the way, then half, a quarter, an eighth), then alternately a point near `at` (in a ball
  // of half, a quarter, ... of the sensor's range) and one anywhere in the spheroid that holds
  // every shorter stop. Near draws find the small regions a stop's targets are seen from; far
  // draws, the other regions.
  Vec3 candidate(const Vec3& a, const Vec3& b, const Vec3& at, double c, std::size_t k, scene_files::Rng& rng) const {
    if (k < kChordSteps) {
      const Vec3 ab = b - a;
      const double t = ab.squaredNorm() > 0.0 ? std::clamp((at - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      return at + std::ldexp(1.0, -static_cast<int>(k)) * (a + t * ab - at);
    }
    if (k % 2 == 0) return in_spheroid(a, b, c, rng);
    const double radius = scene_.visibility().sensor_range() * std::ldexp(1.0, -1 - static_cast<int>((k / 2) % 4));
    for (;;) {
      const double x = rng.uniform(-1.0, 1.0), y = rng.uniform(-1.0, 1.0), z = rng.uniform(-1.0, 1.0);
      if (x * x + y * y + z * z <= 1.0) return at + radius * Vec3(x, y, z);
    }
  }
  // Uniform in the prolate spheroid {q : |q - a| + |q - b| < c} (Gammell et al.'s informed set).
  static Vec3 in_spheroid(const Vec3& a, const Vec3& b, double c, scene_files::Rng& rng) {
    const double d = (b - a).norm();
    const Vec3 axis = d > 0.0 ? Vec3((b - a) / d) : Vec3::UnitZ();
    const Vec3 u = axis.unitOrthogonal();
    const Vec3 v = axis.cross(u);
    const double major = c / 2.0, minor = std::sqrt(std::max(0.0, c * c - d * d)) / 2.0;
    for (;;) {
      const double x = rng.uniform(-1.0, 1.0), y = rng.uniform(-1.0, 1.0), z = rng.uniform(-1.0, 1.0);
      if (x * x + y * y + z * z > 1.0) continue;
      return (a + b) / 2.0 + major * x * axis + minor * y * u + minor * z * v;
    }
  }
  void add(const std::vector<std::uint32_t>& seen) {
    for (const auto t : seen) ++count_[t];
  }
  void remove(const std::vector<std::uint32_t>& seen) {
    for (const auto t : seen) --count_[t];
  }

  const Scene& scene_;
  std::span<const PoiId> targets_;
  std::vector<Vec3>& stops_;
  std::vector<std::vector<std::uint32_t>> sees_;
  std::vector<std::size_t> count_;  // stops seeing each target (the closing stop, the root again, not counted)
};

}  // namespace

double path_length(std::span<const Vec3> stops) {
  double length = 0.0;
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) length += (stops[i + 1] - stops[i]).norm();
  return length;
}

RefineResult refine_viewpoints(const Scene& scene, std::span<const PoiId> targets, std::vector<Vec3>& stops,
                               const RefineOptions& o) {
  if (stops.size() < 2 || stops.front() != stops.back()) {
    throw std::invalid_argument("refine_viewpoints: the path must be closed (front == back)");
  }
  RefineResult r;
  RefinedPath path(scene, targets, stops);
  scene_files::Rng rng(o.seed);
  const auto start = std::chrono::steady_clock::now();
  const auto out_of_time = [&] {
    return (o.stop != nullptr && o.stop->load()) ||
           (o.budget_seconds > 0.0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= o.budget_seconds);
  };
  for (std::size_t pass = 0; pass < o.passes; ++pass) {
    const double before = path_length(stops);
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      if (out_of_time()) {
        r.stopped = true;
        return r;
      }
      const std::size_t size = path.size();
      path.improve_stop(i, o, rng, r);
      if (path.size() < size) --i;  // dropped: the next stop is at i now
    }
    path.two_opt(r);
    ++r.passes;
    if (path_length(stops) >= before - kGain) break;
  }
  return r;
}

}  // namespace ispars::planning
