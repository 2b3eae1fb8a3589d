// What a browser is sent of a roadmap (append_roadmap_messages, SceneFeed's pure part): a reset
// on a new generation, batches within the per-message size, every edge once its ends are sent,
// the draw limits with a note (edges with an end past the vertex limit left out), and nothing
// when the browser is up to date.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "ispars/web/scene_feed.hpp"

namespace ispars::web {
namespace {

// A path of `n` vertices along x: edges i-(i+1).
Roadmap path(std::size_t n) {
  Roadmap r;
  for (std::size_t i = 0; i < n; ++i) (void)r.add_vertex(Vec3(static_cast<double>(i), 0, 0), {});
  for (std::size_t i = 0; i + 1 < n; ++i)
    EXPECT_TRUE(r.add_edge(static_cast<VertexId>(i), static_cast<VertexId>(i + 1)));
  return r;
}

std::vector<nlohmann::json> messages(const Roadmap& r, std::uint64_t generation, const DrawLimits& limits,
                                     ViewerCursor& cursor) {
  std::vector<std::string> out;
  append_roadmap_messages(r, generation, limits, cursor, out);
  std::vector<nlohmann::json> parsed;
  for (const std::string& m : out) parsed.push_back(nlohmann::json::parse(m));
  return parsed;
}

TEST(SceneFeed, ABrowserIsBroughtUpToDateInBatchesAndThenSentNothing) {
  const Roadmap r = path(5);
  ViewerCursor cursor;
  const auto first = messages(r, 7, {100, 100, 2}, cursor);
  ASSERT_EQ(first.size(), 4u);  // a reset, then 5 vertices and 4 edges two at a time
  EXPECT_EQ(first[0]["type"], "reset");
  EXPECT_EQ(first[0]["generation"], 7);
  EXPECT_EQ(first[1]["type"], "batch");
  EXPECT_EQ(first[1]["positions"].size(), 6u);
  EXPECT_EQ(first[1]["edges"], nlohmann::json::array({0, 1}));  // 1-2 waits for vertex 2
  EXPECT_EQ(first[3]["vertices_sent"], 5);
  EXPECT_EQ(first[3]["edges_sent"], 4);
  EXPECT_EQ(first[3]["note"], "");
  std::size_t edges = 0;
  for (std::size_t i = 1; i < first.size(); ++i) edges += first[i]["edges"].size() / 2;
  // Before, an edge whose end came in a later batch was skipped for good (2 of the 4 here).
  EXPECT_EQ(edges, 4u) << "an edge to a vertex of a later batch was never sent";
  EXPECT_TRUE(messages(r, 7, {100, 100, 2}, cursor).empty());
  // Grown: only what is new.
  const Roadmap grown = path(6);
  const auto more = messages(grown, 7, {100, 100, 2}, cursor);
  ASSERT_EQ(more.size(), 1u);
  EXPECT_EQ(more[0]["first_vertex"], 5);
  EXPECT_EQ(more[0]["edges"], nlohmann::json::array({4, 5}));
}

TEST(SceneFeed, ANewGenerationStartsTheBrowserAgain) {
  ViewerCursor cursor;
  (void)messages(path(4), 1, {}, cursor);
  cursor.last_status = "kept";
  const auto again = messages(path(2), 2, {}, cursor);
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0]["type"], "reset");
  EXPECT_EQ(again[1]["first_vertex"], 0);
  EXPECT_EQ(cursor.generation, 2u);
  EXPECT_EQ(cursor.last_status, "kept");
}

TEST(SceneFeed, PastTheDrawLimitsTheFirstPartIsDrawnAndSaidSo) {
  ViewerCursor cursor;
  const auto sent = messages(path(10), 1, {4, 100, 100}, cursor);
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_EQ(sent[1]["vertices_sent"], 4);
  EXPECT_EQ(sent[1]["edges_sent"], 9);
  EXPECT_EQ(sent[1]["edges"].size(), 6u) << "only the edges among the 4 vertices drawn";
  EXPECT_EQ(sent[1]["note"], "drawing the first 4 of 10 vertices and 9 of 9 edges (the viewer's limit)");
  EXPECT_TRUE(messages(path(10), 1, {4, 100, 100}, cursor).empty());
}

}  // namespace
}  // namespace ispars::web
