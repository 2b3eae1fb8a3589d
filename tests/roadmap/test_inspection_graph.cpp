// InspectionGraph (inspection_graph.hpp): from_edges, from_roadmap and read_iris on tiny inputs,
// with every bad input named by file, field (or line) and problem.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

using test::mentions;

// The InputError `f` throws; fails the test when it throws none.
template <class F>
params::InputError error_of(F&& f) {
  try {
    f();
  } catch (const params::InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return params::InputError("", "", "");
}

std::vector<VertexId> neighbor_ids(const InspectionGraph& g, VertexId v) {
  std::vector<VertexId> out;
  for (const Neighbor& n : g.neighbors(v)) out.push_back(n.vertex);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(InspectionGraph, FromEdgesKeepsEdgesBothWaysAndTidiesThePoiLists) {
  // 0-1 twice (2 and 0.5), 1-2, a self-loop at 2 (dropped); 3 alone.
  const std::vector<RoadmapEdge> edges{{0, 1, 2.0}, {1, 2, 1.0}, {2, 2, 0.0}, {1, 0, 0.5}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{3, 1, 3}, {}, {0}, {}}, 4);
  EXPECT_EQ(g.vertex_count(), 4u);
  EXPECT_EQ(g.edge_count(), 3u);
  EXPECT_EQ(g.poi_count(), 4u);
  EXPECT_EQ(std::vector<PoiId>(g.visible(0).begin(), g.visible(0).end()), (std::vector<PoiId>{1, 3}));
  EXPECT_EQ(neighbor_ids(g, 1), (std::vector<VertexId>{0, 0, 2}));
  EXPECT_EQ(neighbor_ids(g, 2), std::vector<VertexId>{1});
  EXPECT_TRUE(g.neighbors(3).empty());
  EXPECT_EQ(g.edge_cost(0, 1), 0.5) << "the cheapest of the parallel edges";
  EXPECT_EQ(g.edge_cost(2, 1), 1.0);
  EXPECT_LT(g.edge_cost(0, 2), 0.0) << "no edge";
  EXPECT_LT(g.edge_cost(2, 2), 0.0) << "the self-loop is gone";
  EXPECT_EQ(g.component_of(2), (std::vector<VertexId>{0, 1, 2}));
  EXPECT_EQ(g.component_of(3), std::vector<VertexId>{3});
}

TEST(InspectionGraph, FromEdgesNamesBadInput) {
  const auto build = [](std::vector<RoadmapEdge> edges, std::vector<std::vector<PoiId>> visible) {
    return [edges, visible] { (void)InspectionGraph::from_edges(2, edges, visible, 2); };
  };
  const params::InputError lists = error_of(build({}, {{}}));
  EXPECT_EQ(lists.field(), "visible");
  EXPECT_TRUE(mentions(lists.problem(), "one POI list per vertex")) << lists.what();

  const params::InputError beyond = error_of(build({{0, 2, 1.0}}, {{}, {}}));
  EXPECT_EQ(beyond.field(), "edges");
  EXPECT_TRUE(mentions(beyond.problem(), "edge 0-2 names a vertex beyond 2")) << beyond.what();

  for (const double cost : {-1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    const params::InputError bad_cost = error_of(build({{0, 1, cost}}, {{}, {}}));
    EXPECT_EQ(bad_cost.field(), "edges");
    EXPECT_TRUE(mentions(bad_cost.problem(), "edge 0-1 has cost")) << bad_cost.what();
  }

  const params::InputError poi = error_of(build({}, {{0}, {2}}));
  EXPECT_EQ(poi.field(), "visible");
  EXPECT_TRUE(mentions(poi.problem(), "POI 2 is beyond the 2 POIs")) << poi.what();
}

TEST(InspectionGraph, FromRoadmapCarriesVerticesEdgesCostsAndPois) {
  Roadmap r(5);
  r.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{4});
  r.add_vertex(Vec3(3, 4, 0), std::vector<PoiId>{0, 2});
  r.add_vertex(Vec3(3, 4, 2), std::vector<PoiId>{});
  r.add_edge(0, 1);
  r.add_edge(2, 1);
  const InspectionGraph g = InspectionGraph::from_roadmap(r);
  EXPECT_EQ(g.vertex_count(), 3u);
  EXPECT_EQ(g.poi_count(), 5u);
  EXPECT_EQ(std::vector<PoiId>(g.visible(1).begin(), g.visible(1).end()), (std::vector<PoiId>{0, 2}));
  EXPECT_EQ(std::vector<PoiId>(g.visible(0).begin(), g.visible(0).end()), std::vector<PoiId>{4});
  EXPECT_EQ(g.edge_cost(1, 0), 5.0);
  EXPECT_EQ(g.edge_cost(1, 2), 2.0);
  EXPECT_LT(g.edge_cost(0, 2), 0.0);
}

// IRIS text files: PREFIX_vertex ("index time_vis time_build poi ...") and PREFIX_edge
// ("source target checked valid time_fk time_cd cost").
struct IrisFiles {
  test::TempDir dir;
  std::filesystem::path prefix;
  IrisFiles(const std::string& vertices, const std::string& edges) : prefix(dir.path() / "g") {
    dir.write("g_vertex", vertices);
    dir.write("g_edge", edges);
  }
};

const std::string kVertices = "0 0.1 0.2\n\n1 0.1 0.2 3 1\n2 0.1 0.2 0\r\n";
const std::string kEdges = "0 1 1 1 0.01 0.02 1.5\n   \n1 2 1 0 0.01 0.02 2.5\n0 2 1 1 0 0 4\n";

TEST(InspectionGraph, ReadIrisReadsVerticesPoisAndValidEdges) {
  const IrisFiles files(kVertices, kEdges);
  const InspectionGraph g = InspectionGraph::read_iris(files.prefix, false);
  EXPECT_EQ(g.vertex_count(), 3u);
  EXPECT_EQ(g.poi_count(), 4u) << "the largest POI id + 1";
  EXPECT_TRUE(g.visible(0).empty());
  EXPECT_EQ(std::vector<PoiId>(g.visible(1).begin(), g.visible(1).end()), (std::vector<PoiId>{1, 3}));
  EXPECT_EQ(std::vector<PoiId>(g.visible(2).begin(), g.visible(2).end()), std::vector<PoiId>{0});
  EXPECT_EQ(g.edge_count(), 2u) << "the edge with valid = 0 is left out";
  EXPECT_EQ(g.edge_cost(0, 1), 1.5);
  EXPECT_EQ(g.edge_cost(0, 2), 4.0);
  EXPECT_LT(g.edge_cost(1, 2), 0.0);
  const InspectionGraph all = InspectionGraph::read_iris(files.prefix, true);
  EXPECT_EQ(all.edge_count(), 3u);
  EXPECT_EQ(all.edge_cost(1, 2), 2.5);
}

// The error read_iris throws for these files.
params::InputError iris_error(const std::string& vertices, const std::string& edges) {
  const IrisFiles files(vertices, edges);
  return error_of([&] { (void)InspectionGraph::read_iris(files.prefix, false); });
}

TEST(InspectionGraph, ReadIrisNamesTheVertexFileLineAndProblem) {
  struct Case {
    std::string vertices, field, problem;
  };
  const std::vector<Case> cases{
      {"", "file", "has no vertices"},
      {"0 0.1\n", "line 1", "expected 'index time_vis time_build poi ...'"},
      {"0 0 0\n2 0 0\n", "line 2", "vertex index 2 where 1 was expected"},
      {"1 0 0\n", "line 1", "vertex index 1 where 0 was expected"},
      {"0 0 0 1\n1 0 0 -3\n", "line 2", "POI id -3"},
      {"0 0 0 1 x\n", "line 1", "a POI id is not an integer"},
      {"0 0 0 1.5\n", "line 1", "a POI id is not an integer"},
  };
  for (const Case& c : cases) {
    const params::InputError e = iris_error(c.vertices, "");
    EXPECT_TRUE(mentions(e.file(), "g_vertex")) << e.what();
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_TRUE(mentions(e.problem(), c.problem)) << e.what();
  }
}

TEST(InspectionGraph, ReadIrisNamesTheEdgeFileLineAndProblem) {
  struct Case {
    std::string edges, field, problem;
  };
  const std::vector<Case> cases{
      {"0 1 1 1 0 0\n", "line 1", "expected 'source target checked valid time_fk time_cd cost'"},
      {"0 1 1 1 0 0 1\n0 3 1 1 0 0 1\n", "line 2", "edge 0-3 names a vertex outside 0..2"},
      {"-1 1 1 1 0 0 1\n", "line 1", "edge -1-1 names a vertex outside 0..2"},
      {"0 1 1 1 0 0 -2\n", "line 1", "cost -2 is not a finite length"},
      {"0 1 1 0 0 0 -2\n", "line 1", "cost -2"},  // checked even on an edge left out
  };
  for (const Case& c : cases) {
    const params::InputError e = iris_error(kVertices, c.edges);
    EXPECT_TRUE(mentions(e.file(), "g_edge")) << e.what();
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_TRUE(mentions(e.problem(), c.problem)) << e.what();
  }
}

TEST(InspectionGraph, ReadIrisNamesAMissingFile) {
  const test::TempDir dir;
  const params::InputError no_vertex = error_of([&] { (void)InspectionGraph::read_iris(dir.path() / "none", false); });
  EXPECT_TRUE(mentions(no_vertex.file(), "none_vertex")) << no_vertex.what();
  EXPECT_EQ(no_vertex.field(), "file");
  EXPECT_EQ(no_vertex.problem(), "cannot be read");
  dir.write("half_vertex", "0 0 0\n");
  const params::InputError no_edge = error_of([&] { (void)InspectionGraph::read_iris(dir.path() / "half", false); });
  EXPECT_TRUE(mentions(no_edge.file(), "half_edge")) << no_edge.what();
  EXPECT_EQ(no_edge.problem(), "cannot be read");
}

// A vertex index that is not an integer ("0.5") is read as index 0 followed by the time fields
// ".5" and the next number, which shifts every field after it: the vertex silently sees POI 2
// instead of the line being refused. Disabled: the parser reads the index with >> into an
// integer and does not check that the token ended there (inspection_graph.cpp, read_iris).
TEST(InspectionGraph, ReadIrisRefusesAVertexIndexThatIsNotAnInteger) {
  const params::InputError e = iris_error("0.5 1 2\n", "");
  EXPECT_EQ(e.field(), "line 1") << e.what();
}

}  // namespace
}  // namespace ispars
