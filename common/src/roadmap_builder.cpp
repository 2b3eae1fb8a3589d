#include "ispars/roadmap_builder.hpp"

#include "ispars/dense_builder.hpp"
#include "ispars/irisc_builder.hpp"
#include "ispars/spars_builder.hpp"

namespace ispars {

std::string_view to_string(BuildMethod method) {
  switch (method) {
    case BuildMethod::dense: return "dense";
    case BuildMethod::spars: return "spars";
    case BuildMethod::ispars: return "ispars";
    case BuildMethod::irisc: return "irisc";
  }
  return "?";
}

std::optional<BuildMethod> parse_build_method(std::string_view text) {
  for (const BuildMethod m : {BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars, BuildMethod::irisc}) {
    if (to_string(m) == text) return m;
  }
  return std::nullopt;
}

std::string_view to_string(SparsVariant variant) {
  switch (variant) {
    case SparsVariant::stretch: return "stretch";
    case SparsVariant::alg1: return "alg1";
  }
  return "?";
}

std::optional<SparsVariant> parse_spars_variant(std::string_view text) {
  for (const SparsVariant v : {SparsVariant::stretch, SparsVariant::alg1}) {
    if (to_string(v) == text) return v;
  }
  return std::nullopt;
}

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
