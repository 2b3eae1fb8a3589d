// ispars-ompl-bench: construction time of Inspection-SPARS against OMPL's SPARS (Debian's
// libompl 1.5), in one process, on the same scene with the same delta, Delta and t. OMPL's SPARS
// is stopped when its dense graph holds as many vertices as ours did after N samples, and runs
// twice: with our collision checker (the algorithms alone compared) and with FCL's exact sphere
// and capsule tests (OMPL as its users run it, with FCL). OMPL computes no visibility;
// Inspection-SPARS does (chi for every sample). Prints a line per run, or JSON with --json.

#include <fmt/format.h>
#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/planners/prm/SPARS.h>
#include <ompl/util/Console.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/reference/fcl_checker.hpp"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

ispars::Vec3 point_of(const ob::State* s) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return {v->values[0], v->values[1], v->values[2]};
}

// The point and segment checks OMPL is given: ours, or FCL's.
struct Checks {
  std::function<bool(const ispars::Vec3&)> point;
  std::function<bool(const ispars::Vec3&, const ispars::Vec3&)> segment;
};

// OMPL's local planner, answered by an exact capsule test.
class SceneMotionValidator final : public ob::MotionValidator {
 public:
  SceneMotionValidator(const ob::SpaceInformationPtr& si, const Checks& checks)
      : ob::MotionValidator(si), checks_(&checks) {}
  bool checkMotion(const ob::State* a, const ob::State* b) const override {
    const bool ok = checks_->segment(point_of(a), point_of(b));
    ok ? ++valid_ : ++invalid_;
    return ok;
  }
  bool checkMotion(const ob::State* a, const ob::State* b, std::pair<ob::State*, double>& last) const override {
    if (checkMotion(a, b)) return true;
    if (last.first != nullptr) si_->copyState(last.first, a);
    last.second = 0.0;
    return false;
  }

 private:
  const Checks* checks_;
};

struct OmplRun {
  double seconds = 0.0;
  unsigned dense = 0, sparse = 0;
  bool capped = false;
};

OmplRun run_ompl_spars(const ispars::planning::Scene& scene, const Checks& checks, unsigned dense_target,
                       double cap_seconds) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(3);
  ob::RealVectorBounds bounds(3);
  for (int i = 0; i < 3; ++i) {
    bounds.setLow(i, scene.config().bounds.min[i]);
    bounds.setHigh(i, scene.config().bounds.max[i]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker([&checks](const ob::State* s) { return checks.point(point_of(s)); });
  si->setMotionValidator(std::make_shared<SceneMotionValidator>(si, checks));
  si->setup();
  // SPARS needs a problem definition with an objective even to build a roadmap alone.
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> root(space);
  for (int i = 0; i < 3; ++i) root[i] = scene.config().root[i];
  pdef->addStartState(root);
  pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));

  og::SPARS spars(si);
  spars.setProblemDefinition(pdef);
  const double extent = si->getMaximumExtent();
  spars.setDenseDeltaFraction(scene.config().dense_delta / extent);
  spars.setSparseDeltaFraction(scene.config().sparse_delta / extent);
  spars.setStretchFactor(scene.config().stretch);
  spars.setMaxFailures(1u << 30);
  spars.setup();
  OmplRun run;
  const auto t0 = std::chrono::steady_clock::now();
  spars.constructRoadmap(ob::PlannerTerminationCondition([&] {
                           if (seconds_since(t0) > cap_seconds) run.capped = true;
                           return spars.milestoneCount() >= dense_target || run.capped;
                         }),
                         false);
  run.seconds = seconds_since(t0);
  run.dense = spars.milestoneCount();
  run.sparse = spars.guardCount();
  return run;
}

// Inspection-SPARS on `samples`, each variant: its figures by variant name, and (to `dense_target`)
// the dense vertex count the stretch variant reached last.
nlohmann::json run_ours(const ispars::planning::Scene& scene, std::size_t samples, unsigned& dense_target) {
  nlohmann::json ours = nlohmann::json::object();
  for (const ispars::SparsVariant variant : {ispars::SparsVariant::stretch, ispars::SparsVariant::alg1}) {
    ispars::planning::BuildOptions options;
    options.variant = variant;
    const auto t0 = std::chrono::steady_clock::now();
    const auto builder = ispars::planning::make_roadmap_builder(ispars::BuildMethod::ispars, scene, options);
    builder->extend(samples);
    const double seconds = seconds_since(t0);
    dense_target = static_cast<unsigned>(builder->dense()->vertex_count());
    ours[std::string(to_string(variant))] = {{"seconds", seconds},
                                             {"dense_vertices", builder->dense()->vertex_count()},
                                             {"sparse_vertices", builder->roadmap().vertex_count()}};
    std::cout << fmt::format(
        "Inspection-SPARS ({}): {} samples, {} dense / {} sparse vertices in {:.3f} s (1 thread)\n", to_string(variant),
        samples, builder->dense()->vertex_count(), builder->roadmap().vertex_count(), seconds);
  }
  return ours;
}

