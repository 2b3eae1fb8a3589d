// ispars-bench rtt: the stats round trip through isparsd against a raw Fast DDS ping-pong that
// moves samples of the same types, sizes, topics, partitions and QoS with no service logic, in
// one run, alternating in blocks of 100. With a keystore script it measures the same four paths
// again under DDS Security (every participant authenticated, access-controlled and encrypted by
// the governance deploy/security/make-keystore.sh writes), so both the service's overhead over
// raw DDS with the same security and the cost of security itself come from one run.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <fmt/format.h>

#include <condition_variable>
#include <iostream>
#include <mutex>
#include <thread>

#include "bench_common.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::bench {
namespace {

namespace fdds = eprosima::fastdds::dds;
constexpr const char* kEchoId = "bench-echo";

// One end of the raw ping-pong, on the service's own topics: pings are QueryRequests on the query
// topic addressed to kEchoId (the daemon drops them as addressed elsewhere), pongs are Replies in
// the pinging client's reply partition, as the daemon's are.
struct RawEndpoints final : public fdds::DataReaderListener {
  // A client: `security` its identity. A server: `client_identity` the partition it answers in.
  RawEndpoints(int domain, const std::string& security, bool is_server, const std::string& client_identity = "")
      : participant({domain, "", "ispars", "raw ping-pong", security}), server(is_server) {
    fdds::DomainParticipant* p = participant.get();
    auto* ping = wire::find_or_create_topic(p, request_type, wire::kQueryTopic);
    auto* pong = wire::find_or_create_topic(p, reply_type, wire::kReplyTopic);
    identity = wire::identity_of(p->guid().guidPrefix);
    auto* pub = server ? p->create_publisher(wire::reply_publisher_qos(client_identity))
                       : p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    auto* sub = server ? p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT)
                       : p->create_subscriber(wire::reply_subscriber_qos(identity));
    if (pub == nullptr || sub == nullptr) throw std::runtime_error("raw ping-pong: no publisher or subscriber");
    writer = pub->create_datawriter(server ? pong : ping, wire::request_reply_writer_qos());
    reader = sub->create_datareader(server ? ping : pong, wire::request_reply_reader_qos(), this,
                                    fdds::StatusMask::data_available());
    if (writer == nullptr || reader == nullptr) throw std::runtime_error("raw ping-pong: endpoints refused");
  }
  ~RawEndpoints() override { reader->set_listener(nullptr); }

  void on_data_available(fdds::DataReader* r) override {
    fdds::SampleInfo info;
    if (server) {
      msg::QueryRequest request;
      while (r->take_next_sample(&request, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data || request.server_id() != kEchoId) continue;
        msg::Reply reply = reply_template;
        reply.client_id(wire::sender_identity(info));
        reply.request_seq(request.request_seq());
        writer->write(&reply);
      }
    } else {
      msg::Reply reply;
      while (r->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        std::lock_guard lock(mutex);
        last_seq = reply.request_seq();
        arrived.notify_all();
      }
    }
  }

  bool matched() {
    fdds::PublicationMatchedStatus pub;
    fdds::SubscriptionMatchedStatus sub;
    writer->get_publication_matched_status(pub);
    reader->get_subscription_matched_status(sub);
    return pub.current_count > 0 && sub.current_count > 0;
  }

  double round_trip(msg::QueryRequest& request) {
    const auto t0 = Clock::now();
    writer->write(&request);
    std::unique_lock lock(mutex);
    arrived.wait_for(lock, std::chrono::seconds(5), [&] { return last_seq == request.request_seq(); });
    return seconds_since(t0);
  }

  wire::Participant participant;
  bool server;
  std::string identity;
  fdds::TypeSupport request_type{new msg::QueryRequestPubSubType()};
  fdds::TypeSupport reply_type{new msg::ReplyPubSubType()};
  fdds::DataWriter* writer = nullptr;
  fdds::DataReader* reader = nullptr;
  msg::Reply reply_template;
  std::mutex mutex;
  std::condition_variable arrived;
  std::uint64_t last_seq = 0;
};

// The daemon's own stats reply, serialized, for the echo server to answer with: both paths move
// samples of the same size.
std::string reply_to_hex(const msg::Reply& reply) {
  msg::ReplyPubSubType type;
  msg::Reply copy = reply;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&copy)());
  if (!type.serialize(&copy, &payload)) throw std::runtime_error("cannot serialize the stats reply");
  std::string hex;
  for (std::uint32_t i = 0; i < payload.length; ++i) hex += fmt::format("{:02x}", payload.data[i]);
  return hex;
}

}  // namespace

msg::Reply reply_from_hex(const std::string& hex) {
  msg::ReplyPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(hex.size() / 2));
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    payload.data[i / 2] = static_cast<eprosima::fastrtps::rtps::octet>(std::stoi(hex.substr(i, 2), nullptr, 16));
  }
  payload.length = static_cast<std::uint32_t>(hex.size() / 2);
  msg::Reply reply;
  if (!type.deserialize(&payload, &reply)) throw std::runtime_error("the echo's reply template does not decode");
  return reply;
}

