#include "lab_build.hpp"

#include "flags.hpp"
#include "ispars/params/cli_archive.hpp"

namespace ispars::lab {

void add_request_flags(CLI::App& command, std::string& method, std::string& variant, BuildRequest& request) {
  command.add_option("--method", method, build_method_names())->check(build_method_check());
  command
      .add_option("--variant", variant,
                  "spars, ispars: stretch (default: bounds routes between nearby sparse vertices) or alg1 "
                  "(the paper's Alg. 1 read literally)")
      ->check(spars_variant_check());
  params::add_flag(command, kSamples, request.samples);
  params::add_flag(command, kSeed, request.seed);
  params::add_flags(command, request.overrides);
}

LabBuild make_lab_build(const planning::Scene& base, std::string_view method, std::string_view variant,
                        BuildRequest request, unsigned threads, std::string_view file) {
  set_method(request, method, variant, file);
  LabBuild build;
  build.recipe = make_recipe(base.config().name, base, request, file);
  build.scene = std::make_unique<planning::Scene>(planning::recipe_scene(base, build.recipe, file));
  build.builder = planning::make_roadmap_builder(build.recipe.method, *build.scene,
                                                 planning::recipe_build_options(build.recipe, threads));
  return build;
}

}  // namespace ispars::lab
