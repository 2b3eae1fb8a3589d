#include "ispars/roadmap/roadmap_batch.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "ispars/roadmap/record_file.hpp"

namespace ispars {

RoadmapBatch batch_since(const Roadmap& roadmap, std::uint64_t version) {
  return batch_range(roadmap, version, roadmap.version());
}

RoadmapBatch batch_range(const Roadmap& roadmap, std::uint64_t from, std::uint64_t to) {
  RoadmapBatch batch;
  batch.to_version = std::min(to, roadmap.version());
  batch.from_version = std::min(from, batch.to_version);
  roadmap.for_each_change(batch.from_version, batch.to_version, [&](const RoadmapChange& change) {
    batch.changes.push_back(change);
    if (change.kind == RoadmapChange::Kind::vertex) {
      batch.positions.push_back(roadmap.position(change.index));
      batch.visible.push_back(roadmap.visibility_table().ids(change.index));
    } else {
      batch.edges.push_back(roadmap.edge(change.index));
    }
  });
  return batch;
}

namespace {

// FNV-1a over values laid out as put_bytes lays them out.
struct Fnv1a {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  template <class T>
  void add(const T& value) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      hash ^= bytes[i];
      hash *= 0x100000001b3ull;
    }
  }
};

}  // namespace

std::uint64_t roadmap_digest(const Roadmap& roadmap) {
  // The digest of encode_batch(batch_since(roadmap, 0)), streamed: a dense roadmap of tens of
  // millions of edges is never copied into a batch or a string to be hashed.
  Fnv1a h;
  h.add(std::uint64_t{0});
  h.add(roadmap.version());
  h.add(static_cast<std::uint32_t>(roadmap.version()));
  roadmap.for_each_change(0, roadmap.version(), [&](const RoadmapChange& c) {
    h.add(static_cast<std::uint8_t>(c.kind));
    h.add(c.index);
  });
  h.add(static_cast<std::uint32_t>(roadmap.vertex_count()));
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    for (int k = 0; k < 3; ++k) h.add(roadmap.position(v)[k]);
    const std::vector<PoiId> ids = roadmap.visibility_table().ids(v);
    h.add(static_cast<std::uint32_t>(ids.size()));
    for (const PoiId id : ids) h.add(id);
  }
  h.add(static_cast<std::uint32_t>(roadmap.edge_count()));
  for (const RoadmapEdge& e : roadmap.edges()) {
    h.add(e.u);
    h.add(e.v);
    h.add(e.cost);
  }
  return h.hash;
}

// Everything apply_batch needs to hold, checked before the replica is touched: a batch from the
// network or a damaged file is refused whole, never half-applied.
void check_batch(const Roadmap& replica, const RoadmapBatch& batch) {
  if (replica.version() != batch.from_version) {
    throw std::runtime_error("batch starts at version " + std::to_string(batch.from_version) +
                             " but the replica is at " + std::to_string(replica.version()));
  }
  if (batch.to_version < batch.from_version || batch.to_version - batch.from_version != batch.changes.size()) {
    throw std::runtime_error("batch does not end at its version");
  }
  if (batch.visible.size() != batch.positions.size())
    throw std::runtime_error("batch POI lists do not match its vertices");
  const std::size_t pois = replica.visibility_table().poi_count();
  std::size_t vertex = 0;
  std::size_t edge = 0;
  std::vector<std::uint64_t> added;  // u * 2^32 + v with u < v, for the duplicate check
  added.reserve(batch.edges.size());
  const auto position = [&](VertexId v) -> const Vec3& {
    return v < replica.vertex_count() ? replica.position(v) : batch.positions[v - replica.vertex_count()];
  };
  for (const RoadmapChange& change : batch.changes) {
    if (change.kind == RoadmapChange::Kind::vertex) {
      if (vertex >= batch.positions.size() || change.index != replica.vertex_count() + vertex) {
        throw std::runtime_error("batch vertex out of order");
      }
      if (!batch.positions[vertex].allFinite()) throw std::runtime_error("batch vertex position is not finite");
      for (const PoiId id : batch.visible[vertex]) {
        if (id >= pois)
          throw std::runtime_error("batch vertex sees POI " + std::to_string(id) + " of " + std::to_string(pois));
      }
      ++vertex;
    } else {
      if (edge >= batch.edges.size() || change.index != replica.edge_count() + edge) {
        throw std::runtime_error("batch edge out of order");
      }
      const RoadmapEdge& e = batch.edges[edge++];
      const std::size_t known = replica.vertex_count() + vertex;
      if (e.u >= known || e.v >= known || e.u == e.v) throw std::runtime_error("batch edge does not fit the replica");
      const auto [lo, hi] = std::minmax(e.u, e.v);
      added.push_back((std::uint64_t{lo} << 32) | hi);
      if (e.u < replica.vertex_count() && e.v < replica.vertex_count() && replica.has_edge(e.u, e.v)) {
        throw std::runtime_error("batch edge is a duplicate");
      }
      if ((position(e.u) - position(e.v)).norm() != e.cost)
        throw std::runtime_error("batch edge cost is not its length");
    }
  }
  if (vertex != batch.positions.size() || edge != batch.edges.size()) {
    throw std::runtime_error("batch holds vertices or edges its change list does not");
  }
  std::sort(added.begin(), added.end());
  if (std::adjacent_find(added.begin(), added.end()) != added.end())
    throw std::runtime_error("batch edge is a duplicate");
}

