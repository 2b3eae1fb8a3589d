#include "builder_handle.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "arrays.hpp"
#include "ispars/params/input_error.hpp"
#include "param_dict.hpp"
#include "verification_dict.hpp"

namespace ispars::python {
namespace {

constexpr const char* kBuild = "build";  // the InputError file of a Builder's arguments
constexpr std::int64_t kMaxThreads = 64;

double memory_limit_bytes(std::uint64_t mb) {
  if (mb != 0) return static_cast<double>(mb) * 1024.0 * 1024.0;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4.0 * 1024.0 * 1024.0 * 1024.0;  // unknown: 4 GiB
  return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

// "512 MiB" below a GiB, "3.5 GiB" from there.
std::string size_text(double bytes) {
  constexpr double kMiB = 1024.0 * 1024.0;
  return bytes < 1024.0 * kMiB ? fmt::format("{:.0f} MiB", bytes / kMiB)
                               : fmt::format("{:.1f} GiB", bytes / 1024.0 / kMiB);
}

}  // namespace

/// Marks the handle busy for one call; refuses a second call meanwhile.
class BuilderHandle::Busy {
 public:
  explicit Busy(std::atomic<bool>& busy) : busy_(busy) {
    if (busy_.exchange(true)) {
      throw std::runtime_error("the builder is in another call (extend or verify) on another thread; wait for it");
    }
  }
  ~Busy() { busy_ = false; }
  Busy(const Busy&) = delete;
  Busy& operator=(const Busy&) = delete;

