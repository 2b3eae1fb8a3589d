// The client's longer exchanges: a snapshot pulled in chunks at one version, a tour with live
// progress, and waiting for a scene's job to end.

#include "client_impl.hpp"
#include "ispars/client/wire_calls.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"

namespace ispars::client {

Snapshot Client::snapshot(const std::string& scene) {
  const std::string server = owner_of(scene);
  for (int attempt = 0; attempt < 3; ++attempt) {
    msg::QueryRequest r = make_query(msg::SNAPSHOT, scene);
    const msg::Reply first = call(*this, r, server);
    const msg::SnapshotChunk& chunk0 = first.body().snapshot();
    Snapshot s;
    s.scene = scene;
    s.generation = chunk0.generation();
    s.version = chunk0.version();
    s.status = from_message(first.status());
    s.root = wire::from_message(chunk0.root());
    for (const auto& p : chunk0.pois()) s.pois.push_back(wire::from_message(p));
    std::string bytes(chunk0.bytes().begin(), chunk0.bytes().end());
    bool restarted = false;
    for (std::uint32_t i = 1; i < chunk0.chunk_count(); ++i) {
      r.args().snapshot().generation(s.generation);
      r.args().snapshot().version(s.version);
      r.args().snapshot().chunk_index(i);
      r.args().snapshot().poi_count(static_cast<std::uint32_t>(s.pois.size()));
      const msg::Reply part = call_raw(*this, r, server);
      if (!part.ok()) {  // the roadmap was rebuilt meanwhile: start again
        restarted = true;
        break;
      }
      const auto& more = part.body().snapshot().bytes();
      bytes.append(more.begin(), more.end());
    }
    if (restarted) continue;
    try {
      s.roadmap = Roadmap(s.pois.size());
      apply_batch(s.roadmap, decode_batch(bytes));
    } catch (const std::runtime_error& e) {
      throw ClientError(ClientError::Kind::protocol,
                        std::string("snapshot of '") + scene + "' is damaged: " + e.what());
    }
    return s;
  }
  throw ClientError(ClientError::Kind::protocol,
                    "the roadmap of '" + scene + "' kept changing generation during the snapshot");
}

TourReply Client::tour(const std::string& scene, double budget, std::uint64_t seed,
                       const std::vector<std::uint32_t>& targets,
                       const std::function<void(double seconds, double cost, double bound)>& progress) {
  return tour(scene, budget, seed, targets, {}, progress);
}

TourReply Client::task_tour(const std::string& scene, const std::string& task, double budget, std::uint64_t seed,
                            const std::function<void(double seconds, double cost, double bound)>& progress) {
  return tour(scene, budget, seed, {}, task, progress);
}

TourReply Client::tour(const std::string& scene, double budget, std::uint64_t seed,
                       const std::vector<std::uint32_t>& targets, const std::string& task,
                       const std::function<void(double seconds, double cost, double bound)>& progress) {
  impl_->ensure_progress_reader();
  {
    std::lock_guard lock(impl_->progress_.mutex);
    impl_->progress_.callback = progress;
  }
  msg::QueryRequest r = make_query(msg::TOUR, scene);
  r.args().tour().budget(budget);
  r.args().tour().seed(seed);
  r.args().tour().targets(targets);
  r.args().tour().task(task);
  // The daemon answers when the search ends: wait for the budget on top of the usual timeout.
  const auto timeout = options_.timeout + std::chrono::milliseconds(static_cast<long>(std::max(0.0, budget) * 1000));
  msg::Reply reply;
  try {
    reply = call(*this, r, {}, timeout);
  } catch (...) {
    std::lock_guard lock(impl_->progress_.mutex);
    impl_->progress_.callback = nullptr;
    throw;
  }
  std::lock_guard lock(impl_->progress_.mutex);
  impl_->progress_.callback = nullptr;
  return to_tour_reply(reply);
}

SceneStatus Client::wait_idle(const std::string& scene, const std::function<void(const SceneStatus&)>& progress,
                              std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  SceneStatus last = stats(scene);  // through the owner: fails clearly when not loaded
  if (progress) progress(last);
  std::uint64_t seen_version = last.version;
  std::uint64_t seen_samples = last.samples_done;
  SceneState seen_state = last.state;
  while (busy(last.state)) {
    if (std::chrono::steady_clock::now() >= deadline) {
      throw ClientError(ClientError::Kind::timeout, fmt::format("scene '{}' still {} after {:.0f} s", scene,
                                                                to_string(last.state), timeout.count() / 1000.0));
    }
    impl_->statuses_.wait_for(std::chrono::milliseconds(500), [&](const auto& latest) {
      const auto it = latest.find(scene);
      return it != latest.end() &&
             (it->second.samples_done() != seen_samples || from_message(it->second.state()) != seen_state ||
              it->second.version() != seen_version);
    });
    if (const auto s = latest_status(scene); s && s->status_seq < last.status_seq && s->server_id == last.server_id) {
      // older than what we know: ignore
    } else if (s) {
      if (s->server_id != last.server_id) {
        // The fleet moved the scene (docs/fleet.md): the new owner's status says what it continues.
        throw ClientError(
            ClientError::Kind::protocol,
            fmt::format("scene '{}' moved from daemon {} to daemon {} while waiting (now {}, {} of {} "
                        "samples); wait on it again to follow the new owner",
                        scene, last.server_id, s->server_id, to_string(s->state), s->samples_done, s->samples_target));
      }
      if (s->state == SceneState::unloaded) {
        throw ClientError(ClientError::Kind::protocol, fmt::format("scene '{}' was unloaded while waiting", scene));
      }
      last = *s;
    } else if (!impl_->daemons_.get(last.server_id)) {
      throw ClientError(ClientError::Kind::no_daemon,
                        fmt::format("daemon {} went away while building '{}'", last.server_id, scene));
    }
    if (last.samples_done != seen_samples || last.state != seen_state || last.version != seen_version) {
      seen_samples = last.samples_done;
      seen_state = last.state;
      seen_version = last.version;
      if (progress) progress(last);
    }
  }
  return last;
}

}  // namespace ispars::client
