// The client's requests: discovery of the daemon that owns a scene, the call with retries, and
// one function per operation.

#include "ispars/client/client.hpp"

#include <type_traits>

#include "client_impl.hpp"
#include "ispars/client/wire_calls.hpp"
#include "ispars/wire/build_args.hpp"
#include "ispars/wire/scene_owner.hpp"

namespace ispars::client {

/// The calls as messages, behind the domain methods and wire_calls.hpp's functions.
struct WireAccess {
  /// call_raw() to `server`, or to the scene's owner, following the scene when its owner leaves.
  template <class Request>
  static msg::Reply routed(Client& c, Request request, const std::string& server, std::chrono::milliseconds timeout);
  /// The owner of `scene` once daemon `gone` has left: waits (until `deadline`) for another to hold it.
  static std::string new_owner_of(Client& c, const std::string& scene, const std::string& gone,
                                  std::chrono::steady_clock::time_point deadline);
  template <class Request>
  static msg::Reply checked(Client& c, Request request, const std::string& server, std::chrono::milliseconds timeout) {
    msg::Reply reply = routed(c, std::move(request), server, timeout);
    if (!reply.ok()) throw ClientError(ClientError::Kind::rejected, reply.error());
    return reply;
  }
  static std::vector<msg::DaemonInfo> daemons(Client& c) { return c.impl_->daemons(c.options_.timeout); }
};

Client::Client(ClientOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>(options_)) {}
Client::~Client() = default;

std::string Client::id() const { return impl_->id(); }
void Client::add_participant_user(ParticipantUser& user) { impl_->add_user(user); }
void Client::remove_participant_user(ParticipantUser& user) { impl_->remove_user(user); }
std::uint64_t Client::rejoins() const { return impl_->rejoins(); }
std::vector<DaemonInfo> Client::daemons() {
  std::vector<DaemonInfo> out;
  for (const auto& d : impl_->daemons(options_.timeout)) out.push_back(from_message(d));
  return out;
}

std::optional<SceneStatus> Client::latest_status(const std::string& scene) const {
  if (auto s = impl_->statuses_.get(scene)) return from_message(*s);
  return std::nullopt;
}

std::string Client::daemon_identity(const std::string& server_id) const { return impl_->daemons_.sender(server_id); }

bool Client::written_by_daemon(const std::string& server_id, const std::string& sender) const {
  return wire::written_by_daemon(impl_->daemons_, server_id, sender);
}

std::string Client::owner_of(const std::string& scene) {
  std::vector<msg::DaemonInfo> all = impl_->daemons(options_.timeout);
  if (all.empty()) throw ClientError(ClientError::Kind::no_daemon, impl_->no_daemon_message());
  if (std::string holder = wire::holder_of(scene, all); !holder.empty()) return holder;
  // A second daemon may be discovered a moment after the first: give announcements a moment.
  impl_->daemons_.wait_for(std::chrono::milliseconds(500), [&](const auto& latest) {
    for (const auto& [id, d] : latest) {
      if (wire::holds(d, scene)) return true;
    }
    return false;
  });
  all = impl_->daemons_.all();
  if (!options_.server.empty() && wire::holder_of(scene, all).empty()) return options_.server;
  // The fleet's rule (wire/scene_owner.hpp), as every daemon computes it.
  if (std::string owner = wire::owner_of(scene, all); !owner.empty()) return owner;
  return all.front().server_id().to_string();  // no daemon offers it: it will say what is wrong with the name
}

std::string WireAccess::new_owner_of(Client& c, const std::string& scene, const std::string& gone,
                                     std::chrono::steady_clock::time_point deadline) {
  // The fleet takes a scene over when its holder leaves: wait for the new holder to announce it.
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  c.impl_->daemons_.wait_for(std::max(left, std::chrono::milliseconds(0)), [&](const auto& latest) {
    for (const auto& [id, d] : latest) {
      if (id != gone && wire::holds(d, scene)) return true;
    }
    return false;
  });
  std::vector<msg::DaemonInfo> all = c.impl_->daemons_.all();
  std::erase_if(all, [&](const msg::DaemonInfo& d) { return d.server_id() == gone; });
  std::string owner = wire::owner_of(scene, all);
  // It holds the scene from its claim on; it serves it once loaded, when it publishes a status.
  const auto until_loaded =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  c.impl_->statuses_.wait_for(std::max(until_loaded, std::chrono::milliseconds(0)), [&](const auto& latest) {
    const auto it = latest.find(scene);
    return it != latest.end() && it->second.server_id() == owner && it->second.state() != msg::SCENE_UNLOADED;
  });
  return owner;
}

msg::QueryRequest make_query(msg::Operation operation, const std::string& scene) {
  msg::QueryRequest r;
  r.scene(scene);
  r.args(wire::query_args(operation));
  return r;
}

msg::ChangeRequest make_change(msg::Operation operation, const std::string& scene) {
  msg::ChangeRequest r;
  r.scene(scene);
  r.args(wire::change_args(operation));
  return r;
}

template <class Request>
msg::Reply WireAccess::routed(Client& c, Request request, const std::string& server,
                              std::chrono::milliseconds timeout) {
  if (!server.empty()) return c.impl_->call(std::move(request), server, timeout);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const std::string scene = request.scene().to_string();
  std::string target = c.owner_of(scene);
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    try {
      return c.impl_->call(request, target, std::max(left, std::chrono::milliseconds(1)));
    } catch (const ClientError& e) {
      if (e.kind() != ClientError::Kind::no_daemon || std::chrono::steady_clock::now() >= deadline) throw;
      std::string next = new_owner_of(c, scene, target, deadline);
      if (next.empty() || next == target) throw;
      // A query or a load is safe to send again. Another change may have been done before the
      // owner left (and its takeover rebuilds the roadmap): the caller decides.
      if constexpr (std::is_same_v<Request, msg::ChangeRequest>) {
        if (request.args()._d() != msg::LOAD_SCENE) {
          throw ClientError(ClientError::Kind::no_daemon,
                            fmt::format("{}; scene '{}' moved to daemon {}, which takes it over from its recipe "
                                        "(check `ispars stats {}` before sending the {} again)",
                                        e.what(), scene, next, scene, wire::to_string(request.args()._d())));
        }
      }
      target = std::move(next);
    }
  }
}

