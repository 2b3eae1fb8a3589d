#include "support/test_support.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include <unistd.h>

namespace ispars::test {

std::filesystem::path scenes_dir() { return ISPARS_SCENES_DIR; }

const std::vector<std::string>& shared_scene_names() {
  static const std::vector<std::string> names{"water_tower", "truss_bridge", "caric_city", "powerplant", "radio_tower"};
  return names;
}

const planning::Scene& shared_scene(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<planning::Scene>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[name];
  if (!slot) slot = std::make_unique<planning::Scene>(planning::Scene::load(scenes_dir() / (name + ".yaml")));
  return *slot;
}

planning::Scene open_scene(double delta, double big_delta, bool wall) {
  scene_files::TriangleMesh mesh;
  mesh.vertices = {{40, 40, 40}, {41, 40, 40}, {40, 41, 40}};
  mesh.triangles = {{0, 1, 2}};
  if (wall) {
    mesh.vertices.insert(mesh.vertices.end(), {{2.5, -1, -1}, {2.5, 1, -1}, {2.5, 1, 1}, {2.5, -1, 1}});
    mesh.triangles.insert(mesh.triangles.end(), {{3, 4, 5}, {3, 5, 6}});
  }
  scene_files::SceneConfig c;
  c.source = "test";
  c.bounds = {Vec3(-50, -50, -50), Vec3(50, 50, 50)};
  c.robot_radius = 0.1;
  c.sensor_range = 1;
  c.dense_delta = delta;
  c.sparse_delta = big_delta;
  c.stretch = 1.05;
  c.root = Vec3(0, 0, 0);
  c.pois = scene_files::PoiSource{3, 1, false, {}};
  return planning::Scene::build(c, mesh);
}

TempDir::TempDir() {
  static int counter = 0;
  path_ = std::filesystem::temp_directory_path() /
          ("ispars-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
  const auto file = path_ / name;
  std::ofstream(file) << text;
  return file;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void print_daemon_log_tails(const std::filesystem::path& dir, std::size_t lines) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    if (entry.path().extension() != ".log") continue;
    const std::string text = read_text(entry.path());
    std::size_t start = text.size();
    for (std::size_t seen = 0; start > 0; --start) {
      if (text[start - 1] == '\n' && ++seen > lines) break;  // the text after it is the tail
    }
    std::fprintf(stderr, "---- the last %zu lines of %s ----\n%s\n", lines, entry.path().string().c_str(),
                 text.substr(start).c_str());
  }
}

std::string thread_stacks(int pid) {
  const auto [code, out] = run_command("command -v gdb >/dev/null 2>&1 && timeout 60 gdb -p " + std::to_string(pid) +
                                       " -batch -ex 'thread apply all bt 24' 2>&1");
  if (code != 0 && out.empty()) return "(no stacks of process " + std::to_string(pid) + ": gdb is missing or failed)\n";
  return out;
}

std::pair<int, std::string> run_command(const std::string& command) {
  std::string output;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, ""};
  char buffer[512];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

double peak_rss_mib(int pid) {
  std::ifstream status(pid == 0 ? std::string("/proc/self/status") : "/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0.0;
      status >> kib;
      return kib / 1024.0;
    }
  }
  return 0.0;
}

std::string fingerprint(const Roadmap& roadmap) {
  std::ostringstream out;
  out << std::hexfloat;
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    const Vec3& p = roadmap.position(v);
    out << 'v' << p.x() << ' ' << p.y() << ' ' << p.z();
    for (const PoiId id : roadmap.visibility_table().ids(v)) out << ' ' << id;
    out << '\n';
  }
  for (const RoadmapEdge& e : roadmap.edges()) out << 'e' << e.u << ' ' << e.v << ' ' << e.cost << '\n';
  return out.str();
}

std::size_t scaled(std::size_t n) {
  static const double scale = [] {
    const char* text = std::getenv("ISPARS_TEST_QUERY_SCALE");
    const double value = text != nullptr ? std::atof(text) : 1.0;
    return value > 0.0 ? value : 1.0;
  }();
  const auto target = static_cast<std::size_t>(static_cast<double>(n) * scale);
  return std::max(target, std::min<std::size_t>(n, 20));
}

std::vector<Vec3> mixed_query_points(const planning::Scene& scene, scene_files::Rng& rng, std::size_t count) {
  const Aabb& box = scene.config().bounds;
  const double r = scene.config().robot_radius;
  const scene_files::TriangleMesh& mesh = scene.mesh();
  std::vector<Vec3> points;
  points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (i % 2 == 0) {
      points.push_back(rng.uniform_in(box));
      continue;
    }
    const std::size_t t = rng.below(mesh.triangle_count());
    const double r1 = std::sqrt(rng.uniform01());
    const double r2 = rng.uniform01();
    const Vec3 on = (1 - r1) * mesh.corner(t, 0) + r1 * (1 - r2) * mesh.corner(t, 1) + r1 * r2 * mesh.corner(t, 2);
    const Vec3 p = on + rng.uniform(0.0, 2.0 * r) * rng.unit_vector();
    points.push_back(p.cwiseMax(box.min).cwiseMin(box.max));
  }
  return points;
}

std::vector<TestSegment> mixed_query_segments(const planning::Scene& scene, scene_files::Rng& rng, std::size_t count) {
  const Aabb& box = scene.config().bounds;
  const std::vector<Vec3> starts = mixed_query_points(scene, rng, count);
  std::vector<TestSegment> segments;
  segments.reserve(count);
  for (const Vec3& a : starts) {
    const double length = rng.uniform(0.0, 1.0) * scene.config().dense_delta;
    const Vec3 b = (a + length * rng.unit_vector()).cwiseMax(box.min).cwiseMin(box.max);
    segments.push_back({a, b});
  }
  return segments;
}

}  // namespace ispars::test
