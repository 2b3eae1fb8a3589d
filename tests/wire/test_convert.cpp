// Messages and core types convert both ways without loss; inconsistent messages are refused.

#include <gtest/gtest.h>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/wire/convert.hpp"
#include "support/test_support.hpp"

namespace ispars::wire {
namespace {

TEST(WireConvert, UpdateBatchesRoundTripIntoAnIdenticalReplica) {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  auto builder = planning::make_roadmap_builder(BuildMethod::ispars, scene, planning::BuildOptions{});
  Roadmap replica(scene.pois().size());
  std::uint64_t version = 0;
  for (int i = 0; i < 5; ++i) {
    builder->extend(300);
    const RoadmapBatch batch = batch_since(builder->roadmap(), version);
    const msg::UpdateBatch m = to_message(batch, "tower", "d1", 9, builder->samples());
    EXPECT_EQ(m.from_version(), version);
    EXPECT_EQ(m.order().size(), batch.changes.size());
    apply_batch(replica, from_message(m));
    version = builder->roadmap().version();
  }
  EXPECT_EQ(roadmap_digest(replica), roadmap_digest(builder->roadmap()));
  EXPECT_EQ(test::fingerprint(replica), test::fingerprint(builder->roadmap()));
}

TEST(WireConvert, InconsistentBatchesAreRefused) {
  msg::UpdateBatch m;
  m.from_version(3);
  m.to_version(5);
  m.order({0});
  EXPECT_THROW((void)from_message(m), std::runtime_error);  // range says 2 changes, order 1
  m.order({0, 0});
  EXPECT_THROW((void)from_message(m), std::runtime_error);  // no vertices
  m.order({0, 7});
  m.vertices().resize(1);
  EXPECT_THROW((void)from_message(m), std::runtime_error);  // unknown kind
  m.to_version(2);
  EXPECT_THROW((void)from_message(m), std::runtime_error);  // backwards
}

}  // namespace
}  // namespace ispars::wire