std::vector<msg::DaemonInfo> daemon_messages(Client& client) { return WireAccess::daemons(client); }

msg::Reply call_raw(Client& client, msg::QueryRequest request, const std::string& server) {
  return WireAccess::routed(client, std::move(request), server, client.options().timeout);
}

msg::Reply call_raw(Client& client, msg::ChangeRequest request, const std::string& server) {
  return WireAccess::routed(client, std::move(request), server, client.options().timeout);
}

msg::Reply call(Client& client, msg::QueryRequest request, const std::string& server) {
  return WireAccess::checked(client, std::move(request), server, client.options().timeout);
}

msg::Reply call(Client& client, msg::ChangeRequest request, const std::string& server) {
  return WireAccess::checked(client, std::move(request), server, client.options().timeout);
}

msg::Reply call(Client& client, msg::QueryRequest request, const std::string& server,
                std::chrono::milliseconds timeout) {
  return WireAccess::checked(client, std::move(request), server, timeout);
}

std::vector<SceneEntry> Client::list_scenes() {
  std::vector<SceneEntry> out;
  const auto all = WireAccess::daemons(*this);
  if (all.empty()) throw ClientError(ClientError::Kind::no_daemon, impl_->no_daemon_message());
  for (const auto& d : all) {
    const msg::Reply reply = call(*this, make_query(msg::LIST_SCENES, ""), d.server_id().to_string());
    for (const auto& e : reply.body().list_scenes().scenes()) out.push_back(from_message(e));
  }
  return out;
}

Reply Client::load(const std::string& scene) { return to_reply(call(*this, make_change(msg::LOAD_SCENE, scene))); }
Reply Client::unload(const std::string& scene) { return to_reply(call(*this, make_change(msg::UNLOAD_SCENE, scene))); }
Reply Client::cancel(const std::string& scene) { return to_reply(call(*this, make_change(msg::CANCEL, scene))); }
Reply Client::drop(const std::string& scene) { return to_reply(call(*this, make_change(msg::DROP, scene))); }
VerifyReply Client::verify(const std::string& scene) {
  return to_verify_reply(call(*this, make_query(msg::VERIFY, scene)));
}
SceneStatus Client::stats(const std::string& scene) {
  return from_message(call(*this, make_query(msg::STATS, scene)).status());
}

Reply Client::build(const std::string& scene, const BuildArgs& args) {
  msg::ChangeRequest r = make_change(msg::BUILD, scene);
  r.args().build(wire::to_message(args));
  return to_reply(call(*this, r));
}

Reply Client::extend(const std::string& scene, std::uint64_t samples) {
  msg::ChangeRequest r = make_change(msg::EXTEND, scene);
  r.args().extend().samples(samples);
  return to_reply(call(*this, r));
}

Reply Client::add_task(const std::string& scene, const std::string& name, const std::vector<Vec3>& pois) {
  msg::ChangeRequest r = make_change(msg::TASK_ADD, scene);
  r.args().task_add().name(name);
  r.args().task_add().pois().reserve(pois.size());
  for (const Vec3& p : pois) r.args().task_add().pois().push_back(wire::to_message(p));
  return to_reply(call(*this, r));
}

Reply Client::add_sampled_task(const std::string& scene, const std::string& name, std::uint32_t count,
                               std::uint64_t seed) {
  msg::ChangeRequest r = make_change(msg::TASK_ADD, scene);
  r.args().task_add().name(name);
  r.args().task_add().sample(count);
  r.args().task_add().sample_seed(seed);
  return to_reply(call(*this, r));
}

Reply Client::remove_task(const std::string& scene, const std::string& name) {
  msg::ChangeRequest r = make_change(msg::TASK_REMOVE, scene);
  r.args().task_remove().name(name);
  return to_reply(call(*this, r));
}

std::vector<TaskEntry> Client::tasks(const std::string& scene) {
  const msg::Reply reply = call(*this, make_query(msg::TASK_LIST, scene));
  std::vector<TaskEntry> out;
  for (const msg::TaskEntry& t : reply.body().task_list().tasks()) out.push_back(from_message(t));
  return out;
}

PathReply Client::path(const std::string& scene, const Vec3& from, const Vec3& to) {
  msg::QueryRequest r = make_query(msg::PATH, scene);
  r.args().path().from(wire::to_message(from));
  r.args().path().to(wire::to_message(to));
  return to_path_reply(call(*this, r));
}

}  // namespace ispars::client
