#include "ispars/planning/builders/roadmap_builder.hpp"

#include "ispars/planning/builders/dense_builder.hpp"
#include "ispars/planning/builders/irisc_builder.hpp"
#include "ispars/planning/builders/spars_builder.hpp"

#include <stdexcept>
#include <string>

namespace ispars::planning {

std::size_t RoadmapBuilder::add_pois(const Scene&, const std::function<bool()>&) {
  throw std::invalid_argument(
      "this method cannot take new POIs into a built roadmap (spars and ispars can): rebuild it with them");
}

std::unique_ptr<RoadmapBuilder> make_roadmap_builder(BuildMethod method, const Scene& scene,
                                                     const BuildOptions& options) {
  switch (method) {
    case BuildMethod::dense:
      return std::make_unique<DenseBuilder>(scene, options);
    case BuildMethod::spars:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::for_variant(options.variant, false));
    case BuildMethod::ispars:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::for_variant(options.variant, true));
    case BuildMethod::irisc:
      return std::make_unique<IriscBuilder>(scene, options);
    case BuildMethod::ispars2:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::dense_free());
  }
  return nullptr;
}

bool takes_pois(BuildMethod method) {
  return method == BuildMethod::spars || method == BuildMethod::ispars || method == BuildMethod::ispars2;
}

bool resumes_from_roadmap(BuildMethod method) { return method == BuildMethod::ispars2 || method == BuildMethod::dense; }

bool resumes_without_replay(BuildMethod method) { return method != BuildMethod::irisc; }

namespace {

bool starts_at_root(const Roadmap& roadmap, const Scene& scene) {
  return roadmap.vertex_count() > 0 && roadmap.position(0) == scene.config().root;
}

// The dense pair's roadmaps fit each other: every sparse vertex is the dense vertex dense_ids
// names, at the same place.
void check_dense_pair(const BuiltRoadmaps& built, const Scene& scene) {
  if (!built.dense) throw std::invalid_argument("the dense pair resumes from its dense roadmap, and none was given");
  if (!starts_at_root(*built.dense, scene)) {
    throw std::invalid_argument("the dense roadmap to resume does not start with the scene's root");
  }
  if (built.dense_ids.size() != built.roadmap.vertex_count()) {
    throw std::invalid_argument("the dense pair to resume maps " + std::to_string(built.dense_ids.size()) +
                                " sparse vertices to dense ones, and has " +
                                std::to_string(built.roadmap.vertex_count()));
  }
  for (VertexId s = 0; s < built.dense_ids.size(); ++s) {
    const VertexId d = built.dense_ids[s];
    if (d >= built.dense->vertex_count() || built.dense->position(d) != built.roadmap.position(s)) {
      throw std::invalid_argument("sparse vertex " + std::to_string(s) +
                                  " of the dense pair to resume is not the dense vertex it names");
    }
  }
}

}  // namespace

std::unique_ptr<RoadmapBuilder> resume_roadmap_builder(BuildMethod method, const Scene& scene,
                                                       const BuildOptions& options, BuiltRoadmaps built) {
  if (!resumes_without_replay(method)) {
    throw std::invalid_argument(std::string(to_string(method)) +
                                " keeps more than its roadmaps: it is replayed, not resumed");
  }
  if (!starts_at_root(built.roadmap, scene)) {
    throw std::invalid_argument("the roadmap to resume does not start with the scene's root");
  }
  const std::size_t samples = built.samples;
  switch (method) {
    case BuildMethod::dense:
      return std::make_unique<DenseBuilder>(scene, options, std::move(built.roadmap), samples);
    case BuildMethod::ispars2:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::dense_free(), std::move(built));
    case BuildMethod::spars:
    case BuildMethod::ispars:
      check_dense_pair(built, scene);
      return std::make_unique<SparsBuilder>(
          scene, options, SparsRules::for_variant(options.variant, method == BuildMethod::ispars), std::move(built));
    case BuildMethod::irisc:
      break;
  }
  throw std::invalid_argument("no builder resumes this method");
}

}  // namespace ispars::planning
