// The client's requests: discovery of the daemon that owns a scene, the call with retries, and
// one function per operation.

#include "ispars/client/client.hpp"

#include <type_traits>

#include "client_impl.hpp"
#include "ispars/wire/scene_owner.hpp"

namespace ispars::client {

Client::Client(ClientOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>(options_)) {}
Client::~Client() = default;

std::string Client::id() const { return impl_->id(); }
void Client::add_participant_user(ParticipantUser& user) { impl_->add_user(user); }
void Client::remove_participant_user(ParticipantUser& user) { impl_->remove_user(user); }
std::uint64_t Client::rejoins() const { return impl_->rejoins(); }
std::vector<msg::DaemonInfo> Client::daemons() { return impl_->daemons(options_.timeout); }
std::optional<msg::SceneStatus> Client::latest_status(const std::string& scene) const {
  return impl_->statuses_.get(scene);
}

std::string Client::daemon_identity(const std::string& server_id) const { return impl_->daemons_.sender(server_id); }

bool Client::written_by_daemon(const std::string& server_id, const std::string& sender) const {
  return wire::written_by_daemon(impl_->daemons_, server_id, sender);
}

std::string Client::owner_of(const std::string& scene) {
  std::vector<msg::DaemonInfo> all = daemons();
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

std::string Client::new_owner_of(const std::string& scene, const std::string& gone,
                                 std::chrono::steady_clock::time_point deadline) {
  // The fleet takes a scene over when its holder leaves: wait for the new holder to announce it.
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  impl_->daemons_.wait_for(std::max(left, std::chrono::milliseconds(0)), [&](const auto& latest) {
    for (const auto& [id, d] : latest) {
      if (id != gone && wire::holds(d, scene)) return true;
    }
    return false;
  });
  std::vector<msg::DaemonInfo> all = impl_->daemons_.all();
  std::erase_if(all, [&](const msg::DaemonInfo& d) { return d.server_id() == gone; });
  std::string owner = wire::owner_of(scene, all);
  // It holds the scene from its claim on; it serves it once loaded, when it publishes a status.
  const auto until_loaded =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  impl_->statuses_.wait_for(std::max(until_loaded, std::chrono::milliseconds(0)), [&](const auto& latest) {
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
msg::Reply Client::routed(Request request, const std::string& server, std::chrono::milliseconds timeout) {
  if (!server.empty()) return impl_->call(std::move(request), server, timeout);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const std::string scene = request.scene().to_string();
  std::string target = owner_of(scene);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    try {
      return impl_->call(request, target, std::max(left, std::chrono::milliseconds(1)));
    } catch (const ClientError& e) {
      if (e.kind() != ClientError::Kind::no_daemon || std::chrono::steady_clock::now() >= deadline) throw;
      std::string next = new_owner_of(scene, target, deadline);
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

msg::Reply Client::call_raw(msg::QueryRequest request, const std::string& server) {
  return routed(std::move(request), server, options_.timeout);
}

msg::Reply Client::call_raw(msg::ChangeRequest request, const std::string& server) {
  return routed(std::move(request), server, options_.timeout);
}

msg::Reply Client::call(msg::QueryRequest request, const std::string& server) {
  return call(std::move(request), server, options_.timeout);
}

msg::Reply Client::call(msg::ChangeRequest request, const std::string& server) {
  msg::Reply reply = routed(std::move(request), server, options_.timeout);
  if (!reply.ok()) throw ClientError(ClientError::Kind::rejected, reply.error());
  return reply;
}

msg::Reply Client::call(msg::QueryRequest request, const std::string& server, std::chrono::milliseconds timeout) {
  msg::Reply reply = routed(std::move(request), server, timeout);
  if (!reply.ok()) throw ClientError(ClientError::Kind::rejected, reply.error());
  return reply;
}

std::vector<msg::SceneEntry> Client::list_scenes() {
  std::vector<msg::SceneEntry> out;
  const auto all = daemons();
  if (all.empty()) throw ClientError(ClientError::Kind::no_daemon, impl_->no_daemon_message());
  for (const auto& d : all) {
    const msg::Reply reply = call(make_query(msg::LIST_SCENES, ""), d.server_id().to_string());
    const auto& scenes = reply.body().list_scenes().scenes();
    out.insert(out.end(), scenes.begin(), scenes.end());
  }
  return out;
}

msg::Reply Client::load(const std::string& scene) { return call(make_change(msg::LOAD_SCENE, scene)); }
msg::Reply Client::unload(const std::string& scene) { return call(make_change(msg::UNLOAD_SCENE, scene)); }
msg::Reply Client::cancel(const std::string& scene) { return call(make_change(msg::CANCEL, scene)); }
msg::Reply Client::drop(const std::string& scene) { return call(make_change(msg::DROP, scene)); }
msg::Reply Client::verify(const std::string& scene) { return call(make_query(msg::VERIFY, scene)); }
msg::SceneStatus Client::stats(const std::string& scene) { return call(make_query(msg::STATS, scene)).status(); }

msg::Reply Client::build(const std::string& scene, const BuildArgs& args) {
  msg::ChangeRequest r = make_change(msg::BUILD, scene);
  msg::BuildArgs& b = r.args().build();
  b.method(args.method);
  b.variant(args.variant);
  b.samples(args.samples);
  b.seed(args.seed);
  b.replace(args.replace);
  for (const auto& [name, value] : args.overrides) {
    msg::Parameter p;
    p.name(name);
    p.value(value);
    b.overrides().push_back(p);
  }
  return call(r);
}

msg::Reply Client::extend(const std::string& scene, std::uint64_t samples) {
  msg::ChangeRequest r = make_change(msg::EXTEND, scene);
  r.args().extend().samples(samples);
  return call(r);
}

msg::Reply Client::path(const std::string& scene, const Vec3& from, const Vec3& to) {
  msg::QueryRequest r = make_query(msg::PATH, scene);
  r.args().path().from(wire::to_message(from));
  r.args().path().to(wire::to_message(to));
  return call(r);
}

}  // namespace ispars::client