namespace {

// One setting (with or without security): a daemon with a built roadmap, a client, and the raw
// ping-pong (its echo server in a process of its own, as the daemon is).
struct Setting {
  Setting(const std::string& daemon_binary, const std::filesystem::path& keystore)
      : bench(daemon_binary, {}, identity(keystore, "bench-daemon"), identity(keystore, "bench-client")) {
    bench.client_identity = identity(keystore, "bench-client");
    client = std::make_unique<Client>(bench.options());
    client->load("tower");
    client->build("tower", ispars::request_of("ispars", 2000));
    client->wait_idle("tower", {}, std::chrono::seconds(120));
    raw = std::make_unique<RawEndpoints>(bench.domain, identity(keystore, "bench-raw"), false);
    const std::string reply_hex = reply_to_hex(client::call(*client, stats));
    // fork + exec: forking a process that already runs DDS threads is unsafe.
    echo = ::fork();
    if (echo == 0) {
      const std::string domain = std::to_string(bench.domain);
      const std::string self = std::filesystem::canonical("/proc/self/exe").string();
      const std::string security = identity(keystore, "bench-echo");
      ::execl(self.c_str(), self.c_str(), "echo", "--domain", domain.c_str(), "--security", security.c_str(),
              "--client", raw->identity.c_str(), "--reply", reply_hex.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    for (int i = 0; !raw->matched(); ++i) {
      if (i > 3000) throw std::runtime_error("the raw echo server did not match within 30 s");
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ping.server_id(kEchoId);
  }
  ~Setting() {
    if (echo > 0) {
      ::kill(echo, SIGTERM);
      ::waitpid(echo, nullptr, 0);
    }
  }
  static std::string identity(const std::filesystem::path& keystore, const std::string& name) {
    return keystore.empty() ? std::string() : (keystore / "identities" / name).string();
  }

  double service_round_trip() {
    const auto t0 = Clock::now();
    (void)client::call(*client, stats);
    return seconds_since(t0);
  }
  double raw_round_trip() {
    ping.request_seq(++seq);
    return raw->round_trip(ping);
  }

  Bench bench;
  std::unique_ptr<Client> client;
  std::unique_ptr<RawEndpoints> raw;
  pid_t echo = -1;
  msg::QueryRequest stats = client::make_query(msg::STATS, "tower");
  msg::QueryRequest ping = client::make_query(msg::STATS, "tower");
  std::uint64_t seq = 0;
  std::vector<double> service, direct;
};

nlohmann::json summary(const Setting& s) {
  const double sm = percentile(s.service, 0.5) * 1e6, sp = percentile(s.service, 0.99) * 1e6;
  const double rm = percentile(s.direct, 0.5) * 1e6, rp = percentile(s.direct, 0.99) * 1e6;
  return {{"round_trips", s.service.size()},
          {"service_median_us", sm},
          {"service_p99_us", sp},
          {"raw_median_us", rm},
          {"raw_p99_us", rp},
          {"median_ratio", sm / rm},
          {"p99_ratio", sp / rp}};
}

}  // namespace

nlohmann::json run_rtt(const std::string& daemon_binary, int count, const std::string& keystore_script) {
  std::filesystem::path keystore;
  if (!keystore_script.empty()) {
    char pattern[] = "/tmp/ispars-keystore-XXXXXX";
    keystore = ::mkdtemp(pattern);
    local::make_keystore(keystore_script, keystore,
                         {"daemon:bench-daemon", "operator:bench-client", "operator:bench-raw", "daemon:bench-echo"});
  }
  std::vector<std::unique_ptr<Setting>> settings;
  settings.push_back(std::make_unique<Setting>(daemon_binary, std::filesystem::path()));
  if (!keystore.empty()) settings.push_back(std::make_unique<Setting>(daemon_binary, keystore));
  for (auto& s : settings) {
    for (int w = 0; w < 50; ++w) {  // warm-up, every path
      (void)s->service_round_trip();
      (void)s->raw_round_trip();
    }
  }
  for (int block = 0; block < count / 100; ++block) {
    for (auto& s : settings) {
      for (int i = 0; i < 100; ++i) s->service.push_back(s->service_round_trip());
      for (int i = 0; i < 100; ++i) s->direct.push_back(s->raw_round_trip());
    }
  }
  nlohmann::json out = summary(*settings.front());
  out["bench"] = "rtt";
  if (settings.size() > 1) {
    const nlohmann::json secure = summary(*settings.back());
    out["secure"] = secure;
    out["security_cost_service_median"] =
        secure["service_median_us"].get<double>() / out["service_median_us"].get<double>();
    out["security_cost_raw_median"] = secure["raw_median_us"].get<double>() / out["raw_median_us"].get<double>();
  }
  settings.clear();
  if (!keystore.empty()) std::filesystem::remove_all(keystore);
  return out;
}

int run_echo(int domain, const std::string& security, const std::string& client_identity,
             const std::string& reply_hex) {
  RawEndpoints server(domain, security, true, client_identity);
  server.reply_template = reply_from_hex(reply_hex);
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  int signal = 0;
  sigwait(&stop, &signal);
  return 0;
}

}  // namespace ispars::bench
