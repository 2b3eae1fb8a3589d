// A build commit's bytes in the store's records (roadmap_store.hpp): the samples, the dense
// ids, the two batches, and the tasks the commit adds or removes, if any; and how a store's task
// list follows its commits.

#include <fmt/format.h>

#include <stdexcept>
#include <string>

#include "ispars/service/roadmap_store.hpp"

namespace ispars::service {
namespace {

std::string_view get_blob(ByteReader& in) {
  const auto size = in.get<std::uint64_t>();
  return in.bytes(size);
}

// A commit's tasks follow its batches, after this marker ("TASKS\0\0\0"): a commit without tasks
// is encoded exactly as before tasks existed, so older stores read as they were.
constexpr std::uint64_t kTasksMarker = 0x0000'0053'4b53'4154ULL;
// The tasks a commit removes follow its added tasks, after this marker ("REMOVED\0").
constexpr std::uint64_t kRemovedMarker = 0x0044'4556'4f4d'4552ULL;

void append_tasks(std::string& out, const BuildCommit& commit) {
  if (!commit.changes_tasks()) return;
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
  if (commit.removed_tasks.empty()) return;
  put_bytes(out, kRemovedMarker);
  put_bytes(out, static_cast<std::uint64_t>(commit.removed_tasks.size()));
  for (const std::uint64_t index : commit.removed_tasks) put_bytes(out, index);
}

void read_tasks(ByteReader& in, BuildCommit& commit) {
  if (in.done()) return;
  if (in.get<std::uint64_t>() != kTasksMarker) throw std::runtime_error("commit payload has trailing bytes");
  commit.task_count = in.get<std::uint64_t>();
  const auto count = in.get<std::uint64_t>();
  if (count > commit.task_count || count > kMaxTasks) throw std::runtime_error("commit task count is impossible");
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
  if (!in.done() && in.get<std::uint64_t>() == kRemovedMarker) {
    const auto removed = in.get<std::uint64_t>();
    if (removed == 0 || removed > kMaxTasks) throw std::runtime_error("commit removed-task count is impossible");
    commit.removed_tasks.resize(removed);
    for (std::uint64_t& index : commit.removed_tasks) index = in.get<std::uint64_t>();
  } else if (!in.done()) {
    throw std::runtime_error("commit payload has trailing bytes");
  }
  if (!commit.changes_tasks()) throw std::runtime_error("commit has a task section that changes no task");
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

bool snapshot_holds(const BuildCommit& commit, std::uint64_t snapshot_samples, std::uint64_t snapshot_task_events) {
  // Every commit but a task's draws at least one sample, so the sample count orders them; a
  // task's commit (an addition or a removal) is ordered after the others of its sample count by
  // the task events after it.
  if (!commit.changes_tasks()) return commit.samples <= snapshot_samples;
  return commit.samples < snapshot_samples ||
         (commit.samples == snapshot_samples && commit.task_count <= snapshot_task_events);
}

std::uint64_t task_events(std::span<const InspectionTask> tasks) {
  std::uint64_t events = tasks.size();
  for (const InspectionTask& t : tasks) events += t.removed ? 1 : 0;
  return events;
}

void fold_tasks(std::vector<InspectionTask>& tasks, const BuildCommit& commit) {
  if (!commit.changes_tasks()) return;
  const std::uint64_t events = task_events(tasks) + commit.tasks.size() + commit.removed_tasks.size();
  if (commit.task_count != events) {
    throw std::runtime_error(fmt::format("a task commit says {} task events after {} and {} more", commit.task_count,
                                         task_events(tasks), commit.tasks.size() + commit.removed_tasks.size()));
  }
  std::vector<InspectionTask> next = tasks;
  next.insert(next.end(), commit.tasks.begin(), commit.tasks.end());
  for (const std::uint64_t index : commit.removed_tasks) {
    if (index >= next.size() || next[index].removed) {
      throw std::runtime_error(fmt::format("a task commit removes task {} of {}, which {}", index, next.size(),
                                           index >= next.size() ? "does not exist" : "was removed already"));
    }
    next[index].removed = true;
  }
  tasks = std::move(next);
}

void set_tasks(BuildCommit& commit, std::span<const InspectionTask> tasks) {
  commit.tasks.assign(tasks.begin(), tasks.end());
  commit.removed_tasks.clear();
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (tasks[i].removed) commit.removed_tasks.push_back(i);
    commit.tasks[i].removed = false;  // recorded by removed_tasks, as a removal's commit does
  }
  commit.task_count = task_events(tasks);
}

}  // namespace ispars::service
