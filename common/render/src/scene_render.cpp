#include "ispars/render/scene_render.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/geometry/embree_scene.hpp"

namespace ispars::render {
namespace {

using Rgb = std::array<float, 3>;
constexpr Rgb kMesh{0.80f, 0.77f, 0.72f};
constexpr Rgb kRoadmap{0.10f, 0.33f, 0.85f};
constexpr Rgb kVertex{0.05f, 0.15f, 0.45f};
constexpr Rgb kDense{0.45f, 0.45f, 0.50f};
constexpr Rgb kTour{1.00f, 0.50f, 0.00f};
constexpr Rgb kSeen{0.10f, 0.70f, 0.20f};
constexpr Rgb kUnseen{0.90f, 0.10f, 0.10f};
constexpr Rgb kPoi{0.55f, 0.20f, 0.70f};  // no roadmap to say whether it is seen

// The camera's frame and projection.
struct View {
  Vec3 eye, forward, right, up;
  double tan_half = 1.0, aspect = 1.0;
  int width = 0, height = 0;

  View(const Camera& c, int w, int h) : eye(c.eye), width(w), height(h) {
    forward = (c.target - c.eye).normalized();
    right = forward.cross(c.up).normalized();
    if (!right.allFinite() || right.norm() < 0.5) right = forward.unitOrthogonal();
    up = right.cross(forward);
    tan_half = std::tan(c.fov_degrees * M_PI / 360.0);
    aspect = static_cast<double>(w) / h;
  }
  // The ray through pixel (x, y), scaled so that its forward component is 1 (t is depth).
  [[nodiscard]] Vec3 ray(double x, double y) const {
    return forward + right * ((2.0 * x / width - 1.0) * tan_half * aspect) + up * ((1.0 - 2.0 * y / height) * tan_half);
  }
  // Screen position and depth of p (depth <= 0: behind the camera).
  [[nodiscard]] Vec3 project(const Vec3& p) const {
    const Vec3 v = p - eye;
    const double z = v.dot(forward);
    return {(v.dot(right) / (z * tan_half * aspect) + 1.0) * 0.5 * width,
            (1.0 - v.dot(up) / (z * tan_half)) * 0.5 * height, z};
  }
};

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), color_(static_cast<std::size_t>(w) * h), depth_(color_.size(), kFar) {}
  static constexpr float kFar = std::numeric_limits<float>::infinity();

  Rgb& color(int x, int y) { return color_[static_cast<std::size_t>(y) * w_ + x]; }
  float& depth(int x, int y) { return depth_[static_cast<std::size_t>(y) * w_ + x]; }

  // Blends `c` into pixel (x, y) at depth z: strongly where nothing nearer hides it, faintly where
  // the mesh does.
  void plot(int x, int y, double z, const Rgb& c, float alpha, float hidden_alpha) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    const float a = z <= depth(x, y) * 1.004 + 0.02 ? alpha : hidden_alpha;
    Rgb& p = color(x, y);
    for (int k = 0; k < 3; ++k) p[k] = p[k] * (1.0f - a) + c[k] * a;
  }

  void line(const View& view, Vec3 a, Vec3 b, const Rgb& c, float alpha, float hidden_alpha, int brush) {
    // Clip to the space in front of the camera.
    constexpr double kNear = 1e-3;
    const double za = (a - view.eye).dot(view.forward), zb = (b - view.eye).dot(view.forward);
    if (za < kNear && zb < kNear) return;
    if (za < kNear) a = a + (b - a) * ((kNear - za) / (zb - za));
    if (zb < kNear) b = b + (a - b) * ((kNear - zb) / (za - zb));
    const Vec3 pa = view.project(a), pb = view.project(b);
    const double pixels = std::max(std::abs(pb.x() - pa.x()), std::abs(pb.y() - pa.y()));
    if (!std::isfinite(pixels) || pixels > 1e5) return;  // nearly edge-on to the eye: not drawable
    const int steps = static_cast<int>(std::ceil(pixels * 1.5)) + 1;
    int last_x = std::numeric_limits<int>::min(), last_y = last_x;
    for (int i = 0; i <= steps; ++i) {
      const Vec3 p = view.project(a + (b - a) * (static_cast<double>(i) / steps));
      const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
      if (x == last_x && y == last_y) continue;
      last_x = x;
      last_y = y;
      for (int dy = -brush; dy <= brush; ++dy) {
        for (int dx = -brush; dx <= brush; ++dx) plot(x + dx, y + dy, p.z(), c, alpha, hidden_alpha);
      }
    }
  }

  void disc(const View& view, const Vec3& at, int radius, const Rgb& c, float hidden_alpha) {
    const Vec3 p = view.project(at);
    if (p.z() <= 0) return;
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        if (dx * dx + dy * dy <= radius * radius) {
          plot(static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy, p.z() * 0.995, c, 1.0f, hidden_alpha);
        }
      }
    }
  }

  [[nodiscard]] Image image() const {
    Image out{w_, h_, std::vector<std::uint8_t>(color_.size() * 3)};
    for (std::size_t i = 0; i < color_.size(); ++i) {
      for (int k = 0; k < 3; ++k)
        out.rgb[3 * i + k] = static_cast<std::uint8_t>(std::clamp(color_[i][k], 0.0f, 1.0f) * 255.0f + 0.5f);
    }
    return out;
  }

 private:
  int w_, h_;
  std::vector<Rgb> color_;
  std::vector<float> depth_;
};

