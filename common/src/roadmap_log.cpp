#include "ispars/roadmap_log.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace ispars {
namespace {

static_assert(std::endian::native == std::endian::little, "the log format is little-endian");

constexpr std::array<char, 8> kMagic{'I', 'S', 'P', 'L', 'O', 'G', '0', '1'};

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Reads fixed-size values from a payload, failing on any overrun.
class Reader {
 public:
  explicit Reader(const std::string& data) : data_(data) {}
  template <class T>
  T get() {
    if (data_.size() - at_ < sizeof(T)) throw std::runtime_error("batch payload is truncated");
    T value;
    std::memcpy(&value, data_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  [[nodiscard]] bool done() const { return at_ == data_.size(); }

 private:
  const std::string& data_;
  std::size_t at_ = 0;
};

std::string system_error(const std::string& what, const std::filesystem::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
}

void write_all(int fd, const char* data, std::size_t size, const std::filesystem::path& path) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(system_error("cannot write", path));
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

void fsync_directory_of(const std::filesystem::path& path) {
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

std::uint32_t crc32(const void* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ bytes[i]) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

RoadmapBatch batch_since(const Roadmap& roadmap, std::uint64_t version) {
  RoadmapBatch batch;
  batch.from_version = std::min(version, roadmap.version());
  batch.to_version = roadmap.version();
  for (const RoadmapChange& change : roadmap.changes_since(version)) {
    batch.changes.push_back(change);
    if (change.kind == RoadmapChange::Kind::vertex) {
      batch.positions.push_back(roadmap.position(change.index));
      batch.visible.push_back(roadmap.visibility_table().ids(change.index));
    } else {
      batch.edges.push_back(roadmap.edges()[change.index]);
    }
  }
  return batch;
}

void apply_batch(Roadmap& replica, const RoadmapBatch& batch) {
  if (replica.version() != batch.from_version) {
    throw std::runtime_error("batch starts at version " + std::to_string(batch.from_version) +
                             " but the replica is at " + std::to_string(replica.version()));
  }
  std::size_t vertex = 0;
  std::size_t edge = 0;
  for (const RoadmapChange& change : batch.changes) {
    if (change.kind == RoadmapChange::Kind::vertex) {
      if (vertex >= batch.positions.size() || change.index != replica.vertex_count()) {
        throw std::runtime_error("batch vertex out of order");
      }
      replica.add_vertex(batch.positions[vertex], batch.visible[vertex]);
      ++vertex;
    } else {
      if (edge >= batch.edges.size() || change.index != replica.edge_count()) {
        throw std::runtime_error("batch edge out of order");
      }
      const RoadmapEdge& e = batch.edges[edge++];
      if (e.u >= replica.vertex_count() || e.v >= replica.vertex_count() || !replica.add_edge(e.u, e.v) ||
          replica.edges().back().cost != e.cost) {
        throw std::runtime_error("batch edge does not fit the replica");
      }
    }
  }
  if (replica.version() != batch.to_version) throw std::runtime_error("batch does not end at its version");
}

std::string encode_batch(const RoadmapBatch& batch) {
  std::string out;
  put(out, batch.from_version);
  put(out, batch.to_version);
  put(out, static_cast<std::uint32_t>(batch.changes.size()));
  for (const RoadmapChange& c : batch.changes) {
    put(out, static_cast<std::uint8_t>(c.kind));
    put(out, c.index);
  }
  put(out, static_cast<std::uint32_t>(batch.positions.size()));
  for (std::size_t i = 0; i < batch.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) put(out, batch.positions[i][k]);
    put(out, static_cast<std::uint32_t>(batch.visible[i].size()));
    for (const PoiId id : batch.visible[i]) put(out, id);
  }
  put(out, static_cast<std::uint32_t>(batch.edges.size()));
  for (const RoadmapEdge& e : batch.edges) {
    put(out, e.u);
    put(out, e.v);
    put(out, e.cost);
  }
  return out;
}

RoadmapBatch decode_batch(const std::string& payload) {
  Reader in(payload);
  RoadmapBatch batch;
  batch.from_version = in.get<std::uint64_t>();
  batch.to_version = in.get<std::uint64_t>();
  const auto changes = in.get<std::uint32_t>();
  if (changes > payload.size()) throw std::runtime_error("batch change count is impossible");
  for (std::uint32_t i = 0; i < changes; ++i) {
    const auto kind = in.get<std::uint8_t>();
    if (kind > 1) throw std::runtime_error("batch change has an unknown kind");
    batch.changes.push_back({static_cast<RoadmapChange::Kind>(kind), in.get<std::uint32_t>()});
  }
  const auto vertices = in.get<std::uint32_t>();
  if (vertices > payload.size()) throw std::runtime_error("batch vertex count is impossible");
  for (std::uint32_t i = 0; i < vertices; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = in.get<double>();
    batch.positions.push_back(p);
    const auto count = in.get<std::uint32_t>();
    if (count > payload.size()) throw std::runtime_error("batch POI count is impossible");
    std::vector<PoiId> ids(count);
    for (auto& id : ids) id = in.get<PoiId>();
    batch.visible.push_back(std::move(ids));
  }
  const auto edges = in.get<std::uint32_t>();
  if (edges > payload.size()) throw std::runtime_error("batch edge count is impossible");
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

LogReplay read_roadmap_log(const std::filesystem::path& path) {
  LogReplay replay;
  std::ifstream file(path, std::ios::binary);
  if (!file) return replay;  // no log yet
  const std::string data((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (data.empty()) return replay;
  if (data.size() < kMagic.size() || std::memcmp(data.data(), kMagic.data(), kMagic.size()) != 0) {
    if (data.size() < kMagic.size() && std::memcmp(data.data(), kMagic.data(), data.size()) == 0) {
      replay.torn_tail = true;  // a crash while writing the magic itself
      replay.tail_problem = "incomplete file header";
      return replay;
    }
    throw std::runtime_error(path.string() + " is not a roadmap log (bad magic)");
  }
  std::size_t at = kMagic.size();
  replay.valid_bytes = at;
  std::uint64_t version = 0;
  bool first = true;
  while (at < data.size()) {
    const std::size_t left = data.size() - at;
    if (left < 8) {
      replay.tail_problem = "incomplete record header";
      break;
    }
    std::uint32_t length = 0;
    std::uint32_t checksum = 0;
    std::memcpy(&length, data.data() + at, 4);
    std::memcpy(&checksum, data.data() + at + 4, 4);
    if (length > left - 8) {
      replay.tail_problem = "record runs past the end of the file";
      break;
    }
    const std::string payload = data.substr(at + 8, length);
    if (crc32(payload.data(), payload.size()) != checksum) {
      replay.tail_problem = "record checksum mismatch";
      break;
    }
    RoadmapBatch batch;
    try {
      batch = decode_batch(payload);
    } catch (const std::runtime_error& e) {
      replay.tail_problem = std::string("undecodable record: ") + e.what();
      break;
    }
    if (!first && batch.from_version != version) {
      replay.tail_problem = "record out of sequence";
      break;
    }
    first = false;
    version = batch.to_version;
    replay.batches.push_back(std::move(batch));
    at += 8 + length;
    replay.valid_bytes = at;
  }
  replay.torn_tail = replay.valid_bytes < data.size();
  return replay;
}

RoadmapLogWriter::RoadmapLogWriter(const std::filesystem::path& path) : path_(path) {
  const LogReplay existing = read_roadmap_log(path);
  torn_tail_ = existing.torn_tail;
  empty_ = existing.batches.empty();
  version_ = empty_ ? 0 : existing.batches.back().to_version;
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(system_error("cannot open", path));
  if (existing.valid_bytes < kMagic.size()) {
    // New (or torn inside its header): start over with just the magic.
    if (::ftruncate(fd_, 0) != 0) throw std::runtime_error(system_error("cannot truncate", path));
    write_all(fd_, kMagic.data(), kMagic.size(), path);
  } else if (existing.torn_tail) {
    if (::ftruncate(fd_, static_cast<off_t>(existing.valid_bytes)) != 0) {
      throw std::runtime_error(system_error("cannot cut the torn tail of", path));
    }
  }
  if (::lseek(fd_, 0, SEEK_END) < 0) throw std::runtime_error(system_error("cannot seek", path));
  if (::fsync(fd_) != 0) throw std::runtime_error(system_error("cannot fsync", path));
  fsync_directory_of(path);
}

RoadmapLogWriter::~RoadmapLogWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void RoadmapLogWriter::append(const RoadmapBatch& batch) {
  if (!empty_ && batch.from_version != version_) {
    throw std::invalid_argument("batch from version " + std::to_string(batch.from_version) +
                                " does not continue the log at version " + std::to_string(version_));
  }
  const std::string payload = encode_batch(batch);
  std::string record;
  put(record, static_cast<std::uint32_t>(payload.size()));
  put(record, crc32(payload.data(), payload.size()));
  record += payload;
  write_all(fd_, record.data(), record.size(), path_);
  if (::fsync(fd_) != 0) throw std::runtime_error(system_error("cannot fsync", path_));
  empty_ = false;
  version_ = batch.to_version;
}

}  // namespace ispars