 private:
  std::atomic<bool>& busy_;
};

BuilderHandle::BuilderHandle(std::shared_ptr<planning::Scene> scene, const std::string& method, std::uint64_t seed,
                             const std::string& variant, std::int64_t threads, const py::dict& overrides,
                             std::uint64_t memory_mb)
    : base_(std::move(scene)), memory_limit_(memory_limit_bytes(memory_mb)) {
  if (!base_) throw params::InputError(kBuild, "scene", "a Scene is required (Scene.load(path))");
  if (threads < 1 || threads > kMaxThreads) {
    throw params::InputError(kBuild, "threads", fmt::format("must be 1 .. {}, got {}", kMaxThreads, threads));
  }
  threads_ = static_cast<unsigned>(threads);
  BuildRequest request;
  set_method(request, method, variant, kBuild);
  request.seed = seed;
  request.samples = 1;  // extend() checks each call's count
  read_dict(overrides, request.overrides, kBuild, "overrides.");
  recipe_ = make_recipe(base_->config().name, *base_, request, kBuild);
  scene_ = std::make_unique<planning::Scene>(planning::recipe_scene(*base_, recipe_, kBuild));
  builder_ = planning::make_roadmap_builder(recipe_.method, *scene_, planning::recipe_build_options(recipe_, threads_));
}

std::uint64_t BuilderHandle::extend(std::int64_t samples, const std::shared_ptr<StopFlag>& stop,
                                    const py::object& progress) {
  if (samples < 1 || !params::problem(kSamples, static_cast<std::uint64_t>(samples)).empty()) {
    throw params::InputError(kBuild, "samples",
                             fmt::format("must be {}, got {}", params::range_text(kSamples), samples));
  }
  const Busy busy(busy_);
  if (const planning::BuildCost cost = expected_cost(static_cast<std::uint64_t>(samples)); cost.bytes > memory_limit_) {
    throw params::InputError(
        kBuild, "samples",
        fmt::format("the roadmap would hold about {} after {} more samples, past this Builder's memory limit of {} "
                    "(Builder(memory_mb=...); 0: half of this machine's memory)",
                    size_text(cost.bytes), samples, size_text(memory_limit_)));
  }
  roadmap_copy_.reset();
  dense_copy_.reset();
  auto halt = std::make_shared<Halt>();
  const Callback report(progress, halt);
  const auto total = static_cast<std::uint64_t>(samples);
  const auto work = [this, total, halt, report] {
    // Chunks of about a tenth of a second: a stop ends the call within one chunk. extend(a) then
    // extend(b) is extend(a + b), so chunking changes nothing in the roadmap.
    std::uint64_t chunk = 64;
    std::uint64_t done = 0;
    auto last_report = std::chrono::steady_clock::now();
    while (done < total && !halt->halted()) {
      const std::uint64_t n = std::min(chunk, total - done);
      const auto t0 = std::chrono::steady_clock::now();
      builder_->extend(n);
      done += n;
      const double took = seconds_since(t0);
      if (took < 0.05) chunk = std::min<std::uint64_t>(chunk * 2, 100'000);
      if (took > 0.2) chunk = std::max<std::uint64_t>(chunk / 2, 1);
      if (report && (done == total || seconds_since(last_report) >= 0.2)) {
        last_report = std::chrono::steady_clock::now();
        report(done, total, builder_->roadmap().vertex_count(), builder_->roadmap().edge_count());
      }
    }
    return done;
  };
  return run_stoppable(work, *halt, stop.get());
}

planning::BuildCost BuilderHandle::expected_cost(std::uint64_t samples) {
  py::gil_scoped_release release;
  if (free_fraction_ < 0.0) free_fraction_ = planning::free_fraction(*scene_);
  return planning::estimate_build_cost(*scene_, recipe_, builder_->samples() + samples, free_fraction_);
}

std::shared_ptr<Roadmap> BuilderHandle::roadmap() {
  const Busy busy(busy_);
  if (!roadmap_copy_) {
    py::gil_scoped_release release;
    roadmap_copy_ = std::make_shared<Roadmap>(builder_->roadmap());
  }
  return roadmap_copy_;
}

std::shared_ptr<Roadmap> BuilderHandle::dense() {
  const Busy busy(busy_);
  if (builder_->dense() == nullptr) return nullptr;
  if (!dense_copy_) {
    py::gil_scoped_release release;
    dense_copy_ = std::make_shared<Roadmap>(*builder_->dense());
  }
  return dense_copy_;
}

py::array_t<std::uint32_t> BuilderHandle::dense_ids() {
  const Busy busy(busy_);
  const std::span<const VertexId> ids = builder_->dense_ids();
  std::vector<std::uint32_t> out(ids.begin(), ids.end());
  const auto n = static_cast<py::ssize_t>(out.size());
  return take(std::move(out), {n});
}

py::dict BuilderHandle::verify(const std::shared_ptr<StopFlag>& stop) {
  const Busy busy(busy_);
  auto halt = std::make_shared<Halt>();
  const auto work = [this, halt] {
    return planning::verify_recipe_roadmaps(*scene_, recipe_, builder_->samples(), builder_->roadmap(),
                                            builder_->dense(), builder_->dense_ids(),
                                            [halt] { return !halt->halted(); });
  };
  const planning::VerificationReport r = run_stoppable(work, *halt, stop.get());
  const bool promised = planning::promises_invariant(recipe_.method);
  py::dict out = verification_dict(r, planning::broken_promises(r, promised), promised);
  out["invariant_drawn"] = r.invariant_drawn;
  return out;
}

py::dict BuilderHandle::recipe() const {
  py::dict out;
  out["scene"] = recipe_.scene;
  out["method"] = std::string(to_string(recipe_.method));
  out["variant"] = std::string(to_string(recipe_.variant));
  out["seed"] = recipe_.seed;
  write_dict(recipe_, out);
  return out;
}

void bind_builder(py::module_& m) {
  m.def("recipe_parameters", &declarations<RecipeOverrides>,
        "The parameters a build may override, as declared once for the daemon, the lab and Python: a list of "
        "dicts of name, type, min, max, range and doc.");
  py::class_<BuilderHandle, std::shared_ptr<BuilderHandle>>(
      m, "Builder",
      "A roadmap under construction, from a recipe: the method, its rule set, the seed and scene parameters "
      "overridden by name (dense_delta, sparse_delta, stretch, stretch_slack, stretch_slack_after, p_accept), "
      "checked as the daemon checks a build request. The same recipe gives the same roadmap as isparsd and "
      "ispars-lab, byte for byte, for any thread count.")
      .def(py::init([](const py::object& scene, const std::string& method, const py::object& seed,
                       const std::string& variant, const py::object& threads, const py::dict& overrides,
                       const py::object& memory_mb, const py::kwargs& named) {
             const auto mb =
                 to_whole_number(memory_mb, kBuild, kMemoryMb.name.data(), static_cast<std::int64_t>(kMemoryMb.min),
                                 static_cast<std::int64_t>(kMemoryMb.max));
             return std::make_shared<BuilderHandle>(
                 scene_of(scene, kBuild), method, to_unsigned_64(seed, kBuild, "seed"), variant,
                 to_whole_number(threads, kBuild, "threads", 1, kMaxThreads),
                 merged(overrides, named, kBuild, "overrides."), static_cast<std::uint64_t>(mb));
           }),
           py::arg("scene"), py::arg("method") = "ispars", py::arg("seed") = 1, py::arg("variant") = "",
           py::arg("threads") = 1, py::arg("overrides") = py::dict(), py::arg("memory_mb") = 0,
           "Each override by keyword (stretch=1.5) or in `overrides` (ispars.recipe_parameters() lists them). "
           "`scene` is a Scene or a scene file's path (str or os.PathLike). `memory_mb`: what the roadmap may be "
           "expected to hold (0: half of this machine's memory); an extend past it is refused before it starts. "
           "Raises InputError (file 'build') naming a bad scene, method, seed, variant, thread count, memory limit "
           "or override.")
      .def(
          "expected_cost",
          [](BuilderHandle& b, const py::object& samples) {
            const planning::BuildCost c = b.expected_cost(static_cast<std::uint64_t>(
                to_whole_number(samples, kBuild, "samples", 0, static_cast<std::int64_t>(kSamples.max))));
            py::dict out;
            out["vertices"] = c.vertices;
            out["edges"] = c.edges;
            out["bytes"] = c.bytes;
            out["memory_limit"] = b.memory_limit();
            return out;
          },
          py::arg("samples"),
          "The upper estimate (the daemon's) of the roadmap after `samples` more samples: a dict of vertices, "
          "edges and bytes, and this Builder's memory_limit in bytes; extend refuses what is past the limit.")
      .def(
          "extend",
          [](BuilderHandle& b, const py::object& samples, const std::shared_ptr<StopFlag>& stop,
             const py::object& progress) {
            return b.extend(to_whole_number(samples, kBuild, "samples", static_cast<std::int64_t>(kSamples.min),
                                            static_cast<std::int64_t>(kSamples.max)),
                            stop, progress);
          },
          py::arg("samples"), py::arg("stop") = nullptr, py::arg("progress") = py::none(),
          "Draws `samples` more samples of the seeded stream (1 .. 2^53), without the GIL. "
          "`progress(done, samples, vertices, edges)` is called about every 0.2 s. Stopped by `stop` or Ctrl-C, "
          "it keeps the samples drawn (extend again goes on with the same stream) and returns how many it drew "
          "(Ctrl-C raises KeyboardInterrupt once stopped).")
      .def_property_readonly("roadmap", &BuilderHandle::roadmap,
                             "A copy of the roadmap as built so far (the sparse one for spars, ispars, ispars2).")
      .def_property_readonly("dense", &BuilderHandle::dense, "A copy of the dense pair (spars, ispars), else None.")
      .def_property_readonly("dense_ids", &BuilderHandle::dense_ids,
                             "(V,) uint32: each roadmap vertex's vertex in the dense pair (empty without one).")
      .def_property_readonly("samples", &BuilderHandle::samples, "Samples drawn so far.")
      .def_property_readonly("scene", &BuilderHandle::base_scene, "The scene it was made on.")
      .def_property_readonly("recipe", &BuilderHandle::recipe, "The recipe: what makes this roadmap again.")
      .def("verify", &BuilderHandle::verify, py::arg("stop") = nullptr,
           "Checks exactly what the method promises (every vertex and edge; Invariant 1 for ispars over the dense "
           "pair, for ispars2 over its own samples drawn again). A dict of counts; 'violations' is 0 when verified.");
}

}  // namespace ispars::python
