// Pictures of scenes: the mesh is shaded where it is, lines in front of it are drawn and lines
// behind it are not, POIs show seen or unseen, large graphs are cut to an even subset, the
// automatic camera frames the whole box, and PNG files round-trip.

#include <gtest/gtest.h>

#include <filesystem>

#include "ispars/params/input_error.hpp"
#include "ispars/render/scene_render.hpp"
#include "support/test_support.hpp"

namespace ispars::render {
namespace {

// A 2 x 2 square in the plane z = 0, seen from straight above.
scene_files::TriangleMesh square() {
  scene_files::TriangleMesh mesh;
  mesh.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

Camera above() { return Camera{Vec3(0, 0, 5), Vec3::Zero(), Vec3::UnitY(), 45.0}; }

bool bluish(const std::uint8_t* p) { return p[2] > 150 && p[2] > p[0] + 60 && p[2] > p[1] + 40; }

// Pixels of the row through the picture's middle that are clearly the roadmap's blue.
int blue_pixels_in_middle_row(const Image& image) {
  int n = 0;
  for (int x = 0; x < image.width; ++x) n += bluish(image.pixel(x, image.height / 2)) ? 1 : 0;
  return n;
}

RenderRequest request_of(const Camera& camera) {
  RenderRequest r;
  r.width = 160;
  r.height = 120;
  r.camera = camera;
  r.threads = 2;
  return r;
}

TEST(SceneRender, TheMeshIsShadedWhereItIsAndTheSkyElsewhere) {
  const scene_files::TriangleMesh mesh = square();
  const RenderResult out = render_scene(mesh, request_of(above()));
  ASSERT_EQ(out.image.width, 160);
  ASSERT_EQ(out.image.height, 120);
  const std::uint8_t* centre = out.image.pixel(80, 60);
  const std::uint8_t* corner = out.image.pixel(2, 2);
  // The mesh is warm grey (red above blue); the sky is bluish white (blue above red).
  EXPECT_GT(centre[0], centre[2]) << int(centre[0]) << " " << int(centre[2]);
  EXPECT_GT(corner[2], corner[0]);
}

TEST(SceneRender, AnEdgeInFrontOfTheMeshIsDrawnAndOneBehindItIsNot) {
  const scene_files::TriangleMesh mesh = square();
  const std::vector<Vec3> positions = {{-0.8, 0, 0.5}, {0.8, 0, 0.5}, {-0.8, 0, -0.5}, {0.8, 0, -0.5}};
  const std::vector<EdgeEnds> in_front = {{0, 1}};
  const std::vector<EdgeEnds> behind = {{2, 3}};
  RenderRequest r = request_of(above());
  r.roadmap = DrawnGraph{positions, in_front};
  const RenderResult front = render_scene(mesh, r);
  EXPECT_EQ(front.roadmap_edges_drawn, 1u);
  EXPECT_GT(blue_pixels_in_middle_row(front.image), 40);  // about 51 pixels long
  r.roadmap = DrawnGraph{positions, behind};
  const RenderResult back = render_scene(mesh, r);
  EXPECT_EQ(back.roadmap_edges_drawn, 1u);
  EXPECT_EQ(blue_pixels_in_middle_row(back.image), 0) << "an edge under the square showed through it";
  // Without the mesh the same edge is in plain view.
  EXPECT_GT(blue_pixels_in_middle_row(render_scene(scene_files::TriangleMesh{}, r).image), 30);  // about 42
}

TEST(SceneRender, PoisShowSeenGreenAndUnseenRed) {
  const scene_files::TriangleMesh mesh = square();
  const std::vector<Vec3> pois = {{-0.5, 0, 0}, {0.5, 0, 0}};
  RenderRequest r = request_of(above());
  r.pois = pois;
  r.poi_seen = {true, false};
  const RenderResult out = render_scene(mesh, r);
  const auto at = [&](const Vec3& p) {
    const double f = 1.0 / std::tan(22.5 * M_PI / 180.0);  // the camera is 5 above the plane
    const double x = (p.x() * f / 5.0 / (160.0 / 120.0) + 1.0) * 80.0, y = (1.0 - p.y() * f / 5.0) * 60.0;
    return out.image.pixel(static_cast<int>(x), static_cast<int>(y));
  };
  const std::uint8_t* seen = at(pois[0]);
  const std::uint8_t* unseen = at(pois[1]);
  EXPECT_GT(seen[1], seen[0] + 80) << "not green";
  EXPECT_GT(unseen[0], unseen[1] + 80) << "not red";
}

TEST(SceneRender, AGraphOverTheEdgeLimitIsDrawnAsAnEvenSubset) {
  std::vector<Vec3> positions;
  std::vector<EdgeEnds> edges;
  for (int i = 0; i < 101; ++i) positions.emplace_back(-1 + 0.02 * i, 0.3, 0.2);
  for (VertexId i = 0; i < 100; ++i) edges.push_back({i, i + 1});
  RenderRequest r = request_of(above());
  r.dense = DrawnGraph{positions, edges};
  r.roadmap = DrawnGraph{positions, edges};
  r.max_edges = 10;
  const RenderResult out = render_scene(square(), r);
  EXPECT_EQ(out.roadmap_edges_drawn, 10u);
  EXPECT_EQ(out.dense_edges_drawn, 10u);
  r.max_edges = 1000;
  EXPECT_EQ(render_scene(square(), r).roadmap_edges_drawn, 100u);
}

TEST(SceneRender, TheAutomaticCameraFramesEveryCornerOfTheBox) {
  const Aabb box{Vec3(-40, -10, 0), Vec3(60, 30, 25)};
  for (const double aspect : {0.5, 4.0 / 3.0, 3.0}) {
    const Camera c = framing_camera(box, aspect);
    const Vec3 f = (c.target - c.eye).normalized(), right = f.cross(c.up).normalized(), up = right.cross(f);
    const double t = std::tan(c.fov_degrees * M_PI / 360.0);
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                        (k & 4) ? box.max.z() : box.min.z());
      const Vec3 v = corner - c.eye;
      ASSERT_GT(v.dot(f), 0.0);
      EXPECT_LE(std::abs(v.dot(right)) / v.dot(f), t * aspect * 1.0001) << "aspect " << aspect << " corner " << k;
      EXPECT_LE(std::abs(v.dot(up)) / v.dot(f), t * 1.0001) << "aspect " << aspect << " corner " << k;
    }
  }
}

TEST(SceneRender, BadSizesAndCamerasAreRefusedByName) {
  RenderRequest r = request_of(above());
  r.width = 8;
  try {
    (void)render_scene(square(), r);
    FAIL();
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.field(), "width");
  }
  r = request_of(Camera{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3::UnitZ(), 45.0});
  EXPECT_THROW((void)render_scene(square(), r), params::InputError);
  r = request_of(Camera{Vec3(0, 0, 5), Vec3::Zero(), Vec3::UnitZ(), 45.0});  // up along the view: still drawn
  EXPECT_NO_THROW((void)render_scene(square(), r));
}

TEST(SceneRender, PngFilesRoundTripAndAnUnwritablePathIsNamed) {
  test::TempDir dir;
  const RenderResult out = render_scene(square(), request_of(above()));
  const auto path = (dir.path() / "square.png").string();
  write_png(path, out.image);
  const Image back = read_png(path);
  EXPECT_EQ(back.width, out.image.width);
  EXPECT_EQ(back.height, out.image.height);
  EXPECT_EQ(back.rgb, out.image.rgb);
  const std::string missing = (dir.path() / "no-such-dir" / "x.png").string();
  try {
    write_png(missing, out.image);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)read_png(path + ".missing"), std::runtime_error);
}

}  // namespace
}  // namespace ispars::render
