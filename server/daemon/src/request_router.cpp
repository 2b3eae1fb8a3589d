#include "ispars/server/request_router.hpp"

#include <spdlog/spdlog.h>

#include <type_traits>

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

// Client ids are GUID strings (about 50 bytes); the IDL bound (128) is above this limit, so an
// id the transport cut is refused, never taken for another client's.
constexpr std::size_t kMaxClientId = 100;
constexpr unsigned kQuickThreads = 2;
constexpr unsigned kSlowThreads = 2;

// Operations whose cost grows with the scene or the roadmap.
bool slow_operation(msg::Operation operation) {
  switch (operation) {
    case msg::LOAD_SCENE:
    case msg::PATH:
    case msg::SNAPSHOT:
    case msg::VERIFY:
    case msg::TASK_ADD:  // checks each POI against the surface
    case msg::TASK_LIST:
      return true;  // coverage over the roadmap
    default:
      return false;
  }
}

// A reply to `request` from `server_id`, ok until told otherwise, its body the request's operation.
template <class Request>
msg::Reply reply_to(const Request& request, const std::string& server_id) {
  msg::Reply reply;
  reply.client_id(request.client_id());
  reply.request_seq(request.request_seq());
  reply.server_id(server_id);
  reply.protocol(msg::PROTOCOL_VERSION);
  reply.ok(true);
  reply.body(wire::empty_reply_body(request.args()._d()));
  return reply;
}

}  // namespace

RequestRouter::RequestRouter(Parts parts, std::unique_ptr<RequestLedger> ledger)
    : parts_(std::move(parts)),
      ledger_(std::move(ledger)),
      quick_lane_(kQuickThreads, parts_.request_queue),
      slow_lane_(kSlowThreads, parts_.request_queue) {}

RequestRouter::~RequestRouter() { stop(); }

void RequestRouter::stop() {
  quick_lane_.stop();
  slow_lane_.stop();
}

void RequestRouter::receive(msg::QueryRequest request) { dispatch(std::move(request)); }
void RequestRouter::receive(msg::ChangeRequest request) { dispatch(std::move(request)); }

template <class Request>
void RequestRouter::dispatch(Request request) {
  const std::string client = request.client_id().to_string();
  if (client.empty() || client.size() > kMaxClientId) {
    spdlog::warn("dropped a request with an unusable client id ({} bytes)", client.size());
    return;  // nowhere to send a reply
  }
  // Retries are settled here, before any queue: a retry of a request still waiting or running
  // takes no place in a lane, and one already answered is answered again from the cache (or,
  // for a change begun before this daemon restarted, from its ledger).
  constexpr bool change = std::is_same_v<Request, msg::ChangeRequest>;
  if constexpr (change) {
    if (auto before = ledger_->from_before(request, reply_to(request, parts_.server_id))) {
      try {
        before->status(parts_.statuses.status_message(*parts_.service.session(request.scene().to_string())));
      } catch (const std::exception&) {  // not loaded here: no status
      }
      spdlog::info("answering retry {} #{} of a change begun before this daemon started, from its ledger", client,
                   request.request_seq());
      parts_.out.send_reply(*before);
      return;
    }
  }
  msg::Reply cached;
  switch (cache_.admit(client, request.request_seq(), cached)) {
    case ReplyCache::Admission::in_progress:
      return;  // its reply is on the way
    case ReplyCache::Admission::answered:
      spdlog::debug("answering retry {} #{} from the cache", client, request.request_seq());
      parts_.out.send_reply(cached);
      return;
    case ReplyCache::Admission::new_request:
      break;
  }
  const bool slow = slow_operation(request.args()._d());
  service::WorkerPool& lane = slow ? slow_lane_ : quick_lane_;
  // A change goes ahead of the reads waiting in its lane, and a drop stops the scene's running
  // verifies now. A drop is quick work once they stop (its store goes in a rename and a removal),
  // so it takes the quick lane: in the slow one it waited for a free thread behind snapshot
  // encodings (up to 2.75 s of a 100,000-sample scene's in LoopingViewers...).
  if constexpr (change) {
    if (request.args()._d() == msg::DROP) {
      parts_.service.stop_readers(request.scene().to_string(),
                                  fmt::format("scene '{}' is being dropped", request.scene().to_string()));
    }
  }
  const auto shared = std::make_shared<const Request>(std::move(request));
  if (!lane.submit([this, shared] { handle(*shared); }, change)) {
    cache_.forget(client, shared->request_seq());
    refuse_busy(*shared, lane, slow ? "slow" : "quick");
  }
}

template <class Request>
void RequestRouter::refuse_busy(const Request& request, const service::WorkerPool& lane, const char* lane_name) {
  spdlog::warn("{} #{} {} refused: the {} lane holds {} requests", request.client_id().to_string(),
               request.request_seq(), wire::to_string(request.args()._d()), lane_name, lane.max_queued());
  msg::Reply reply = reply_to(request, parts_.server_id);
  reply.ok(false);
  reply.error(
      fmt::format("request: kind: busy: {} requests are queued on this daemon's {} lane (its limit); "
                  "retry later",
                  lane.max_queued(), lane_name));
  parts_.metrics.count_request(wire::to_string(request.args()._d()), RequestOutcome::busy, 0.0);
  parts_.out.send_reply(reply);  // not cached: a retry is a new chance
}

template <class Request>
void RequestRouter::handle(const Request& request) {
  const auto taken = std::chrono::steady_clock::now();
  msg::Reply reply = reply_to(request, parts_.server_id);
  const msg::Operation operation = request.args()._d();
  const std::string client = request.client_id().to_string();
  const std::string scene = request.scene().to_string();
  bool now = true;
  try {
    if (request.protocol() != msg::PROTOCOL_VERSION) {
      throw params::InputError(
          "request", "protocol",
          fmt::format("this daemon speaks ispars protocol {}, the request protocol {}; use a client "
                      "of the same release",
                      msg::PROTOCOL_VERSION, request.protocol()));
    }
    if (request.request_seq() == 0) {
      throw params::InputError("request", "request_seq", "0 is reserved (the route-open reply); start at 1");
    }
    if constexpr (std::is_same_v<Request, msg::ChangeRequest>) {
      if (RequestLedger::kept(operation)) ledger_->begin(request);  // durable before anything changes
    }
    now = answer(request, reply);
  } catch (const params::InputError& e) {
    reply.ok(false);
    reply.error(e.what());
    spdlog::info("{} #{} {} '{}': {}", client, request.request_seq(), wire::to_string(operation), scene.substr(0, 64),
                 e.what());
  } catch (const std::exception& e) {
    reply.ok(false);
    reply.error(std::string("internal error: ") + e.what());
    spdlog::error("{} #{} {} '{}' failed: {}", client, request.request_seq(), wire::to_string(operation),
                  scene.substr(0, 64), e.what());
  }
  if (now) finish(reply, taken);
}

void RequestRouter::finish(const msg::Reply& reply, std::chrono::steady_clock::time_point taken) {
  const std::string& error = reply.error();
  const RequestOutcome outcome = reply.ok()                              ? RequestOutcome::ok
                                 : error.rfind("internal error", 0) == 0 ? RequestOutcome::failed
                                                                         : RequestOutcome::refused;
  parts_.metrics.count_request(wire::to_string(reply.body()._d()), outcome,
                               std::chrono::duration<double>(std::chrono::steady_clock::now() - taken).count());
  ledger_->answered(reply);
  cache_.complete(reply.client_id().to_string(), reply.request_seq(), reply);
  parts_.out.send_reply(reply);
}

}  // namespace ispars::server
