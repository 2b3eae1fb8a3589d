// A fuzz test of the daemon's request path: a thousand malformed, oversized or random-byte
// requests from raw DDS writers (not the client library) while eight well-behaved clients keep
// querying. Every valid request is answered, every bad one refused or dropped, the daemon lives,
// and nothing stored changes.

#include <atomic>
#include <limits>
#include <random>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/wire/convert.hpp"
#include "support/raw_bytes_writer.hpp"
#include "support/raw_peer.hpp"

namespace ispars::test {
namespace {

// A typed request with hostile fields: any operation value, scene names long or odd, and
// arguments out of every range. Seeded, so a failure can be replayed.
msg::QueryRequest hostile_request(std::mt19937_64& rng, std::uint64_t seq) {
  std::uniform_int_distribution<int> pick(0, 15);
  msg::QueryRequest r;
  r.server_id("d");
  r.request_seq(seq);
  r.protocol(pick(rng) == 0 ? static_cast<std::uint16_t>(rng()) : msg::PROTOCOL_VERSION);
  static const std::vector<std::string> scenes = {"s0",       "",   "../s0", std::string(127, 'x'), "s0/..",
                                                  "\x01\xff", "S0", "s9",    std::string(64, 's')};
  r.scene(scenes[rng() % scenes.size()]);
  const int op = pick(rng);
  switch (op % 6) {
    case 0:
      r.args(wire::query_args(msg::STATS));
      break;
    case 1: {
      r.args(wire::query_args(msg::PATH));
      const double values[] = {std::numeric_limits<double>::quiet_NaN(), 1e300, -1e300, 0.0, 1.0};
      r.args().path().from().x(values[rng() % 5]);
      r.args().path().to().z(values[rng() % 5]);
      break;
    }
    case 2: {
      r.args(wire::query_args(msg::SNAPSHOT));
      r.args().snapshot().chunk_index(static_cast<std::uint32_t>(rng()));
      r.args().snapshot().version(rng());
      r.args().snapshot().generation(rng());
      break;
    }
    case 3: {
      r.args(wire::query_args(msg::TOUR));
      const double budgets[] = {std::numeric_limits<double>::quiet_NaN(), -1.0, 0.0, 1e9, 0.05};
      r.args().tour().budget(budgets[rng() % 5]);
      r.args().tour().targets(
          std::vector<std::uint32_t>(rng() % 50 == 0 ? 1'000'001 : rng() % 8, static_cast<std::uint32_t>(rng())));
      break;
    }
    case 4:
      r.args(wire::query_args(msg::LIST_SCENES));
      break;
    default: {
      r.args(wire::query_args(msg::STATS));
      r.args()._d() = static_cast<msg::Operation>(rng() % 40);  // often outside the enum or a change
      break;
    }
  }
  return r;
}

// Bytes a broken peer might send: wholly random, or a valid header over a random body.
std::string random_payload(std::mt19937_64& rng) {
  const std::size_t size = rng() % 600;
  std::string bytes(size, '\0');
  for (char& c : bytes) c = static_cast<char>(rng());
  if (rng() % 2 == 0 && size >= 4) {
    bytes[0] = 0;
    bytes[1] = 1;  // CDR little endian
    bytes[2] = 0;
    bytes[3] = 0;
  }
  return bytes;
}

TEST_F(ServiceTest, AThousandMalformedRequestsWhileEightClientsQuery) {
  auto daemon = start("d");
  Client control(client_options(domain_));
  const auto built = load_and_build(control, "s0", ispars_build(3000));
  const std::uint64_t digest = roadmap_digest(control.snapshot("s0").roadmap);

  std::atomic<bool> done{false};
  std::atomic<int> answered{0};
  std::vector<std::string> failures(8);
  std::vector<std::jthread> clients;
  for (int c = 0; c < 8; ++c) {
    clients.emplace_back([&, c] {
      try {
        Client client(client_options(domain_));
        while (!done) {
          const auto s = client.stats("s0");
          if (s.samples_done != built.samples_done || s.version != built.version) {
            failures[static_cast<std::size_t>(c)] = "the roadmap changed";
            return;
          }
          if (client.list_scenes().empty()) failures[static_cast<std::size_t>(c)] = "no scenes listed";
          answered += 2;
        }
      } catch (const std::exception& e) {
        failures[static_cast<std::size_t>(c)] = e.what();
      }
    });
  }
  std::mt19937_64 rng(20261123);
  RawBytesWriter bytes(domain_);
  RawPeer typed_a(domain_), typed_b(domain_);
  ASSERT_TRUE(bytes.wait_matched());
  constexpr int kRandomBytes = 400, kTyped = 600;
  for (int i = 0; i < kRandomBytes; ++i) EXPECT_TRUE(bytes.write(random_payload(rng)));
  for (int i = 0; i < kTyped; ++i) {
    RawPeer& peer = i % 2 == 0 ? typed_a : typed_b;
    ASSERT_TRUE(peer.post(hostile_request(rng, static_cast<std::uint64_t>(i) + 1)))
        << (daemon->alive() ? "no daemon matched" : "the daemon died on the malformed requests");
    if (i % 50 == 49) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a queue, not a flood
  }
  // The typed ones that reach the daemon are answered, nearly all with an error.
  std::size_t replies = 0;
  (void)eventually(
      [&] {
        replies = typed_a.replies_received() + typed_b.replies_received();
        return replies >= static_cast<std::size_t>(kTyped / 2);
      },
      std::chrono::seconds(30), "half the typed requests answered", std::chrono::milliseconds(100));  // checked below
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the well-behaved clients work on a while
  done = true;
  for (auto& t : clients) t.join();
  EXPECT_EQ(failures, std::vector<std::string>(8)) << "a well-behaved client was not answered";
  EXPECT_GT(answered.load(), 16);
  EXPECT_GE(replies, static_cast<std::size_t>(kTyped / 2)) << "typed requests went unanswered";
  std::size_t refused = 0;
  for (const RawPeer* peer : {&typed_a, &typed_b}) {
    for (const msg::Reply& r : peer->replies()) {
      if (!r.ok()) {
        ++refused;
        // "WHAT: FIELD: problem" (request, path or tour), never an internal error.
        const std::string& error = r.error();
        const bool named =
            (error.rfind("request: ", 0) == 0 || error.rfind("path: ", 0) == 0 || error.rfind("tour: ", 0) == 0) &&
            error.find(": ", error.find(": ") + 2) != std::string::npos;
        EXPECT_TRUE(named) << "not a named refusal: " << error;
      }
    }
  }
  EXPECT_GT(refused, replies / 2);
  EXPECT_TRUE(daemon->alive()) << daemon->log();
  EXPECT_NE(daemon->log().find("dropped a malformed ispars::msg::QueryRequest sample"), std::string::npos)
      << "random bytes were not reported";
  const auto after = control.stats("s0");
  EXPECT_EQ(after.samples_done, built.samples_done);
  EXPECT_EQ(after.version, built.version);
  EXPECT_EQ(roadmap_digest(control.snapshot("s0").roadmap), digest) << "stored data changed";
}

}  // namespace
}  // namespace ispars::test