// OMPL's SPARS to `dense_target` with `checks` named `name`. It can throw "Vertex has no interface
// neighbor with given representative" (a defect of its shortcut bookkeeping,
// ../shared/notes/algorithms.md); each attempt draws new samples, so it is tried up to 5 times and
// the attempts that threw are reported. Nothing (and a message) when all 5 threw.
std::optional<nlohmann::json> run_ompl(const ispars::planning::Scene& scene, const std::string& name,
                                       const Checks& checks, unsigned dense_target, double cap, double ours_seconds,
                                       bool& capped) {
  OmplRun run;
  std::vector<std::string> failures;
  for (int attempt = 0; attempt < 5 && failures.size() == static_cast<std::size_t>(attempt); ++attempt) {
    try {
      run = run_ompl_spars(scene, checks, dense_target, cap);
    } catch (const ompl::Exception& e) {
      failures.emplace_back(e.what());
      std::cout << fmt::format("OMPL SPARS ({}) attempt {} threw: {}\n", name, attempt + 1, e.what());
    }
  }
  if (failures.size() == 5) {
    std::cerr << "ispars-ompl-bench: OMPL's SPARS threw on every attempt\n";
    return std::nullopt;
  }
  capped = capped || run.capped;
  const double ratio = run.seconds / ours_seconds;
  std::cout << fmt::format(
      "OMPL SPARS with {}: {} dense / {} sparse vertices in {:.3f} s{}; {:.0f}x the time of "
      "Inspection-SPARS (stretch)\n",
      name == "fcl" ? "FCL" : "our checker", run.dense, run.sparse, run.seconds,
      run.capped ? " (stopped at the cap, short of the dense target)" : "", ratio);
  return nlohmann::json{{"seconds", run.seconds}, {"dense_vertices", run.dense},     {"sparse_vertices", run.sparse},
                        {"capped", run.capped},   {"attempts_that_threw", failures}, {"over_ispars", ratio}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ispars-ompl-bench: Inspection-SPARS construction against OMPL's SPARS on the same scene"};
  std::string scene_path;
  std::size_t samples = 7000;
  double cap = 600.0;
  bool json = false;
  double delta = 0.0;
  app.add_option("scene", scene_path, "Scene YAML file")->required();
  app.add_option("--samples", samples, "N: samples drawn by Inspection-SPARS")->check(CLI::Range(1, 10'000'000));
  app.add_option("--cap", cap, "Seconds OMPL's SPARS may take at most")->check(CLI::Range(0.1, 1e5));
  app.add_option("--delta", delta, "delta, with Delta = 1.5 delta (0: the scene's)")->check(CLI::Range(0.0, 1e6));
  app.add_flag("--json", json, "Print one JSON object as the last line of stdout");
  CLI11_PARSE(app, argc, argv);
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  try {
    const ispars::planning::Scene loaded = ispars::planning::Scene::load(scene_path);
    const ispars::planning::Scene scene =
        delta > 0.0 ? loaded.with_roadmap_parameters(delta, 1.5 * delta, loaded.config().stretch, "--delta")
                    : loaded.with_roadmap_parameters(loaded.config().dense_delta, loaded.config().sparse_delta,
                                                     loaded.config().stretch, "scene");
    unsigned dense_target = 0;
    const nlohmann::json ours = run_ours(scene, samples, dense_target);
    const Checks ours_checks{[&](const ispars::Vec3& q) { return scene.point_valid(q); },
                             [&](const ispars::Vec3& a, const ispars::Vec3& b) { return scene.segment_valid(a, b); }};
    const ispars::reference::FclCollisionChecker fcl(scene.mesh(), scene.config().bounds, scene.config().robot_radius);
    const Checks fcl_checks{[&](const ispars::Vec3& q) { return fcl.point_valid(q); },
                            [&](const ispars::Vec3& a, const ispars::Vec3& b) { return fcl.segment_valid(a, b); }};
    const double ours_seconds = ours["stretch"]["seconds"].get<double>();
    nlohmann::json ompl_json = nlohmann::json::object();
    bool capped = false;
    for (const auto& [name, checks] : {std::pair<std::string, const Checks*>{"our_checker", &ours_checks},
                                       std::pair<std::string, const Checks*>{"fcl", &fcl_checks}}) {
      const auto row = run_ompl(scene, name, *checks, dense_target, cap, ours_seconds, capped);
      if (!row) return 1;
      ompl_json[name] = *row;
    }
    if (json) {
      std::cout << nlohmann::json{{"scene", scene.config().name},
                                  {"samples", samples},
                                  {"delta", scene.config().dense_delta},
                                  {"Delta", scene.config().sparse_delta},
                                  {"ispars", ours},
                                  {"ompl_spars", ompl_json}}
                       .dump()
                << std::endl;
    }
    return capped ? 1 : 0;
  } catch (const ispars::params::InputError& e) {
    std::cerr << "ispars-ompl-bench: error: " << e.what() << '\n';
    return 2;
  }
}
