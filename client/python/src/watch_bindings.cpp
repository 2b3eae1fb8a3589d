// ispars.Watch: a live replica of a scene's roadmap, iterated as batches of what is new.

#include <fmt/format.h>

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "arrays.hpp"
#include "client_handle.hpp"
#include "ispars/client/replica.hpp"
#include "stoppable.hpp"

namespace ispars::python {
namespace {

/// A replica and what the iteration has handed out of it: each batch is what is new since the
/// last (the whole roadmap again after a rebuild, a drop or a resync).
class WatchHandle {
 public:
  WatchHandle(ClientHandle client, const std::string& scene) : client_(std::move(client)) {
    py::gil_scoped_release release;
    replica_ = std::make_shared<client::RoadmapReplica>(*client_, scene, [this](const client::ReplicaEvent& e) {
      std::lock_guard lock(mutex_);
      ++changes_;
      resynced_ = resynced_ || e.resynced;
      changed_.notify_all();
    });
  }
  ~WatchHandle() { close(); }
  WatchHandle(const WatchHandle&) = delete;
  WatchHandle& operator=(const WatchHandle&) = delete;

  /// The next batch: waits (Ctrl-C raises KeyboardInterrupt) for a change, up to `timeout` s
  /// (None: for ever); None on a timeout; StopIteration once closed.
  py::object next(const py::object& timeout) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeout.is_none() ? 1e9 : timeout.cast<double>()));
    for (;;) {
      bool ready = false;
      {
        py::gil_scoped_release release;
        std::unique_lock lock(mutex_);
        ready =
            changed_.wait_for(lock, std::chrono::milliseconds(20), [this] { return closed_ || changes_ != taken_; });
        if (closed_) ready = true;
      }
      if (ready) break;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (std::chrono::steady_clock::now() >= deadline) return py::none();
    }
    bool resynced = false;
    {
      std::lock_guard lock(mutex_);
      if (closed_) throw py::stop_iteration();
      taken_ = changes_;
      resynced = std::exchange(resynced_, false);
    }
    return batch(resynced);
  }

  /// The replica as it is now, copied.
  std::shared_ptr<Roadmap> roadmap() {
    const auto held = replica();
    py::gil_scoped_release release;
    return std::make_shared<Roadmap>(held->roadmap());
  }

  /// Stops following. A call still reading the replica on another thread keeps it until done.
  void close() {
    std::shared_ptr<client::RoadmapReplica> replica;
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
      replica = std::move(replica_);
      changed_.notify_all();
    }
    py::gil_scoped_release release;
    replica.reset();
  }

 private:
  // The replica, held by the caller: close() on another thread cannot destroy it under a read.
  std::shared_ptr<const client::RoadmapReplica> replica() {
    std::lock_guard lock(mutex_);
    if (!replica_) throw std::runtime_error("the watch is closed");
    return replica_;
  }

  // What is new since the last batch, as a dict; the whole roadmap when its generation changed
  // or the replica resynced (then "resynced" is True and the counts start from 0).
  py::dict batch(bool resynced) {
    std::vector<Vec3> positions;
    std::vector<std::uint32_t> edges;
    std::uint64_t generation = 0, samples = 0, version = 0, vertices = 0, edge_count = 0;
    std::size_t first_vertex = 0, first_edge = 0;
    const auto held = replica();
    {
      py::gil_scoped_release release;
      held->read([&](const Roadmap& r, std::uint64_t g, std::uint64_t s) {
        resynced = resynced || g != generation_ || r.vertex_count() < vertices_ || r.edge_count() < edges_;
        first_vertex = resynced ? 0 : vertices_;
        first_edge = resynced ? 0 : edges_;
        positions.assign(r.positions().begin() + static_cast<std::ptrdiff_t>(first_vertex), r.positions().end());
        for (std::size_t i = first_edge; i < r.edge_count(); ++i) {
          edges.push_back(r.edge_ends()[i].u);
          edges.push_back(r.edge_ends()[i].v);
        }
        generation = g;
        samples = s;
        version = r.version();
        vertices = r.vertex_count();
        edge_count = r.edge_count();
      });
    }
    generation_ = generation;
    vertices_ = vertices;
    edges_ = edge_count;
    py::dict out;
    out["generation"] = generation;
    out["version"] = version;
    out["vertex_count"] = vertices;
    out["edge_count"] = edge_count;
    out["samples_done"] = samples;
    out["resynced"] = resynced;
    out["first_vertex"] = first_vertex;
    out["positions"] = take_points(std::move(positions));
    out["first_edge"] = first_edge;
    const auto n = static_cast<py::ssize_t>(edges.size() / 2);
    out["edges"] = take(std::move(edges), {n, 2});
    return out;
  }

  ClientHandle client_;                              // outlives replica_
  std::shared_ptr<client::RoadmapReplica> replica_;  // guarded by mutex_
  std::mutex mutex_;
  std::condition_variable changed_;
  std::uint64_t changes_ = 0, taken_ = 0;
  bool resynced_ = false, closed_ = false;
  // What the batches handed out so far hold (the Python thread's alone).
  std::uint64_t generation_ = 0, vertices_ = 0, edges_ = 0;
};

}  // namespace

void bind_watch(py::module_& m) {
  py::class_<WatchHandle, std::shared_ptr<WatchHandle>>(
      m, "Watch",
      "A live replica of a scene's roadmap (Client.watch). Iterating gives batches, dicts of what is new since "
      "the last: positions (new vertices, from first_vertex), edges (new edges' ends, from first_edge), and the "
      "totals (vertex_count, edge_count, version, generation, samples_done). After a rebuild, a drop or a resync "
      "a batch holds the whole roadmap again, with resynced True. Iteration ends when the watch is closed.")
      .def("__iter__", [](const std::shared_ptr<WatchHandle>& self) { return self; })
      .def("__next__", [](WatchHandle& self) { return self.next(py::none()); })
      .def("next", &WatchHandle::next, py::arg("timeout") = py::none(),
           "The next batch, waiting at most `timeout` seconds (None: until one comes); None on a timeout.")
      .def("roadmap", &WatchHandle::roadmap, "A copy of the replica as it is now.")
      .def("close", &WatchHandle::close, "Stops following; iteration ends.")
      .def("__enter__", [](const std::shared_ptr<WatchHandle>& self) { return self; })
      .def("__exit__", [](WatchHandle& self, const py::args&) { self.close(); });
  auto client = py::reinterpret_borrow<py::class_<ClientHandle>>(m.attr("Client"));
  client.def(
      "watch",
      [](const ClientHandle& self, const std::string& scene) {
        // Asked first, as `ispars watch` does: a scene no daemon holds raises ClientError at once
        // instead of a watch that waits silently for ever.
        (void)run_detached([self, scene] { return self->stats(scene); });
        return std::make_shared<WatchHandle>(self, scene);
      },
      py::arg("scene"),
      "Follows the scene's roadmap: a snapshot, then every update (for batch in client.watch(scene): ...). "
      "Raises ClientError at once when no daemon holds the scene.");
}

}  // namespace ispars::python
