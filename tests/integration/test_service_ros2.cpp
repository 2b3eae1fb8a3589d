// isparsd --ros2 as a ROS 2 viewer sees it: the test reads rt/ispars/s0/roadmap and
// rt/ispars/s0/tour as raw bytes under the ROS 2 type names only (a reader of any other name or
// topic would match nothing), and hands each sample to tests/readers/decode_ros2.cjs, which decodes
// it with Foxglove's ROS 2 CDR reader and the ROS 2 message definitions, nothing of this project.
// The decoded markers must be the roadmap the daemon's snapshot holds, vertex for vertex and edge
// for edge; the path the tour the client was given; an unload clears the markers; a daemon
// without --ros2 publishes nothing there.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "integration/service_fixture.hpp"
#include "support/raw_sample_reader.hpp"

namespace ispars::test {
namespace {

constexpr const char* kMarkerArray = "visualization_msgs::msg::dds_::MarkerArray_";
constexpr const char* kPath = "nav_msgs::msg::dds_::Path_";

class Ros2Test : public ServiceTest {
 protected:
  // `bytes` decoded by the independent decoder as the ROS 2 message `type` (e.g. nav_msgs/Path).
  nlohmann::json decode(const std::string& type, const std::string& bytes) {
    const std::filesystem::path file = dir_.path() / ("sample-" + std::to_string(++decoded_) + ".cdr");
    {
      std::ofstream out(file, std::ios::binary);
      out << bytes;
    }
    const auto [status, output] =
        run_command("NODE_PATH='" + std::string(ISPARS_READERS_NODE_MODULES) + "' timeout -k 5 60 node '" +
                    ISPARS_READERS_DIR + "/decode_ros2.cjs' " + type + " '" + file.string() + "' 2>&1");
    if (status != 0) throw std::runtime_error("the decoder failed (" + std::to_string(status) + "): " + output);
    return nlohmann::json::parse(output);
  }

  // The latest sample of `reader`, decoded as `type`, once `done` holds of it (nullopt after 30 s).
  std::optional<nlohmann::json> latest_until(RawSampleReader& reader, const std::string& type,
                                             const std::function<bool(const nlohmann::json&)>& done) {
    std::string last;
    std::optional<nlohmann::json> decoded;
    const bool ok = eventually(
        [&] {
          const std::vector<std::string> samples = reader.take();
          if (samples.empty() || samples.back() == last) return false;
          last = samples.back();
          decoded = decode(type, last);
          return done(*decoded);
        },
        std::chrono::seconds(30), "the latest " + type + " sample", std::chrono::milliseconds(200));
    return ok ? decoded : std::nullopt;
  }

  std::size_t decoded_ = 0;
};

// The marker of namespace `ns` in a decoded MarkerArray (a null json when there is none).
nlohmann::json marker(const nlohmann::json& array, const std::string& ns) {
  for (const auto& m : array.at("markers")) {
    if (m.at("ns") == ns) return m;
  }
  return {};
}

Vec3 point(const nlohmann::json& p) {
  return {p.at("x").get<double>(), p.at("y").get<double>(), p.at("z").get<double>()};
}

TEST_F(Ros2Test, AViewerDecodesTheRoadmapAndTheTourWithTheRos2DefinitionsAlone) {
  auto daemon = start("d", {"--ros2", "--ros2-frame", "inspection"});
  Client client(client_options(domain_));
  const SceneStatus built = load_and_build(client, "s0", ispars_build(3000));
  RawSampleReader roadmaps(domain_, "rt/ispars/s0/roadmap", kMarkerArray);
  const auto markers = latest_until(roadmaps, "visualization_msgs/MarkerArray", [&](const nlohmann::json& a) {
    const nlohmann::json v = marker(a, "vertices");
    return !v.is_null() && v.at("points").size() == built.vertices;
  });
  ASSERT_TRUE(markers) << "no marker array with " << built.vertices << " vertices came (matched: " << roadmaps.matched()
                       << ")";
  const client::Snapshot snapshot = client.snapshot("s0");
  const nlohmann::json vertices = marker(*markers, "vertices"), edges = marker(*markers, "edges"),
                       pois = marker(*markers, "pois");
  EXPECT_EQ(vertices.at("type"), 7) << "SPHERE_LIST";
  EXPECT_EQ(edges.at("type"), 5) << "LINE_LIST";
  EXPECT_EQ(pois.at("type"), 8) << "POINTS";
  EXPECT_EQ(vertices.at("header").at("frame_id"), "inspection");
  EXPECT_EQ(vertices.at("pose").at("orientation").at("w"), 1.0);
  ASSERT_EQ(vertices.at("points").size(), snapshot.roadmap.vertex_count());
  for (std::size_t v = 0; v < snapshot.roadmap.vertex_count(); ++v) {
    ASSERT_EQ(point(vertices.at("points")[v]), snapshot.roadmap.position(static_cast<VertexId>(v))) << "vertex " << v;
  }
  ASSERT_EQ(edges.at("points").size(), 2 * built.edges) << "two points an edge, as many edges as stats gives";
  for (std::size_t e = 0; e < built.edges; ++e) {
    const EdgeEnds ends = snapshot.roadmap.edge_ends()[e];
    ASSERT_EQ(point(edges.at("points")[2 * e]), snapshot.roadmap.position(ends.u)) << "edge " << e;
    ASSERT_EQ(point(edges.at("points")[2 * e + 1]), snapshot.roadmap.position(ends.v)) << "edge " << e;
  }
  ASSERT_EQ(pois.at("points").size(), built.poi_count);
  std::size_t green = 0;
  for (const auto& c : pois.at("colors")) green += c.at("g").get<double>() > 0.5 ? 1 : 0;
  EXPECT_EQ(green, built.pois_covered) << "a green POI for each one some vertex sees";

  RawSampleReader tours(domain_, "rt/ispars/s0/tour", kPath);
  const client::Tour tour = client.tour("s0", 1.0, 1, {}).tour;
  ASSERT_FALSE(tour.flown_path.empty());
  const auto path = latest_until(
      tours, "nav_msgs/Path", [&](const nlohmann::json& p) { return p.at("poses").size() == tour.flown_path.size(); });
  ASSERT_TRUE(path) << "no path of the tour's " << tour.flown_path.size() << " stops came";
  EXPECT_EQ(path->at("header").at("frame_id"), "inspection");
  for (std::size_t i = 0; i < tour.flown_path.size(); ++i) {
    EXPECT_EQ(point(path->at("poses")[i].at("pose").at("position")), tour.flown_path[i]) << "stop " << i;
  }

  client.unload("s0");
  const auto cleared = latest_until(roadmaps, "visualization_msgs/MarkerArray", [](const nlohmann::json& a) {
    return a.at("markers").size() == 1 && a.at("markers")[0].at("action") == 3;
  });
  EXPECT_TRUE(cleared) << "an unload sends one DELETEALL marker";
  EXPECT_EQ(daemon->terminate(), 0);
}

TEST_F(Ros2Test, ADaemonWithoutTheSwitchPublishesNoRos2Topic) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  (void)load_and_build(client, "s0", ispars_build(800));
  RawSampleReader roadmaps(domain_, "rt/ispars/s0/roadmap", kMarkerArray);
  // Matching is what a sample would need first; 3 s is three leases of the localhost profile.
  EXPECT_FALSE(eventually([&] { return roadmaps.matched(); }, std::chrono::seconds(3), "a ROS 2 writer",
                          std::chrono::milliseconds(100)));
  EXPECT_EQ(daemon->terminate(), 0);
}

}  // namespace
}  // namespace ispars::test
