#include "ispars/builders/roadmap_builder.hpp"

#include "ispars/builders/dense_builder.hpp"
#include "ispars/builders/irisc_builder.hpp"
#include "ispars/builders/spars_builder.hpp"

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
  }
  return nullptr;
}

}  // namespace ispars
