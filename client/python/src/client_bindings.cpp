// ispars.Client: every request of the C++ client, each off the GIL; Ctrl-C returns at once.

#include <fmt/format.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>

#include "arrays.hpp"
#include "client_handle.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"
#include "ispars/wire/participant.hpp"
#include "param_dict.hpp"
#include "stoppable.hpp"
#include "tour_model.hpp"
#include "verification_dict.hpp"

namespace ispars::python {
namespace {

using client::Client;

constexpr const char* kClient = "client";

// A request's sample count, checked here as the daemon would check it (kSamples).
std::uint64_t sample_count(const py::object& value, const char* file) {
  return static_cast<std::uint64_t>(to_whole_number(value, file, "samples", static_cast<std::int64_t>(kSamples.min),
                                                    static_cast<std::int64_t>(kSamples.max)));
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : fallback;
}

ClientHandle connect(const py::object& domain, const std::string& profile_file, const std::string& profile_name,
                     const std::string& security, double timeout, const std::string& server) {
  client::ClientOptions o;
  const std::string domain_text = env_or("ISPARS_DOMAIN", "0");
  long d = 0;
  if (domain.is_none()) {
    char* end = nullptr;
    d = std::strtol(domain_text.c_str(), &end, 10);
    if (*end != '\0')
      throw params::InputError("ISPARS_DOMAIN", "domain", fmt::format("'{}' is not a number", domain_text));
  } else {
    d = static_cast<long>(to_whole_number(domain, kClient, "domain", 0, 232));
  }
  if (d < 0 || d > 232) throw params::InputError(kClient, "domain", fmt::format("must be 0 .. 232, got {}", d));
  if (!(timeout > 0 && timeout <= 3600))
    throw params::InputError(kClient, "timeout", fmt::format("must be in (0, 3600] s, got {}", timeout));
  o.participant.domain = static_cast<int>(d);
  o.participant.profile_file = profile_file.empty() ? env_or("ISPARS_PROFILE_FILE", "") : profile_file;
  o.participant.profile_name = profile_name;
  o.participant.security = security.empty() ? env_or("ISPARS_SECURITY", "") : security;
  o.participant.name = "ispars python";
  o.timeout = std::chrono::milliseconds(static_cast<long>(timeout * 1000));
  o.server = server;
  const std::string profile = o.participant.profile_file;  // a copy: o is moved into the client
  if (!profile.empty() && !std::ifstream(profile)) {
    throw params::InputError(profile, "profile_file", "cannot be read (a Fast DDS XML profiles file)");
  }
  py::gil_scoped_release release;
  try {
    return ClientHandle{std::make_shared<Client>(std::move(o))};
  } catch (const std::runtime_error& e) {
    // The participant's own words name a profiles file it could not load or a missing profile.
    if (!profile.empty() && std::string_view(e.what()).find(profile) != std::string_view::npos) {
      throw params::InputError(profile, "profile_file", e.what());
    }
    throw;
  }
}

py::dict scene_entry(const client::SceneEntry& e) {
  py::dict out;
  out["scene"] = e.scene;
  out["loaded"] = e.loaded;
  out["has_roadmap"] = e.has_roadmap;
  out["server_id"] = e.server_id;
  out["note"] = e.note;
  return out;
}

std::vector<std::pair<double, double>> pairs_of(const std::vector<double>& flat) {
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i + 1 < flat.size(); i += 2) out.emplace_back(flat[i], flat[i + 1]);
  return out;
}

// The daemon's tour as the one tour model (tour_model.hpp), with the reply's keys beside it.
py::dict daemon_tour_dict(client::TourReply&& r, double seconds) {
  client::Tour& t = r.tour;
  TourFields f;
  f.cost = t.cost;
  f.walk = std::move(t.walk);
  f.waypoints = std::move(t.waypoints);
  f.covered = t.covered;
  f.target_count = t.target_count;
  if (t.lower_bound > 0.0) f.lower_bound = t.lower_bound;  // 0 on the wire: none proven
  f.bound_complete = t.bound_complete;
  f.trace = pairs_of(t.trace);
  f.bound_trace = pairs_of(t.bound_trace);
  f.valid = t.valid;
  if (!t.valid) f.problem = "the daemon's validation of the walk or the flown tour failed";
  f.seconds = seconds;
  f.version = t.version;
  f.flown = true;  // the daemon always flies its tours
  f.shortcut_path = std::move(t.shortcut_path);
  f.shortcut_cost = t.shortcut_cost;
  f.flown_path = std::move(t.flown_path);
  f.flown_sees = std::move(t.flown_sees);
  f.flown_cost = t.flown_cost;
  for (const client::TourStage& s : t.stages) f.stages.push_back({s.name, s.cost, s.seconds});
  f.graph_vertices = t.graph_vertices;
  f.graph_edges = t.graph_edges;
  py::dict out = tour_dict(std::move(f));
  for (const auto& [key, value] : reply_dict(r)) out[key] = value;
  return out;
}

py::dict verify_dict(const client::VerifyReply& r) {
  py::dict out = verification_dict(r.verify, r.verify.violations, r.verify.invariant_promised);
  for (const auto& [key, value] : reply_dict(r)) out[key] = value;
  return out;
}

py::dict snapshot_dict(client::Snapshot&& s) {
  py::dict out;
  out["scene"] = s.scene;
  out["generation"] = s.generation;
  out["version"] = s.version;
  out["roadmap"] = std::make_shared<Roadmap>(std::move(s.roadmap));
  out["root"] = take_points({s.root}).attr("reshape")(3);
  out["pois"] = take_points(std::move(s.pois));
  out["status"] = s.status;
  return out;
}

void bind_status(py::module_& m) {
  using client::SceneStatus;
  py::class_<SceneStatus>(m, "SceneStatus", "A scene's status as its owning daemon published it.")
      .def_property_readonly(
          "state", [](const SceneStatus& s) { return std::string(client::to_string(s.state)); },
          "empty, idle, queued, replaying, building, failed or unloaded.")
      .def_readonly("scene", &SceneStatus::scene)
      .def_readonly("server_id", &SceneStatus::server_id)
      .def_readonly("method", &SceneStatus::method)
      .def_readonly("variant", &SceneStatus::variant)
      .def_readonly("seed", &SceneStatus::seed)
      .def_readonly("generation", &SceneStatus::generation)
      .def_readonly("accepted_generation", &SceneStatus::accepted_generation)
      .def_readonly("samples_done", &SceneStatus::samples_done)
      .def_readonly("samples_target", &SceneStatus::samples_target)
      .def_readonly("version", &SceneStatus::version)
      .def_readonly("vertices", &SceneStatus::vertices)
      .def_readonly("edges", &SceneStatus::edges)
      .def_readonly("components", &SceneStatus::components)
      .def_readonly("dense_vertices", &SceneStatus::dense_vertices)
      .def_readonly("dense_edges", &SceneStatus::dense_edges)
      .def_readonly("poi_count", &SceneStatus::poi_count)
      .def_readonly("pois_covered", &SceneStatus::pois_covered)
      .def_readonly("pois_covered_root", &SceneStatus::pois_covered_root)
      .def_readonly("dense_delta", &SceneStatus::dense_delta)
      .def_readonly("sparse_delta", &SceneStatus::sparse_delta)
      .def_readonly("stretch", &SceneStatus::stretch)
      .def_readonly("p_accept", &SceneStatus::p_accept)
      .def_readonly("last_error", &SceneStatus::last_error)
      .def_readonly("scene_fingerprint", &SceneStatus::scene_fingerprint)
      .def_readonly("tasks", &SceneStatus::tasks)
      .def("__repr__", [](const SceneStatus& s) {
        return fmt::format("<ispars.SceneStatus '{}' {} on {}: {} vertices, {} edges, {}/{} samples>", s.scene,
                           client::to_string(s.state), s.server_id, s.vertices, s.edges, s.samples_done,
                           s.samples_target);
      });
}

py::list list_scenes(const ClientHandle& self) {
  const auto entries = run_detached([self] { return self->list_scenes(); });
  py::list out;
  for (const auto& e : entries) out.append(scene_entry(e));
  return out;
}

void bind_requests(py::class_<ClientHandle>& c) {
  c.def("scenes", &list_scenes,
        "Every scene of every daemon on the domain: dicts of scene, loaded, has_roadmap, server_id, note.");
  const auto change = [&c](const char* name, client::Reply (Client::*call)(const std::string&), const char* doc) {
    c.def(
        name,
        [call](const ClientHandle& self, const std::string& scene) {
          return reply_dict(run_detached([self, call, scene] { return ((*self).*call)(scene); }));
        },
        py::arg("scene"), doc);
  };
  change("load", &Client::load, "Loads a scene of a daemon's scene directory (and its stored roadmap).");
  change("unload", &Client::unload, "Unloads a scene (its stored roadmap stays on disk).");
  change("cancel", &Client::cancel, "Cancels the scene's build or extend, keeping what it committed.");
  change("drop", &Client::drop, "Drops the scene's roadmap, stored copy included.");
  c.def(
      "build",
      [](const ClientHandle& self, const std::string& scene, const py::object& samples, const std::string& method,
         const py::object& seed, const std::string& variant, const py::dict& overrides, bool replace,
         const py::kwargs& named) {
        client::BuildArgs args;
        set_method(args, method, variant, "build");
        args.samples = sample_count(samples, "build");
        args.seed = to_unsigned_64(seed, "build", "seed");
        read_dict(merged(overrides, named, "build", "overrides."), args.overrides, "build", "overrides.");
        args.replace = replace;
        return reply_dict(run_detached([self, scene, args] { return self->build(scene, args); }));
      },
      py::arg("scene"), py::arg("samples"), py::arg("method") = "ispars", py::arg("seed") = 1, py::arg("variant") = "",
      py::arg("overrides") = py::dict(), py::arg("replace") = false,
      "Queues a build; each override by keyword (stretch=1.5) or in `overrides`. A bad name or a value out of "
      "its range raises InputError before anything is sent; the daemon checks every field against the scene "
      "(a refusal raises ClientError 'rejected' naming it). "
      "wait_idle() waits for it.");
  c.def(
      "extend",
      [](const ClientHandle& self, const std::string& scene, const py::object& count) {
        const std::uint64_t samples = sample_count(count, "extend");
        return reply_dict(run_detached([self, scene, samples] { return self->extend(scene, samples); }));
      },
      py::arg("scene"), py::arg("samples"), "Queues `samples` more samples of the roadmap's stream.");
  c.def(
      "stats",
      [](const ClientHandle& self, const std::string& scene) {
        return run_detached([self, scene] { return self->stats(scene); });
      },
      py::arg("scene"), "The scene's status (a SceneStatus).");
  c.def(
      "path",
      [](const ClientHandle& self, const std::string& scene, const py::object& from, const py::object& to) {
        const Vec3 a = to_vec3(from, "from");
        const Vec3 b = to_vec3(to, "to");
        client::PathReply r = run_detached([self, scene, a, b] { return self->path(scene, a, b); });
        py::dict out = reply_dict(r);
        out["length"] = r.path.length;
        out["waypoints"] = take_points(std::move(r.path.waypoints));
        return out;
      },
      py::arg("scene"), py::arg("start"), py::arg("goal"), "A collision-free path on the roadmap: length, waypoints.");
  c.def(
      "verify",
      [](const ClientHandle& self, const std::string& scene) {
        return verify_dict(run_detached([self, scene] { return self->verify(scene); }));
      },
      py::arg("scene"), "Checks the roadmap on the daemon; 'violations' is 0 when verified.");
  c.def(
      "snapshot",
      [](const ClientHandle& self, const std::string& scene) {
        return snapshot_dict(run_detached([self, scene] { return self->snapshot(scene); }));
      },
      py::arg("scene"),
      "The whole roadmap at one version: a dict of scene, generation, version, roadmap (a Roadmap), root, pois, "
      "status.");
}

void bind_tours_and_waits(py::class_<ClientHandle>& c) {
  c.def(
      "tour",
      [](const ClientHandle& self, const std::string& scene, double budget, const py::object& seed_value,
         const py::object& target_list, const std::string& task, const py::object& progress) {
        const std::uint64_t seed = to_unsigned_64(seed_value, "tour", "seed");
        std::vector<std::uint32_t> targets;
        for (const std::int64_t id : to_whole_numbers(target_list, "tour", "targets")) {
          if (id < 0 || id > std::numeric_limits<std::uint32_t>::max())
            throw params::InputError("tour", "targets", fmt::format("{} is not a POI id", id));
          targets.push_back(static_cast<std::uint32_t>(id));
        }
        if (const std::string problem = params::problem(kTourBudget, budget); !problem.empty())
          throw params::InputError("tour", "budget", problem);
        auto halt = std::make_shared<Halt>();
        const Callback report(progress, halt);
        const auto call = [self, scene, budget, seed, targets, task, report] {
          const auto on_progress = [report](double t, double cost, double bound) {
            report(t, cost, bound > 0.0 ? std::optional<double>(bound) : std::nullopt);  // 0: none yet
          };
          return task.empty() ? self->tour(scene, budget, seed, targets, on_progress)
                              : self->task_tour(scene, task, budget, seed, on_progress);
        };
        const auto t0 = std::chrono::steady_clock::now();
        client::TourReply r = run_detached(call);
        halt->rethrow();
        return daemon_tour_dict(std::move(r),
                                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      },
      py::arg("scene"), py::arg("budget") = 5.0, py::arg("seed") = 1, py::arg("targets") = py::list(),
      py::arg("task") = "", py::arg("progress") = py::none(),
      "An inspection tour searched and flown on the daemon for `budget` seconds (0 .. 3600); progress(seconds, "
      "cost, bound) from the first tour on as it improves (bound None until one is proven). Targets default to "
      "every POI seen from the root's component; `task` aims at one inspection task. Returns the tour model "
      "ispars.tour returns (docs/python.md, 'Tours') with the reply's server_id, message and status.");
  c.def(
      "wait_idle",
      [](const ClientHandle& self, const std::string& scene, double timeout, const py::object& progress) {
        if (!(timeout > 0))
          throw params::InputError(kClient, "timeout", fmt::format("must be positive, got {}", timeout));
        auto halt = std::make_shared<Halt>();
        const Callback report(progress, halt);
        const auto call = [self, scene, timeout, report] {
          return self->wait_idle(
              scene, [report](const client::SceneStatus& s) { report(s); },
              std::chrono::milliseconds(static_cast<long>(timeout * 1000)));
        };
        client::SceneStatus s = run_detached(call);
        halt->rethrow();
        return s;
      },
      py::arg("scene"), py::arg("timeout") = 600.0, py::arg("progress") = py::none(),
      "Waits until the scene has no job; progress(status) on each status seen. Raises ClientError 'timeout'.");
  c.def(
      "_bench_stats",
      [](const ClientHandle& self, const std::string& scene, std::int64_t count) {
        // The benchmark's C++ side: `count` stats calls from C++ alone, each timed (seconds).
        py::gil_scoped_release release;
        std::vector<double> seconds;
        for (std::int64_t i = 0; i < count; ++i) {
          const auto t0 = std::chrono::steady_clock::now();
          (void)self->stats(scene);
          seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        return seconds;
      },
      py::arg("scene"), py::arg("count"), "For bench_python.py: `count` STATS round trips timed in C++ alone.");
  c.def_property_readonly(
      "id",
      [](const ClientHandle& self) {
        py::gil_scoped_release release;  // a callback on a client thread may be waiting for the GIL
        return self->id();
      },
      "This client's identity: its participant's GUID prefix, as daemons read it.");
}

}  // namespace

py::dict reply_dict(const client::Reply& reply) {
  py::dict out;
  out["server_id"] = reply.server_id;
  out["message"] = reply.message;
  out["status"] = reply.status;
  return out;
}

void route_logs() {
  auto logger = spdlog::stderr_logger_mt("ispars-python");
  logger->set_pattern("ispars: %l: %v");
  logger->set_level(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  wire::route_fastdds_log_to_spdlog(/*warnings=*/false);
  // Fast DDS logs from a thread of its own that outlives the interpreter's teardown of spdlog.
  py::module_::import("atexit").attr("register")(py::cpp_function([] { wire::stop_fastdds_log_routing(); }));
}

void bind_client(py::module_& m) {
  bind_status(m);
  py::class_<ClientHandle> c(
      m, "Client",
      "A connection to every isparsd on a DDS domain. Calls go to each scene's owner, with retries and a "
      "timeout, without the GIL; Ctrl-C returns at once (a request already sent ends by itself). Refusals "
      "raise ClientError with the daemon's named message.");
  c.def(py::init(&connect), py::arg("domain") = py::none(), py::arg("profile_file") = "",
        py::arg("profile_name") = "ispars", py::arg("security") = "", py::arg("timeout") = 15.0, py::arg("server") = "",
        "Joins `domain` (default: $ISPARS_DOMAIN, else 0). `profile_file` a Fast DDS XML profiles file (default: "
        "$ISPARS_PROFILE_FILE, else localhost only); `security` a DDS Security identity directory (default: "
        "$ISPARS_SECURITY, else none).");
  bind_requests(c);
  bind_tours_and_waits(c);
  const auto close = [](ClientHandle& self) {
    std::shared_ptr<client::Client> gone = std::move(self.client);
    py::gil_scoped_release release;  // its threads may wait for the GIL to end a callback
    gone.reset();
  };
  c.def("close", close,
        "Leaves the domain: this object's calls raise RuntimeError from now on. Watches made from it hold the "
        "connection until they end too. Called again it does nothing.");
  c.def_property_readonly("closed", [](const ClientHandle& self) { return !self.client; });
  c.def("__enter__", [](py::object self) { return self; });
  c.def("__exit__", [close](ClientHandle& self, const py::args&) {
    close(self);
    return false;
  });
}

}  // namespace ispars::python
