#include "ispars/builders/roadmap_builder.hpp"

#include "ispars/builders/dense_builder.hpp"
#include "ispars/builders/irisc_builder.hpp"
#include "ispars/builders/spars_builder.hpp"

#include <stdexcept>
#include <string>

namespace ispars {

std::unique_ptr<RoadmapBuilder> make_roadmap_builder(BuildMethod method, const Scene& scene,
                                                     const BuildOptions& options) {
  switch (method) {
    case BuildMethod::dense: return std::make_unique<DenseBuilder>(scene, options);
    case BuildMethod::spars:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::for_variant(options.variant, false));
    case BuildMethod::ispars:
      return std::make_unique<SparsBuilder>(scene, options, SparsRules::for_variant(options.variant, true));
    case BuildMethod::irisc: return std::make_unique<IriscBuilder>(scene, options);
    case BuildMethod::ispars2: return std::make_unique<SparsBuilder>(scene, options, SparsRules::dense_free());
  }
  return nullptr;
}

bool resumes_from_roadmap(BuildMethod method) {
  return method == BuildMethod::ispars2 || method == BuildMethod::dense;
}

std::unique_ptr<RoadmapBuilder> resume_roadmap_builder(BuildMethod method, const Scene& scene,
                                                       const BuildOptions& options, Roadmap roadmap,
                                                       std::size_t samples) {
  if (!resumes_from_roadmap(method)) {
    throw std::invalid_argument(std::string(to_string(method)) + " keeps more than its roadmap: it is replayed, not resumed");
  }
  if (roadmap.vertex_count() == 0 || roadmap.position(0) != scene.config().root) {
    throw std::invalid_argument("the roadmap to resume does not start with the scene's root");
  }
  if (method == BuildMethod::dense) return std::make_unique<DenseBuilder>(scene, options, std::move(roadmap), samples);
  return std::make_unique<SparsBuilder>(scene, options, SparsRules::dense_free(), std::move(roadmap), samples);
}

}  // namespace ispars
