// The roadmap file (roadmap_json.hpp): what roadmap_file_json writes, read_roadmap_file_graph
// reads back exactly, for either graph; a file that does not parse, lacks the graph or holds an
// inconsistent one is refused with the file and the field named.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

using test::mentions;

// Positions that are not short decimals, so a lossy number format would show.
Roadmap sample_roadmap() {
  Roadmap r(3);
  r.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{2});
  r.add_vertex(Vec3(1.0 / 3.0, -0.1, 1e-7), std::vector<PoiId>{0, 1});
  r.add_vertex(Vec3(12345.678901234567, 2.0 / 7.0, -5.5), std::vector<PoiId>{});
  r.add_edge(1, 0);
  r.add_edge(1, 2);
  return r;
}

const std::vector<Vec3> kPois{Vec3(1, 2, 3), Vec3(0.5, 0.25, 0.125), Vec3(-1, -1, -1)};

void expect_same(const RoadmapFileGraph& read, const Roadmap& written) {
  ASSERT_EQ(read.positions.size(), written.vertex_count());
  ASSERT_EQ(read.graph.vertex_count(), written.vertex_count());
  EXPECT_EQ(read.graph.poi_count(), kPois.size());
  for (VertexId v = 0; v < written.vertex_count(); ++v) {
    EXPECT_EQ(read.positions[v], written.position(v)) << "vertex " << v << ": bit for bit";
    const auto seen = read.graph.visible(v);
    EXPECT_EQ(std::vector<PoiId>(seen.begin(), seen.end()), written.visibility_table().ids(v)) << "vertex " << v;
  }
  ASSERT_EQ(read.graph.edge_count(), written.edge_count());
  for (std::size_t i = 0; i < written.edge_count(); ++i) {
    const RoadmapEdge a = read.graph.edges()[i], b = written.edge(i);
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
    EXPECT_EQ(a.cost, b.cost) << "edge " << i << ": bit for bit";
  }
}

TEST(RoadmapJson, RoundTripOfBothGraphs) {
  const test::TempDir dir;
  const Roadmap sparse = sample_roadmap();
  Roadmap dense = sample_roadmap();
  dense.add_vertex(Vec3(0.7, 0.7, 0.7), std::vector<PoiId>{1});
  dense.add_edge(3, 0);
  const std::string text = roadmap_file_json("water tower", Vec3(0, 0, 0), kPois, sparse, &dense);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << "one line";
  EXPECT_EQ(text.back(), '\n');
  EXPECT_TRUE(mentions(text, "\"scene\":\"water tower\"")) << text;
  const auto file = dir.write("r.json", text);
  expect_same(read_roadmap_file_graph(file, "roadmap"), sparse);
  expect_same(read_roadmap_file_graph(file, "dense"), dense);
}

TEST(RoadmapJson, WithoutDenseThereIsNoDenseGraph) {
  const test::TempDir dir;
  const Roadmap r = sample_roadmap();
  const auto file = dir.write("r.json", roadmap_file_json("s", Vec3(0, 0, 0), kPois, r, nullptr));
  expect_same(read_roadmap_file_graph(file, "roadmap"), r);
  try {
    (void)read_roadmap_file_graph(file, "dense");
    ADD_FAILURE() << "read a dense graph that was not written";
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.field(), "graphs.dense");
    EXPECT_TRUE(mentions(e.problem(), "missing")) << e.what();
  }
}

TEST(RoadmapJson, AnEmptyRoadmapRoundTrips) {
  const test::TempDir dir;
  const Roadmap empty(0);
  const auto file = dir.write("r.json", roadmap_file_json("s", Vec3(1, 2, 3), {}, empty, nullptr));
  const RoadmapFileGraph g = read_roadmap_file_graph(file, "roadmap");
  EXPECT_EQ(g.graph.vertex_count(), 0u);
  EXPECT_TRUE(g.positions.empty());
}

