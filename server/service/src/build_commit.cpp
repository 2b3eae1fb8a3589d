// A build commit's bytes in the store's records (roadmap_store.hpp): the samples, the dense
// ids, the two batches, and the tasks the commit adds, if any.

#include <stdexcept>
#include <string>

#include "ispars/service/roadmap_store.hpp"

namespace ispars {
namespace {

std::string_view get_blob(ByteReader& in) {
  const auto size = in.get<std::uint64_t>();
  return in.bytes(size);
}

// A commit's tasks follow its batches, after this marker ("TASKS\0\0\0"): a commit without tasks
// is encoded exactly as before tasks existed, so older stores read as they were.
constexpr std::uint64_t kTasksMarker = 0x0000'0053'4b53'4154ULL;

void append_tasks(std::string& out, const BuildCommit& commit) {
  if (commit.tasks.empty()) return;
  put_bytes(out, kTasksMarker);
  put_bytes(out, commit.task_count);
  put_bytes(out, static_cast<std::uint64_t>(commit.tasks.size()));
  for (const InspectionTask& task : commit.tasks) {
    put_bytes(out, static_cast<std::uint64_t>(task.name.size()));
    out += task.name;
    put_bytes(out, static_cast<std::uint64_t>(task.pois.size()));
    for (const Vec3& p : task.pois) {
      put_bytes(out, p.x());
      put_bytes(out, p.y());
      put_bytes(out, p.z());
    }
  }
}

void read_tasks(ByteReader& in, BuildCommit& commit) {
  if (in.done()) return;
  if (in.get<std::uint64_t>() != kTasksMarker) throw std::runtime_error("commit payload has trailing bytes");
  commit.task_count = in.get<std::uint64_t>();
  const auto count = in.get<std::uint64_t>();
  if (count == 0 || count > commit.task_count || count > kMaxTasks) throw std::runtime_error("commit task count is impossible");
  commit.tasks.resize(count);
  for (InspectionTask& task : commit.tasks) {
    const auto name_size = in.get<std::uint64_t>();
    if (name_size > 64) throw std::runtime_error("commit task name is too long");
    task.name = std::string(in.bytes(name_size));
    const auto pois = in.get<std::uint64_t>();
    if (pois == 0 || pois > kMaxTaskPois) throw std::runtime_error("commit task POI count is impossible");
    task.pois.resize(pois);
    for (Vec3& p : task.pois) {
      const auto x = in.get<double>();
      const auto y = in.get<double>();
      p = Vec3(x, y, in.get<double>());
    }
  }
}

}  // namespace

std::string encode_commit(const BuildCommit& commit) {
  // One allocation of the exact size, each batch encoded in place: a fold of a large roadmap holds
  // its encoding once, not a doubling string beside copies of its parts.
  const std::size_t roadmap_size = encoded_batch_size(commit.roadmap);
  const std::size_t dense_size = encoded_batch_size(commit.dense);
  std::string out;
  out.reserve(4 * sizeof(std::uint64_t) + commit.new_dense_ids.size() * sizeof(VertexId) + roadmap_size + dense_size);
  put_bytes(out, commit.samples);
  put_bytes(out, static_cast<std::uint64_t>(commit.new_dense_ids.size()));
  for (const VertexId id : commit.new_dense_ids) put_bytes(out, id);
  put_bytes(out, static_cast<std::uint64_t>(roadmap_size));
  append_encoded_batch(out, commit.roadmap);
  put_bytes(out, static_cast<std::uint64_t>(dense_size));
  append_encoded_batch(out, commit.dense);
  append_tasks(out, commit);
  return out;
}

BuildCommit decode_commit(const std::string& payload) {
  ByteReader in(payload);
  BuildCommit commit;
  commit.samples = in.get<std::uint64_t>();
  const auto ids = in.get<std::uint64_t>();
  if (ids > in.remaining() / sizeof(VertexId)) throw std::runtime_error("commit id count is impossible");
  commit.new_dense_ids.resize(ids);
  for (auto& id : commit.new_dense_ids) id = in.get<VertexId>();
  commit.roadmap = decode_batch(get_blob(in));
  commit.dense = decode_batch(get_blob(in));
  read_tasks(in, commit);
  if (!in.done()) throw std::runtime_error("commit payload has trailing bytes");
  return commit;
}

bool snapshot_holds(const BuildCommit& commit, std::uint64_t snapshot_samples, std::uint64_t snapshot_tasks) {
  // Every commit but a task's draws at least one sample, so the sample count orders them; a
  // task's commit is ordered after the others of its sample count by the task count.
  if (commit.tasks.empty()) return commit.samples <= snapshot_samples;
  return commit.samples < snapshot_samples || (commit.samples == snapshot_samples && commit.task_count <= snapshot_tasks);
}

}  // namespace ispars
