#include "ispars/builders/route_stretch.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ispars/search/graph_search.hpp"

namespace ispars {
namespace {

StretchStats summarize(std::vector<double>& ratios, std::size_t disconnected, double t) {
  StretchStats s;
  s.pairs = ratios.size();
  s.disconnected = disconnected;
  if (ratios.empty()) return s;
  std::sort(ratios.begin(), ratios.end());
  const auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(ratios.size()))) - 1;
    return ratios[std::min(ratios.size() - 1, i)];
  };
  s.median = at(0.5);
  s.p95 = at(0.95);
  s.max = ratios.back();
  const auto over = std::count_if(ratios.begin(), ratios.end(), [t](double r) { return r > t; });
  s.share_over_t = static_cast<double>(over) / static_cast<double>(ratios.size());
  return s;
}

struct Samples {
  std::vector<double> dense, segment;
  std::size_t dense_disconnected = 0, segment_disconnected = 0;
};

}  // namespace

RouteStretchReport measure_route_stretch(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                         std::span<const VertexId> dense_ids, const RouteStretchOptions& options) {
  RouteStretchReport report;
  std::vector<VertexId> viewpoints;
  for (VertexId s = 0; s < sparse.vertex_count(); ++s) {
    if (count(sparse.visible(s)) > 0) viewpoints.push_back(s);
  }
  report.viewpoints = viewpoints.size();
  const std::size_t step =
      options.max_sources == 0 ? 1 : std::max<std::size_t>(1, (viewpoints.size() + options.max_sources - 1) / options.max_sources);
  std::vector<char> is_source(sparse.vertex_count(), 0);
  for (std::size_t i = 0; i < viewpoints.size(); i += step) is_source[viewpoints[i]] = 1;

  constexpr std::size_t kBins = 4;
  std::array<Samples, kBins> samples;
  Samples within;
  const double unit = options.big_delta;
  for (const VertexId a : viewpoints) {
    if (!is_source[a]) continue;
    ++report.sources;
    const std::vector<double> ds = shortest_distances(sparse, a);
    const std::vector<double> dd = shortest_distances(dense, dense_ids[a]);
    for (const VertexId b : viewpoints) {
      if (b == a || (is_source[b] && b < a)) continue;  // each pair once
      const double route_dense = dd[dense_ids[b]];
      if (!std::isfinite(route_dense)) continue;  // not joined in G_d either: nothing to compare
      const double length = (sparse.position(a) - sparse.position(b)).norm();
      const auto bin = std::min<std::size_t>(kBins - 1, static_cast<std::size_t>(length / unit));
      const bool joined = std::isfinite(ds[b]);
      for (Samples* s : {&samples[bin], bin < 3 ? &within : nullptr}) {
        if (s == nullptr) continue;
        s->dense.push_back(joined ? ds[b] / route_dense : INFINITY);
        s->dense_disconnected += !joined;
      }
      if (bin < 3 && scene.segment_valid(sparse.position(a), sparse.position(b))) {
        for (Samples* s : {&samples[bin], &within}) {
          s->segment.push_back(joined ? ds[b] / length : INFINITY);
          s->segment_disconnected += !joined;
        }
      }
    }
  }
  for (std::size_t i = 0; i < kBins; ++i) {
    StretchBin& bin = report.bins[i];
    bin.from = static_cast<double>(i);
    bin.to = i + 1 < kBins ? static_cast<double>(i + 1) : INFINITY;
    bin.vs_dense = summarize(samples[i].dense, samples[i].dense_disconnected, options.stretch);
    bin.vs_segment = summarize(samples[i].segment, samples[i].segment_disconnected, options.stretch);
  }
  report.within_3_delta.from = 0.0;
  report.within_3_delta.to = 3.0;
  report.within_3_delta.vs_dense = summarize(within.dense, within.dense_disconnected, options.stretch);
  report.within_3_delta.vs_segment = summarize(within.segment, within.segment_disconnected, options.stretch);
  return report;
}

}  // namespace ispars