void apply_batch(Roadmap& replica, const RoadmapBatch& batch) {
  check_batch(replica, batch);
  apply_checked_batch(replica, batch);
}

void apply_checked_batch(Roadmap& replica, const RoadmapBatch& batch) {
  // A batch large beside the replica (a snapshot, a long journal commit) grows each neighbour
  // list once, to its size after the batch. Counting costs a pass over the replica's vertices,
  // which a small streamed batch would not repay: its lists grow as they go.
  const std::size_t before = replica.vertex_count();
  std::vector<std::uint32_t> gained;
  if (batch.edges.size() >= before) {
    gained.assign(before + batch.positions.size(), 0);
    for (const RoadmapEdge& e : batch.edges) {
      ++gained[e.u];
      ++gained[e.v];
    }
    for (VertexId v = 0; v < before; ++v) {
      if (gained[v] != 0) replica.reserve_neighbors(v, gained[v]);
    }
  }
  replica.reserve_edges(batch.edges.size());
  std::size_t vertex = 0;
  std::size_t edge = 0;
  for (const RoadmapChange& change : batch.changes) {
    if (change.kind == RoadmapChange::Kind::vertex) {
      const VertexId v = replica.add_vertex(batch.positions[vertex], batch.visible[vertex]);
      if (!gained.empty() && gained[v] != 0) replica.reserve_neighbors(v, gained[v]);
      ++vertex;
    } else {
      const RoadmapEdge& e = batch.edges[edge++];
      replica.add_new_edge(e.u, e.v);
    }
  }
}

// Encoded bytes of a change (kind, index), of a vertex before its POI ids (position, id count)
// and of an edge (ends, cost): the sizes encode_batch writes and decode_batch checks counts by.
constexpr std::size_t kChangeBytes = sizeof(std::uint8_t) + sizeof(std::uint32_t);
constexpr std::size_t kVertexBytes = 3 * sizeof(double) + sizeof(std::uint32_t);
constexpr std::size_t kEdgeBytes = 2 * sizeof(VertexId) + sizeof(double);

std::size_t encoded_batch_size(const RoadmapBatch& batch) {
  std::size_t size = 2 * sizeof(std::uint64_t) + 3 * sizeof(std::uint32_t);
  size += batch.changes.size() * kChangeBytes + batch.positions.size() * kVertexBytes;
  for (const auto& ids : batch.visible) size += ids.size() * sizeof(PoiId);
  return size + batch.edges.size() * kEdgeBytes;
}

