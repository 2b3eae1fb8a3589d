// The reply cache: a retried request is answered from the cache, never run twice.

#include <gtest/gtest.h>

#include "ispars/server/reply_cache.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

msg::Reply reply(std::uint64_t seq, const std::string& text) {
  msg::Reply r;
  r.request_seq(seq);
  r.body(wire::empty_reply_body(msg::STATS));
  r.message(text);
  return r;
}

TEST(ReplyCache, RetriesAreAnsweredFromTheCacheAndInProgressOnesAreNotRunAgain) {
  ReplyCache cache;
  msg::Reply out;
  EXPECT_EQ(cache.admit("c1", 5, out), ReplyCache::Admission::new_request);
  EXPECT_EQ(cache.admit("c1", 5, out), ReplyCache::Admission::in_progress);
  cache.complete("c1", 5, reply(5, "done"));
  ASSERT_EQ(cache.admit("c1", 5, out), ReplyCache::Admission::answered);
  EXPECT_EQ(out.message(), "done");
  // Another client's same sequence number is another request.
  EXPECT_EQ(cache.admit("c2", 5, out), ReplyCache::Admission::new_request);
}

TEST(ReplyCache, AForgottenRequestIsNewAgainButAnAnsweredOneIsKept) {
  ReplyCache cache;
  msg::Reply out;
  ASSERT_EQ(cache.admit("c", 1, out), ReplyCache::Admission::new_request);
  cache.forget("c", 1);  // refused as busy, never run
  EXPECT_EQ(cache.admit("c", 1, out), ReplyCache::Admission::new_request);
  cache.complete("c", 1, reply(1, "ran"));
  cache.forget("c", 1);  // only requests still in progress are forgotten
  EXPECT_EQ(cache.admit("c", 1, out), ReplyCache::Admission::answered);
}

TEST(ReplyCache, MemoryIsBoundedPerClientAndInClients) {
  ReplyCache cache(/*clients=*/2, /*per_client=*/3);
  msg::Reply out;
  for (std::uint64_t s = 1; s <= 5; ++s) {
    ASSERT_EQ(cache.admit("a", s, out), ReplyCache::Admission::new_request);
    cache.complete("a", s, reply(s, "r"));
  }
  EXPECT_EQ(cache.admit("a", 5, out), ReplyCache::Admission::answered);
  EXPECT_EQ(cache.admit("a", 1, out), ReplyCache::Admission::new_request);  // evicted: oldest first
  cache.complete("a", 1, reply(1, "r"));
  cache.admit("b", 1, out);
  cache.complete("b", 1, reply(1, "r"));
  cache.admit("c", 1, out);  // evicts the least recent client, a
  EXPECT_EQ(cache.admit("b", 1, out), ReplyCache::Admission::answered);
  EXPECT_EQ(cache.admit("a", 5, out), ReplyCache::Admission::new_request) << "a was not evicted";
}

// A request still waiting or running is never evicted, per client or with its client: its retry
// would run it again (an extend twice, under client churn).
TEST(ReplyCache, ARequestInProgressIsNeverEvicted) {
  ReplyCache cache(/*clients=*/2, /*per_client=*/3);
  msg::Reply out;
  ASSERT_EQ(cache.admit("op", 1, out), ReplyCache::Admission::new_request);  // a long extend
  for (std::uint64_t s = 2; s <= 10; ++s) {
    cache.admit("op", s, out);
    cache.complete("op", s, reply(s, "r"));
  }
  EXPECT_EQ(cache.admit("op", 1, out), ReplyCache::Admission::in_progress) << "evicted by the same client's later ones";
  for (int c = 0; c < 50; ++c) {  // client churn
    const std::string other = "viewer" + std::to_string(c);
    cache.admit(other, 1, out);
    cache.complete(other, 1, reply(1, "r"));
  }
  EXPECT_EQ(cache.admit("op", 1, out), ReplyCache::Admission::in_progress) << "evicted with its client";
  cache.complete("op", 1, reply(1, "extended"));
  ASSERT_EQ(cache.admit("op", 1, out), ReplyCache::Admission::answered);
  EXPECT_EQ(out.message(), "extended");
}

TEST(ReplyCache, SnapshotChunksAreNotKept) {
  ReplyCache cache;
  msg::Reply out;
  cache.admit("a", 1, out);
  msg::Reply chunk = reply(1, "");
  chunk.body(wire::empty_reply_body(msg::SNAPSHOT));
  chunk.body().snapshot().bytes().resize(1000);
  cache.complete("a", 1, chunk);
  EXPECT_EQ(cache.admit("a", 1, out), ReplyCache::Admission::new_request);  // re-read, harmless
}

}  // namespace
}  // namespace ispars::server
