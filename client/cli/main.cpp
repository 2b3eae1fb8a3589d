// `ispars`: the command-line client of isparsd.

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <iostream>

#include "cli_output.hpp"
#include "ispars/client/client.hpp"
#include "render_command.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/wire/convert.hpp"

namespace {

using ispars::client::Client;
using ispars::client::ClientError;
namespace msg = ispars::msg;
using ispars::cli::print_status;
using ispars::cli::Progress;
using ispars::cli::status_json;
using ispars::cli::write_text;

std::atomic<bool> g_interrupted{false};

}  // namespace

int main(int argc, char** argv) {
  // Warnings from the client library (a peer dropped under DDS Security, say) go to stderr, never
  // into the command's output (--json included).
  spdlog::set_default_logger(spdlog::stderr_color_mt("ispars"));
  CLI::App app{"ispars: client of the isparsd roadmap service"};
  app.require_subcommand(1);
  ispars::client::ClientOptions options;
  int domain = 0;
  double timeout_s = 15;
  std::string profile_file, profile_name = "ispars", security;
  app.add_option("--domain", domain, "DDS domain id")->envname("ISPARS_DOMAIN")->check(CLI::Range(0, 232));
  app.add_option("--profile-file", profile_file, "Fast DDS XML profiles file (default: built-in localhost only)")
      ->envname("ISPARS_PROFILE_FILE");
  app.add_option("--profile-name", profile_name, "participant profile in the profiles file");
  app.add_option("--security", security,
                 "DDS Security identity directory (deploy/security/make-keystore.sh); default: no security")
      ->envname("ISPARS_SECURITY");
  app.add_option("--timeout", timeout_s, "seconds to wait for a daemon and each reply")->check(CLI::PositiveNumber);
  app.add_option("--server", options.server, "the daemon to load a scene on, when several offer it");

  auto* scenes = app.add_subcommand("scenes", "list, load or unload scenes");
  scenes->require_subcommand(1);
  auto* scenes_list = scenes->add_subcommand("list", "scenes of every daemon");
  bool list_json = false;
  scenes_list->add_flag("--json", list_json, "one JSON object");
  std::string scene;
  auto* scenes_load = scenes->add_subcommand("load", "load a scene (and its stored roadmap)");
  scenes_load->add_option("scene", scene, "scene name")->required();
  auto* scenes_unload = scenes->add_subcommand("unload", "unload a scene (its stored roadmap stays)");
  scenes_unload->add_option("scene", scene, "scene name")->required();

  ispars::client::BuildArgs build_args;
  bool wait = false;
  bool json = false;
  std::vector<std::string> sets;
  auto* build = app.add_subcommand("build", "build a new roadmap");
  build->add_option("scene", scene, "scene name")->required();
  build->add_option("--method", build_args.method, ispars::build_method_names())->required();
  build->add_option("--variant", build_args.variant, "spars, ispars: the rule set, " + ispars::spars_variant_names() +
                                                         " (default stretch)");
  build->add_option("--samples", build_args.samples, "samples to draw")->required()->check(CLI::PositiveNumber);
  build->add_option("--seed", build_args.seed, "random seed");
  build->add_flag("--replace", build_args.replace, "replace an existing roadmap");
  std::string set_help = "parameter override NAME=VALUE, one of:";
  for (const ispars::RecipeParameter& p : ispars::recipe_overrides()) {
    set_help += fmt::format("\n    {}: {}; {}", p.name, p.doc, p.range);
  }
  build->add_option("--set", sets, set_help);
  build->add_flag("--wait", wait, "follow progress until the build ends");
  build->add_flag("--json", json, "print the final status as JSON");

  std::uint64_t extend_samples = 0;
  auto* extend = app.add_subcommand("extend", "add samples to a roadmap");
  extend->add_option("scene", scene, "scene name")->required();
  extend->add_option("--samples", extend_samples, "more samples")->required()->check(CLI::PositiveNumber);
  extend->add_flag("--wait", wait, "follow progress until the extension ends");
  extend->add_flag("--json", json, "print the final status as JSON");

  auto* cancel = app.add_subcommand("cancel", "stop a running build after its current chunk");
  cancel->add_option("scene", scene, "scene name")->required();
  auto* stats = app.add_subcommand("stats", "a scene's roadmap status");
  stats->add_option("scene", scene, "scene name")->required();
  stats->add_flag("--json", json, "one JSON object");
  auto* drop = app.add_subcommand("drop", "delete a scene's roadmap");
  drop->add_option("scene", scene, "scene name")->required();
  auto* verify = app.add_subcommand("verify", "check a roadmap (validity, costs, Invariant 1)");
  verify->add_option("scene", scene, "scene name")->required();

  std::vector<double> from, to;
  auto* path = app.add_subcommand("path", "shortest path through the roadmap");
  path->add_option("scene", scene, "scene name")->required();
  path->add_option("--from", from, "start X Y Z")->required()->expected(3);
  path->add_option("--to", to, "goal X Y Z")->required()->expected(3);
  path->add_flag("--json", json, "one JSON object");

  std::string dump, out;
  bool until_idle = false;
  auto* watch = app.add_subcommand("watch", "follow a roadmap live (a replica kept from update batches)");
  watch->add_option("scene", scene, "scene name")->required();
  watch->add_option("--dump", dump, "write the replica to FILE on exit (the ispars-lab build --out JSON)");
  watch->add_flag("--until-idle", until_idle, "exit when the scene has no job and the replica is current");

  double budget = 10;
  std::uint64_t tour_seed = 1;
  std::vector<std::uint32_t> targets;
  auto* tour = app.add_subcommand("tour", "an inspection tour on the scene's roadmap, searched by the daemon");
  tour->add_option("scene", scene, "scene name")->required();
  tour->add_option("--budget", budget, "seconds of search")->required()->check(CLI::Range(0.001, 3600.0));
  tour->add_option("--seed", tour_seed, "search seed");
  tour->add_option("--targets", targets, "POI ids to see (default: every POI seen from the root's component)")
      ->delimiter(',');
  tour->add_flag("--json", json, "one JSON object");
  tour->add_option("--out", out, "write the tour (walk, positions, trace) as JSON");

  auto* snapshot = app.add_subcommand("snapshot", "fetch the whole roadmap");
  snapshot->add_option("scene", scene, "scene name")->required();
  snapshot->add_option("--out", out, "JSON file to write")->required();

  ispars::cli::RenderArgs render_args;
  auto* render = ispars::cli::add_render_command(app, render_args);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars: " << e.what() << " (see --help)\n";
    return 2;
  }
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    char* end = nullptr;
    const double value = eq == std::string::npos ? 0.0 : std::strtod(s.c_str() + eq + 1, &end);
    if (eq == std::string::npos || eq == 0 || end == s.c_str() + eq + 1 || *end != '\0') {
      std::cerr << "ispars: --set: '" << s << "' is not NAME=NUMBER\n";
      return 2;
    }
    build_args.overrides[s.substr(0, eq)] = value;
  }

  options.participant.domain = domain;
  options.participant.profile_file = profile_file;
  options.participant.profile_name = profile_name;
  options.participant.security = security;
  options.participant.name = "ispars cli";
  options.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
  const auto long_wait = std::chrono::hours(24 * 365);

  try {
    Client client(options);
    if (*scenes_list) {
      const auto entries = client.list_scenes();
      if (list_json) {
        nlohmann::json list = nlohmann::json::array();
        for (const auto& e : entries) {
          list.push_back({{"name", e.scene().to_string()}, {"server_id", e.server_id().to_string()}, {"loaded", e.loaded()},
                          {"has_roadmap", e.has_roadmap()}, {"note", e.note()}});
        }
        std::cout << nlohmann::json{{"scenes", list}}.dump() << std::endl;
      } else {
        for (const auto& e : entries) {
          std::cout << fmt::format("{:<24} {:<28} {}{}{}\n", e.scene().to_string(), e.server_id().to_string(),
                                   e.loaded() ? "loaded" : "-", e.has_roadmap() ? ", stored roadmap" : "",
                                   e.note().empty() ? "" : "\n    " + e.note());
        }
      }
    } else if (*scenes_load) {
      const msg::Reply r = client.load(scene);
      std::cout << r.message() << "\n";
      print_status(r.status());
    } else if (*scenes_unload) {
      std::cout << client.unload(scene).message() << "\n";
    } else if (*build || *extend) {
      const msg::Reply r = *build ? client.build(scene, build_args) : client.extend(scene, extend_samples);
      if (!json) std::cout << r.message() << "\n";
      msg::SceneStatus final_status = r.status();
      if (wait) {
        Progress progress(!json);
        final_status = client.wait_idle(scene, [&](const msg::SceneStatus& s) { progress(s); }, long_wait);
        progress.finish();
      }
      if (json) {
        std::cout << status_json(final_status).dump() << std::endl;
      } else if (wait) {
        print_status(final_status);
      }
      if (wait && final_status.state() == msg::SCENE_FAILED) return 1;
    } else if (*cancel) {
      std::cout << client.cancel(scene).message() << "\n";
    } else if (*stats) {
      const msg::SceneStatus s = client.stats(scene);
      if (json) {
        std::cout << status_json(s).dump() << std::endl;
      } else {
        print_status(s);
      }
    } else if (*drop) {
      std::cout << client.drop(scene).message() << "\n";
    } else if (*verify) {
      const msg::Reply r = client.verify(scene);
      const std::uint64_t violations = r.body().verify().violations();
      std::cout << (violations == 0 ? "verified: " : "NOT verified: ") << r.message() << "\n";
      return violations == 0 ? 0 : 1;
    } else if (*path) {
      const msg::Reply reply = client.path(scene, {from[0], from[1], from[2]}, {to[0], to[1], to[2]});
      const msg::PathResult& r = reply.body().path();
      if (json) {
        nlohmann::json points = nlohmann::json::array();
        for (const auto& p : r.waypoints()) points.push_back({p.x(), p.y(), p.z()});
        std::cout << nlohmann::json{{"scene", scene}, {"length", r.length()}, {"waypoints", points}}.dump() << std::endl;
      } else {
        std::cout << fmt::format("path of length {:.3f} through {} waypoints\n", r.length(), r.waypoints().size());
        for (const auto& p : r.waypoints()) std::cout << fmt::format("  {:.3f} {:.3f} {:.3f}\n", p.x(), p.y(), p.z());
      }
    } else if (*tour) {
      const bool tty = ::isatty(STDERR_FILENO) != 0;
      const msg::Reply reply = client.tour(scene, budget, tour_seed, targets, [&](double t, double cost, double bound) {
        if (json) return;
        std::cerr << fmt::format("{}{:8.2f} s  best tour {:.6g}  proven bound {:.6g}{}", tty ? "\r" : "", t, cost, bound,
                                 tty ? "   " : "\n")
                  << std::flush;
      });
      if (tty && !json) std::cerr << "\n";
      const msg::TourResult& r = reply.body().tour();
      nlohmann::json trace = nlohmann::json::array();
      for (std::size_t i = 0; i + 1 < r.trace().size(); i += 2) trace.push_back({r.trace()[i], r.trace()[i + 1]});
      nlohmann::json bound_trace = nlohmann::json::array();
      for (std::size_t i = 0; i + 1 < r.bound_trace().size(); i += 2) {
        bound_trace.push_back({r.bound_trace()[i], r.bound_trace()[i + 1]});
      }
      const double seconds = r.trace().empty() ? 0.0 : r.trace()[r.trace().size() - 2];
      const nlohmann::json result = {{"cost", r.cost()},
                                     {"covered", r.covered()},
                                     {"targets", r.target_count()},
                                     {"seconds", seconds},
                                     {"lower_bound", r.lower_bound()},
                                     {"valid", r.valid()},
                                     {"trace", trace},
                                     {"bound_trace", bound_trace},
                                     {"bound_complete", r.bound_complete()},
                                     {"walk_steps", r.walk().empty() ? 0 : r.walk().size() - 1},
                                     {"shortcut_cost", r.shortcut_cost()},
                                     {"shortcut_steps", r.shortcut_stops().empty() ? 0 : r.shortcut_stops().size() - 1},
                                     {"version", r.version()}};
      if (!out.empty()) {
        nlohmann::json positions = nlohmann::json::array();
        for (const auto& p : r.waypoints()) positions.push_back({p.x(), p.y(), p.z()});
        nlohmann::json file = result;
        file["walk"] = r.walk();
        file["positions"] = positions;
        nlohmann::json flown = nlohmann::json::array();  // the shortcut tour: what render draws
        for (const auto& p : r.shortcut_path()) flown.push_back({p.x(), p.y(), p.z()});
        file["path"] = flown;
        write_text(out, file.dump() + "\n");
      }
      if (json) {
        std::cout << result.dump() << std::endl;
      } else {
        std::cout << reply.message() << "\n";
        std::cout << fmt::format("  shortcut: {:.6g} in {} straight steps (the path as flown)\n", r.shortcut_cost(),
                                 r.shortcut_stops().empty() ? 0 : r.shortcut_stops().size() - 1);
        std::cout << fmt::format("  {} roadmap steps, proven lower bound {:.6g} (gap {:.1f}%{}), {}\n",
                                 r.walk().empty() ? 0 : r.walk().size() - 1, r.lower_bound(),
                                 r.cost() > 0 ? 100.0 * (r.cost() - r.lower_bound()) / r.cost() : 0.0,
                                 r.bound_complete() ? ", LP solved over all its cuts" : "",
                                 r.valid() ? "valid" : "NOT valid");
      }
      return r.valid() ? 0 : 1;
    } else if (*render) {
      return ispars::cli::render_from_daemon(client, render_args);
    } else if (*snapshot) {
      const ispars::client::Snapshot s = client.snapshot(scene);
      write_text(out, ispars::roadmap_file_json(scene, s.root, s.pois, s.roadmap, nullptr));
      std::cout << fmt::format("wrote {} at version {} ({} vertices, {} edges, digest {:016x}) to {}\n", scene, s.version,
                               s.roadmap.vertex_count(), s.roadmap.edge_count(), ispars::roadmap_digest(s.roadmap), out);
    } else if (*watch) {
      std::signal(SIGINT, [](int) { g_interrupted = true; });
      std::signal(SIGTERM, [](int) { g_interrupted = true; });
      (void)client.stats(scene);  // fails clearly when the scene is not loaded anywhere
      Progress progress(true);
      ispars::client::RoadmapReplica replica(client, scene);
      bool retired = false;
      while (!g_interrupted) {
        const auto s = client.latest_status(scene);
        if (s) progress(*s);
        if (replica.retirements() > 0) {  // dropped or unloaded: nothing left to follow
          retired = true;
          break;
        }
        if (until_idle && s && s->state() != msg::SCENE_BUILDING && s->state() != msg::SCENE_QUEUED &&
            s->state() != msg::SCENE_REPLAYING && replica.snapshots_taken() > 0) {
          const msg::SceneStatus now = client.stats(scene);
          if (replica.wait_for(now.generation(), now.version(), std::chrono::seconds(10))) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      progress.finish();
      const ispars::Roadmap g = replica.roadmap();
      std::cout << fmt::format("replica of {}: version {}, {} vertices, {} edges, digest {:016x} ({} snapshots, {} batches)\n",
                               scene, g.version(), g.vertex_count(), g.edge_count(), ispars::roadmap_digest(g),
                               replica.snapshots_taken(), replica.batches_applied());
      if (retired) {
        const auto s = client.latest_status(scene);
        const std::string what = !s                                     ? "dropped or unloaded"
                                 : s->state() == msg::SCENE_UNLOADED ? "unloaded"
                                 : s->state() == msg::SCENE_EMPTY     ? "dropped"
                                                                      : "dropped or unloaded";
        std::cerr << fmt::format("ispars: the roadmap of scene '{}' was {} while watching{}\n", scene, what,
                                 dump.empty() ? "" : "; nothing written to " + dump);
        return 1;
      }
      if (!dump.empty()) write_text(dump, ispars::roadmap_file_json(scene, replica.root(), replica.pois(), g, nullptr));
    }
    return 0;
  } catch (const ClientError& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    return e.kind() == ClientError::Kind::rejected || e.kind() == ClientError::Kind::forbidden ? 1 : 3;
  } catch (const CLI::ValidationError& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    return 1;
  }
}
