#include "ispars/planning/builders/route_stretch.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ispars/planning/search/graph_search.hpp"

namespace ispars::planning {
namespace {

// The ratios d_s / reference and the excesses (d_s - t reference) / Delta of one bin's pairs.
struct Samples {
  std::vector<double> ratios, excesses;
  std::size_t disconnected = 0;

  void add(double route, double reference, double t, double unit) {
    const bool joined = std::isfinite(route);
    ratios.push_back(joined ? route / reference : INFINITY);
    excesses.push_back(joined ? (route - t * reference) / unit : INFINITY);
    disconnected += !joined;
  }
};

StretchStats summarize(Samples& s, double t) {
  StretchStats out;
  std::vector<double>& ratios = s.ratios;
  out.pairs = ratios.size();
  out.disconnected = s.disconnected;
  if (ratios.empty()) return out;
  std::sort(ratios.begin(), ratios.end());
  const auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(ratios.size()))) - 1;
    return ratios[std::min(ratios.size() - 1, i)];
  };
  out.median = at(0.5);
  out.p95 = at(0.95);
  out.p99 = at(0.99);
  out.max = ratios.back();
  const auto over = std::count_if(ratios.begin(), ratios.end(), [t](double r) { return r > t; });
  out.share_over_t = static_cast<double>(over) / static_cast<double>(ratios.size());
  out.max_excess = *std::max_element(s.excesses.begin(), s.excesses.end());
  return out;
}

// Each pair lands in its own bin and in the aggregates it belongs to.
struct BinSamples {
  std::vector<Samples> dense, segment;  // per bin
  Samples dense_within, segment_within, dense_beyond, segment_beyond, dense_all, segment_all;
};

StretchBin bin_of(double from, double to, Samples& dense, Samples& segment, double t) {
  StretchBin b;
  b.from = from;
  b.to = to;
  b.vs_dense = summarize(dense, t);
  b.vs_segment = summarize(segment, t);
  return b;
}

std::vector<VertexId> viewpoints_of(const Roadmap& sparse) {
  std::vector<VertexId> out;
  for (VertexId s = 0; s < sparse.vertex_count(); ++s) {
    if (count(sparse.visible(s)) > 0) out.push_back(s);
  }
  return out;
}

}  // namespace

RouteStretchReport measure_route_stretch(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                         std::span<const VertexId> dense_ids, const RouteStretchOptions& options) {
  RouteStretchReport report;
  const std::vector<VertexId> viewpoints = viewpoints_of(sparse);
  report.viewpoints = viewpoints.size();
  const std::size_t step =
      options.max_sources == 0
          ? 1
          : std::max<std::size_t>(1, (viewpoints.size() + options.max_sources - 1) / options.max_sources);
  std::vector<char> is_source(sparse.vertex_count(), 0);
  for (std::size_t i = 0; i < viewpoints.size(); i += step) is_source[viewpoints[i]] = 1;

  const std::size_t bins = options.bins + 1;
  BinSamples s;
  s.dense.resize(bins);
  s.segment.resize(bins);
  const double unit = options.big_delta;
  const double t = options.stretch;
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
      const double in_delta = length / unit;
      const auto bin = std::min<std::size_t>(bins - 1, static_cast<std::size_t>(in_delta));
      const bool within = in_delta < 3.0;
      for (Samples* x : {&s.dense[bin], within ? &s.dense_within : &s.dense_beyond, &s.dense_all}) {
        x->add(ds[b], route_dense, t, unit);
      }
      if (in_delta < static_cast<double>(options.segment_bins) &&
          scene.segment_valid(sparse.position(a), sparse.position(b))) {
        for (Samples* x : {&s.segment[bin], within ? &s.segment_within : &s.segment_beyond, &s.segment_all}) {
          x->add(ds[b], length, t, unit);
        }
      }
    }
  }
  for (std::size_t i = 0; i < bins; ++i) {
    const double to = i + 1 < bins ? static_cast<double>(i + 1) : INFINITY;
    report.bins.push_back(bin_of(static_cast<double>(i), to, s.dense[i], s.segment[i], t));
  }
  report.within_3_delta = bin_of(0.0, 3.0, s.dense_within, s.segment_within, t);
  report.beyond_3_delta = bin_of(3.0, INFINITY, s.dense_beyond, s.segment_beyond, t);
  report.all = bin_of(0.0, INFINITY, s.dense_all, s.segment_all, t);
  return report;
}

}  // namespace ispars::planning