// The InputError reading `text` as a roadmap file throws for graph "roadmap".
params::InputError error_for(const std::string& text) {
  const test::TempDir dir;
  const auto file = dir.write("bad.json", text);
  try {
    (void)read_roadmap_file_graph(file, "roadmap");
  } catch (const params::InputError& e) {
    EXPECT_TRUE(mentions(e.file(), "bad.json")) << e.what();
    return e;
  }
  ADD_FAILURE() << "no InputError for " << text;
  return params::InputError("", "", "");
}

TEST(RoadmapJson, MalformedFilesAreNamedByField) {
  struct Case {
    std::string text, field, problem;
  };
  const std::string pois = R"("pois":[[0,0,0],[1,1,1]],)";
  const std::vector<Case> cases{
      {"{\"graphs\": ", "json", "parse error"},
      {"[1, 2]", "graphs.roadmap", "missing"},
      {R"({"graphs": []})", "graphs.roadmap", "missing"},
      {R"({"graphs": {"dense": {}}})", "graphs.roadmap", "missing"},
      {R"({"graphs": {"roadmap": {"vertices": [], "visible": []}}})", "graphs.roadmap", "malformed"},
      {R"({"graphs": {"roadmap": {"vertices": [[0, 0]], "visible": [[]], "edges": []}}})", "graphs.roadmap",
       "malformed"},
      {R"({"graphs": {"roadmap": {"vertices": [[0, 0, "a"]], "visible": [[]], "edges": []}}})", "graphs.roadmap",
       "malformed"},
      {"{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0]], "visible": [], "edges": []}}})",
       "graphs.roadmap.visible", "one POI list per vertex"},
      {"{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0]], "visible": [[2]], "edges": []}}})",
       "graphs.roadmap.visible", "POI 2 is beyond the 2 POIs"},
      {"{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0],[1,0,0]], "visible": [[],[]],
         "edges": [[0, 2, 1.0]]}}})",
       "graphs.roadmap.edges", "names a vertex beyond 2"},
      {"{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0],[1,0,0]], "visible": [[],[]],
         "edges": [[0, 1, -1.0]]}}})",
       "graphs.roadmap.edges", "has cost -1"},
      {"{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0],[1,0,0]], "visible": [[],[]],
         "edges": [[0, 1]]}}})",
       "graphs.roadmap", "malformed"},
  };
  for (const Case& c : cases) {
    const params::InputError e = error_for(c.text);
    EXPECT_EQ(e.field(), c.field) << c.text << "\n" << e.what();
    EXPECT_TRUE(mentions(e.problem(), c.problem)) << c.text << "\n" << e.what();
  }
}

TEST(RoadmapJson, AMissingFileIsNamed) {
  const test::TempDir dir;
  try {
    (void)read_roadmap_file_graph(dir.path() / "none.json", "roadmap");
    ADD_FAILURE() << "read a file that does not exist";
  } catch (const params::InputError& e) {
    EXPECT_TRUE(mentions(e.file(), "none.json"));
    EXPECT_EQ(e.field(), "file");
    EXPECT_EQ(e.problem(), "cannot be read");
  }
}

// A vertex id or POI id that is not an integer (1.5) is truncated to 1 by nlohmann's
// get<std::uint32_t>, so the file below reads as an edge 0-1 and a vertex seeing POI 1 instead
// of being refused. Disabled: read_roadmap_file_graph (roadmap_json.cpp) does not check that
// ids are unsigned integers (is_number_unsigned) before get<VertexId>() / get<PoiId>().
TEST(RoadmapJson, FractionalIdsAreRefused) {
  const std::string pois = R"("pois":[[0,0,0],[1,1,1]],)";
  const params::InputError edge = error_for("{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0],[1,0,0]],
      "visible": [[],[]], "edges": [[0, 1.5, 1.0]]}}})");
  EXPECT_EQ(edge.field(), "graphs.roadmap") << edge.what();
  const params::InputError poi = error_for("{" + pois + R"("graphs": {"roadmap": {"vertices": [[0,0,0],[1,0,0]],
      "visible": [[1.5],[]], "edges": []}}})");
  EXPECT_EQ(poi.field(), "graphs.roadmap") << poi.what();
}

}  // namespace
}  // namespace ispars
