// The scene filter on roadmap updates over real Fast DDS (localhost UDP, a domain of this
// process's own): batches of every size around one UDP datagram's, and one of seven datagrams,
// reach every filtered reader of their scene whole, however many follow it, and no reader of
// another scene. Intraprocess delivery is off, so samples cross the transport as they do between
// a daemon and its clients (within one process Fast DDS hands them over in memory, which hid the
// fault below).
//
// Fast DDS 2.9.1 sizes a sample's fragments before a writer that filters for its readers adds
// the filter's information to the sample's inline QoS, and every fragment carries it: a batch
// past one datagram then never fits a message, and never reaches a filtered reader in another
// process ("Cannot add RTPS submesage to the CDRMessage. Buffer too small"). The updates writer
// therefore leaves the filtering to each reader (updates_writer_qos); these tests fail when it
// filters.

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <gtest/gtest.h>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "ispars/local/local_daemon.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/scene_filter.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"
#include "support/eventually.hpp"

namespace ispars::wire {
namespace {

namespace fdds = eprosima::fastdds::dds;
using namespace std::chrono_literals;
using test::eventually;

// Counts the batches one reader takes, and the vertices they held.
struct Counting final : fdds::DataReaderListener {
  void on_data_available(fdds::DataReader* reader) override {
    msg::UpdateBatch batch;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&batch, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      ++batches;
      vertices += batch.vertices().size();
    }
  }
  std::atomic<std::size_t> batches{0}, vertices{0};
};

// A batch of `scene` with `vertex_count` vertices that see 12 POIs each: about 70 bytes a vertex.
msg::UpdateBatch large_batch(const std::string& scene, std::uint32_t vertex_count) {
  msg::UpdateBatch b;
  b.scene(scene);
  b.server_id("filter-test");
  b.generation(1);
  b.from_version(0);
  b.to_version(vertex_count);
  std::vector<msg::Vertex> vertices(vertex_count);
  for (std::uint32_t i = 0; i < vertex_count; ++i) {
    vertices[i].id(i);
    vertices[i].pois(std::vector<std::uint32_t>(12, i));
  }
  b.vertices(std::move(vertices));
  b.order(std::vector<std::uint8_t>(vertex_count, 0));
  return b;
}

// The daemon's side (its updates writer, the filter registered as DdsEndpoints does) and a
// client's (filtered readers, as RoadmapReplica makes them), on two participants.
// Intraprocess delivery off while it lives (read by Fast DDS as endpoints match).
struct OverTheTransport {
  OverTheTransport() {
    eprosima::fastrtps::LibrarySettingsAttributes off = before;
    off.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
    eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(off);
  }
  ~OverTheTransport() { eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(before); }
  const eprosima::fastrtps::LibrarySettingsAttributes before =
      eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings();
};

class SceneFilterTest : public ::testing::Test {
 protected:
  SceneFilterTest() : domain_(local::random_domain()), writer_side_({domain_, "", "ispars", "filter writer", ""}) {
    fdds::DomainParticipant* p = writer_side_.get();
    fdds::Topic* topic = find_or_create_topic(p, writer_type_, kUpdatesTopic);
    EXPECT_TRUE(register_scene_filter(p));
    publisher_ = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    writer_ = publisher_->create_datawriter(topic, updates_writer_qos());
  }
  ~SceneFilterTest() override {
    for (auto& r : readers_) (*r)->delete_contained_entities();
    writer_side_->delete_contained_entities();
  }

  // A reader of `scene`'s batches only.
  // A reader of `scene`'s batches only, on a participant of its own (as each client has).
  Counting& follow(const std::string& scene) {
    const std::string name = std::string(kUpdatesTopic) + "@" + scene + "#" + std::to_string(counters_.size());
    readers_.push_back(std::make_unique<Participant>(ParticipantOptions{domain_, "", "ispars", "filter reader", ""}));
    fdds::DomainParticipant* p = readers_.back()->get();
    fdds::Topic* topic = find_or_create_topic(p, reader_type_, kUpdatesTopic);
    fdds::ContentFilteredTopic* filtered = scene_filtered_topic(p, topic, name, scene);
    EXPECT_NE(filtered, nullptr);
    counters_.push_back(std::make_unique<Counting>());
    EXPECT_NE(p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT)
                  ->create_datareader(filtered, updates_reader_qos(), counters_.back().get(),
                                      fdds::StatusMask::data_available()),
              nullptr);
    return *counters_.back();
  }