void append_encoded_batch(std::string& out, const RoadmapBatch& batch) {
  out.reserve(out.size() + encoded_batch_size(batch));  // one allocation: no doubling, no copy
  put_bytes(out, batch.from_version);
  put_bytes(out, batch.to_version);
  put_bytes(out, static_cast<std::uint32_t>(batch.changes.size()));
  for (const RoadmapChange& c : batch.changes) {
    put_bytes(out, static_cast<std::uint8_t>(c.kind));
    put_bytes(out, c.index);
  }
  put_bytes(out, static_cast<std::uint32_t>(batch.positions.size()));
  for (std::size_t i = 0; i < batch.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) put_bytes(out, batch.positions[i][k]);
    put_bytes(out, static_cast<std::uint32_t>(batch.visible[i].size()));
    for (const PoiId id : batch.visible[i]) put_bytes(out, id);
  }
  put_bytes(out, static_cast<std::uint32_t>(batch.edges.size()));
  for (const RoadmapEdge& e : batch.edges) {
    put_bytes(out, e.u);
    put_bytes(out, e.v);
    put_bytes(out, e.cost);
  }
}

std::optional<std::string> encode_prefix(const Roadmap& roadmap, std::uint64_t to,
                                         const std::function<bool()>& keep_going) {
  constexpr std::uint64_t kSlice = 1 << 16;  // changes per look at keep_going: milliseconds each
  RoadmapBatch whole;
  whole.to_version = std::min(to, roadmap.version());
  whole.changes.reserve(whole.to_version);
  whole.positions.reserve(roadmap.vertex_count());  // at most: the prefix may hold fewer
  whole.visible.reserve(roadmap.vertex_count());
  whole.edges.reserve(roadmap.edge_count());
  for (std::uint64_t at = 0; at < whole.to_version; at += kSlice) {
    if (!keep_going()) return std::nullopt;
    RoadmapBatch part = batch_range(roadmap, at, std::min(at + kSlice, whole.to_version));
    whole.changes.insert(whole.changes.end(), part.changes.begin(), part.changes.end());
    std::move(part.positions.begin(), part.positions.end(), std::back_inserter(whole.positions));
    std::move(part.visible.begin(), part.visible.end(), std::back_inserter(whole.visible));
    whole.edges.insert(whole.edges.end(), part.edges.begin(), part.edges.end());
  }
  if (!keep_going()) return std::nullopt;
  return encode_batch(whole);
}

std::string encode_batch(const RoadmapBatch& batch) {
  std::string out;
  append_encoded_batch(out, batch);
  return out;
}

RoadmapBatch decode_batch(std::string_view payload) {
  ByteReader in(payload);
  RoadmapBatch batch;
  batch.from_version = in.get<std::uint64_t>();
  batch.to_version = in.get<std::uint64_t>();
  const auto changes = in.get<std::uint32_t>();
  if (changes > in.remaining() / kChangeBytes) throw std::runtime_error("batch change count is impossible");
  batch.changes.reserve(changes);
  for (std::uint32_t i = 0; i < changes; ++i) {
    const auto kind = in.get<std::uint8_t>();
    if (kind > 1) throw std::runtime_error("batch change has an unknown kind");
    batch.changes.push_back({static_cast<RoadmapChange::Kind>(kind), in.get<std::uint32_t>()});
  }
  const auto vertices = in.get<std::uint32_t>();
  if (vertices > in.remaining() / kVertexBytes) throw std::runtime_error("batch vertex count is impossible");
  batch.positions.reserve(vertices);
  batch.visible.reserve(vertices);
  for (std::uint32_t i = 0; i < vertices; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = in.get<double>();
    batch.positions.push_back(p);
    const auto count = in.get<std::uint32_t>();
    if (count > in.remaining() / sizeof(PoiId)) throw std::runtime_error("batch POI count is impossible");
    std::vector<PoiId> ids(count);
    for (auto& id : ids) id = in.get<PoiId>();
    batch.visible.push_back(std::move(ids));
  }
  const auto edges = in.get<std::uint32_t>();
  if (edges > in.remaining() / kEdgeBytes) throw std::runtime_error("batch edge count is impossible");
  batch.edges.reserve(edges);
  for (std::uint32_t i = 0; i < edges; ++i) {
    RoadmapEdge e;
    e.u = in.get<VertexId>();
    e.v = in.get<VertexId>();
    e.cost = in.get<double>();
    batch.edges.push_back(e);
  }
  if (!in.done()) throw std::runtime_error("batch payload has trailing bytes");
  return batch;
}

}  // namespace ispars