// Casts one ray per pixel: the mesh shaded by its facing to the eye and to a light above, or the
// background; fills the depth buffer.
void shade_mesh(const scene_files::TriangleMesh& mesh, const View& view, Canvas& canvas, int threads) {
  if (mesh.empty()) return;
  const planning::EmbreeScene bvh(mesh);
  const Vec3 light = (view.up * 0.8 + view.right * 0.4 - view.forward * 0.4).normalized();
  const auto rows = [&](int first, int step) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int y = first; y < view.height; y += step) {
      for (int x = 0; x < view.width; ++x) {
        const Vec3 d = view.ray(x + 0.5, y + 0.5);
        RTCRayHit hit{};
        hit.ray.org_x = static_cast<float>(view.eye.x());
        hit.ray.org_y = static_cast<float>(view.eye.y());
        hit.ray.org_z = static_cast<float>(view.eye.z());
        hit.ray.dir_x = static_cast<float>(d.x());
        hit.ray.dir_y = static_cast<float>(d.y());
        hit.ray.dir_z = static_cast<float>(d.z());
        hit.ray.tnear = 0.0f;
        hit.ray.tfar = std::numeric_limits<float>::infinity();
        hit.ray.mask = 0xFFFFFFFFu;
        hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(bvh.handle(), &context, &hit);
        if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        Vec3 n(hit.hit.Ng_x, hit.hit.Ng_y, hit.hit.Ng_z);
        n.normalize();
        const Vec3 to_eye = -d.normalized();
        if (n.dot(to_eye) < 0) n = -n;  // two-sided
        const float lit =
            static_cast<float>(0.30 + 0.45 * std::max(0.0, n.dot(to_eye)) + 0.30 * std::max(0.0, n.dot(light)));
        canvas.color(x, y) = {kMesh[0] * lit, kMesh[1] * lit, kMesh[2] * lit};
        canvas.depth(x, y) = hit.ray.tfar;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(rows, t, threads);
  rows(0, threads);
  for (auto& t : pool) t.join();
}

std::size_t draw_graph(const View& view, Canvas& canvas, const DrawnGraph& g, std::size_t max_edges, const Rgb& c,
                       float alpha, float hidden_alpha) {
  const std::size_t stride = max_edges == 0 ? g.edges.size() + 1 : (g.edges.size() + max_edges - 1) / max_edges;
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < g.edges.size(); i += std::max<std::size_t>(stride, 1)) {
    const EdgeEnds& e = g.edges[i];
    if (e.u >= g.positions.size() || e.v >= g.positions.size()) continue;
    canvas.line(view, g.positions[e.u], g.positions[e.v], c, alpha, hidden_alpha, 0);
    ++drawn;
  }
  return drawn;
}

}  // namespace