  bool matched(int readers) {
    fdds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count == readers;
  }

  OverTheTransport over_the_transport_;  // first: before any participant
  int domain_;
  Participant writer_side_;
  std::vector<std::unique_ptr<Participant>> readers_;
  fdds::TypeSupport writer_type_{new SafeType<msg::UpdateBatchPubSubType>()};
  fdds::TypeSupport reader_type_{new SafeType<msg::UpdateBatchPubSubType>()};
  fdds::Publisher* publisher_ = nullptr;
  fdds::DataWriter* writer_ = nullptr;
  std::vector<std::unique_ptr<Counting>> counters_;
};

// Three replicas of s0 (the fleet's many followers, a gateway among them) and one of s1: a
// batch of about 400 kB (seven datagrams) reaches each of s0's whole, and none of s1's.
TEST_F(SceneFilterTest, ALargeBatchReachesEveryFilteredReaderOfItsSceneWhole) {
  ASSERT_NE(writer_, nullptr);
  Counting& a = follow("s0");
  Counting& b = follow("s0");
  Counting& c = follow("s0");
  Counting& other = follow("s1");
  ASSERT_TRUE(eventually([&] { return matched(4); }, 20s, "the writer matches the four readers"));
  msg::UpdateBatch batch = large_batch("s0", 6000);
  ASSERT_TRUE(writer_->write(&batch));
  for (Counting* r : {&a, &b, &c}) {
    EXPECT_TRUE(eventually([&] { return r->batches.load() == 1; }, 10s, "a replica of s0 takes the batch"));
    EXPECT_EQ(r->vertices.load(), 6000u);
  }
  // A small batch of s1 after it: s1's replica takes that one only.
  msg::UpdateBatch small = large_batch("s1", 10);
  ASSERT_TRUE(writer_->write(&small));
  EXPECT_TRUE(eventually([&] { return other.batches.load() == 1; }, 10s, "s1's replica takes its batch"));
  EXPECT_EQ(other.vertices.load(), 10u) << "a batch of s0 reached a replica of s1";
  EXPECT_EQ(a.batches.load(), 1u) << "a batch of s1 reached a replica of s0";
}

// Batches of every size around a UDP datagram's, 8 bytes apart: each reaches each replica.
TEST_F(SceneFilterTest, BatchesOfEverySizeAroundOneDatagramReachEveryFilteredReader) {
  ASSERT_NE(writer_, nullptr);
  Counting& a = follow("s0");
  Counting& b = follow("s0");
  Counting& c = follow("s0");
  ASSERT_TRUE(eventually([&] { return matched(3); }, 20s, "the writer matches the three readers"));
  std::size_t written = 0;
  for (std::size_t extra = 0; extra < 1024; extra += 8) {
    msg::UpdateBatch batch = large_batch("s0", 800);  // 64.8 kB, then up to 1 kB more
    batch.order().resize(batch.order().size() + extra, 0);
    batch.to_version(++written);
    ASSERT_TRUE(writer_->write(&batch));
    // Within the writer's history (kUpdatesKept): each batch acknowledged by every reader first.
    ASSERT_EQ(writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0)), ReturnCode_t::RETCODE_OK)
        << "batch " << written << " (" << batch.order().size() << " + " << batch.vertices().size()
        << " vertices) not acknowledged";
  }
  for (Counting* r : {&a, &b, &c}) {
    EXPECT_TRUE(eventually([&] { return r->batches.load() == written; }, 20s, "a replica of s0 takes every batch"))
        << r->batches.load() << " of " << written;
  }
}

}  // namespace
}  // namespace ispars::wire
