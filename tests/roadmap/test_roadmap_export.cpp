// roadmap_export: PLY and GraphML of a roadmap small enough to write out by hand.

#include "ispars/roadmap/roadmap_export.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <vector>

#include "ispars/roadmap/roadmap_batch.hpp"

namespace ispars {
namespace {

Roadmap three_vertices() {
  Roadmap r(4);
  const std::vector<PoiId> two{1, 3};
  r.add_vertex(Vec3(0, 0, 0), two);
  r.add_vertex(Vec3(0.1, 2.5, -1), {});
  r.add_vertex(Vec3(3, 4, 0), std::vector<PoiId>{2});
  EXPECT_TRUE(r.add_edge(0, 2));
  EXPECT_TRUE(r.add_edge(1, 2));
  return r;
}

TEST(RoadmapExport, PlyListsEachVertexWithItsPoiCountThenEachEdge) {
  const Roadmap r = three_vertices();
  const std::string ply = roadmap_ply(r);
  const std::string body = ply.substr(ply.find("end_header\n") + 11);
  EXPECT_EQ(body, "0 0 0 2\n0.1 2.5 -1 0\n3 4 0 1\n0 2\n1 2\n") << "the shortest text of each double";
  EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex 3\n"), std::string::npos);
  EXPECT_NE(ply.find("element edge 2\n"), std::string::npos);
  EXPECT_NE(ply.find(fmt::format("4 POIs, digest {:#018x}", roadmap_digest(r))), std::string::npos) << ply;
}

TEST(RoadmapExport, GraphmlGivesNodesTheirPoisAndEdgesTheirLengths) {
  const std::string g = roadmap_graphml(three_vertices());
  EXPECT_NE(g.find("<node id=\"n0\"><data key=\"x\">0</data><data key=\"y\">0</data><data key=\"z\">0</data>"
                   "<data key=\"pois\">1 3</data></node>"),
            std::string::npos)
      << g;
  EXPECT_NE(g.find("<node id=\"n1\">"), std::string::npos);
  EXPECT_NE(g.find("<data key=\"pois\"></data>"), std::string::npos) << "a vertex seeing nothing";
  EXPECT_NE(g.find("<edge id=\"e0\" source=\"n0\" target=\"n2\"><data key=\"weight\">5</data></edge>"),
            std::string::npos)
      << "3-4-5";
  EXPECT_NE(g.find("edgedefault=\"undirected\""), std::string::npos);
  EXPECT_EQ(g.substr(g.size() - 22), "  </graph>\n</graphml>\n");
}

}  // namespace
}  // namespace ispars