Camera framing_camera(const Aabb& box, double aspect) {
  Camera c;
  c.target = (box.min + box.max) * 0.5;
  const Vec3 direction = Vec3(0.55, -0.75, 0.42).normalized();  // from the front-right, above
  const View frame(Camera{c.target + direction, c.target, c.up, c.fov_degrees}, 1000, static_cast<int>(1000 / aspect));
  // The nearest eye on that line that keeps every corner of the box in the frame.
  double distance = 1e-3;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                      (k & 4) ? box.max.z() : box.min.z());
    const Vec3 v = corner - c.target;
    const double depth = v.dot(frame.forward);  // in front of the target: positive
    distance = std::max(distance, std::abs(v.dot(frame.right)) / (frame.tan_half * frame.aspect) - depth);
    distance = std::max(distance, std::abs(v.dot(frame.up)) / frame.tan_half - depth);
  }
  c.eye = c.target + direction * distance * 1.04;
  return c;
}

RenderResult render_scene(const scene_files::TriangleMesh& mesh, const RenderRequest& request) {
  if (request.width < 16 || request.width > 8192)
    throw params::InputError("render", "width", "must be 16..8192 pixels");
  if (request.height < 16 || request.height > 8192)
    throw params::InputError("render", "height", "must be 16..8192 pixels");
  RenderResult result;
  if (request.camera) {
    result.camera = *request.camera;
  } else {
    // The structure and the tour fill the picture; the roadmap around them is context.
    Aabb box{Vec3::Constant(std::numeric_limits<double>::max()), Vec3::Constant(std::numeric_limits<double>::lowest())};
    const auto grow = [&](const Vec3& p) {
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    };
    for (const auto& v : mesh.vertices) grow(v.cast<double>());
    for (const Vec3& p : request.tour) grow(p);
    if (!(box.min.array() <= box.max.array()).all()) {
      for (const Vec3& p : request.roadmap ? request.roadmap->positions : std::span<const Vec3>{}) grow(p);
    }
    if (!(box.min.array() <= box.max.array()).all()) box = Aabb{Vec3::Constant(-1), Vec3::Constant(1)};
    const Vec3 centre = (box.min + box.max) * 0.5;
    box = Aabb{centre + (box.min - centre) * 1.15, centre + (box.max - centre) * 1.15};
    result.camera = framing_camera(box, static_cast<double>(request.width) / request.height);
  }
  const Camera& c = result.camera;
  if (!c.eye.allFinite() || !c.target.allFinite() || (c.target - c.eye).norm() < 1e-9 || !(c.fov_degrees > 1.0) ||
      !(c.fov_degrees < 170.0)) {
    throw params::InputError("render", "camera",
                             "needs finite eye and target apart, and a field of view of 1..170 degrees");
  }
  const View view(c, request.width, request.height);
  Canvas canvas(request.width, request.height);
  for (int y = 0; y < request.height; ++y) {  // a soft sky
    const float s = static_cast<float>(y) / request.height;
    for (int x = 0; x < request.width; ++x)
      canvas.color(x, y) = {0.93f - 0.08f * s, 0.95f - 0.06f * s, 0.98f - 0.03f * s};
  }
  const int threads =
      request.threads > 0 ? request.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  shade_mesh(mesh, view, canvas, std::min(threads, 64));
  if (request.dense) {
    result.dense_edges_drawn = draw_graph(view, canvas, *request.dense, request.max_edges, kDense, 0.25f, 0.04f);
  }
  if (request.roadmap) {
    result.roadmap_edges_drawn = draw_graph(view, canvas, *request.roadmap, request.max_edges, kRoadmap, 0.40f, 0.10f);
    for (const Vec3& p : request.roadmap->positions) canvas.disc(view, p, 1, kVertex, 0.2f);
  }
  for (std::size_t i = 0; i < request.pois.size(); ++i) {
    const Rgb& colour = request.poi_seen.empty()                               ? kPoi
                        : (i < request.poi_seen.size() && request.poi_seen[i]) ? kSeen
                                                                               : kUnseen;
    canvas.disc(view, request.pois[i], 3, colour, 0.0f);
  }
  for (std::size_t i = 0; i + 1 < request.tour.size(); ++i) {
    canvas.line(view, request.tour[i], request.tour[i + 1], kTour, 1.0f, 0.45f, 1);
  }
  result.image = canvas.image();
  return result;
}

}  // namespace ispars::render
