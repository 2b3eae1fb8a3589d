#pragma once
// A lab build, checked as the daemon and Python check theirs: the request's method, variant and
// overrides go through make_recipe (builders/recipe_builder.hpp), so the lab refuses what the
// daemon refuses, with the same message, and builds the same roadmap.

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <string_view>

#include "ispars/planning/builders/recipe_builder.hpp"

namespace ispars::lab {

/// The flags of a build request: --method and --variant (into `method`, `variant`), and each
/// declared parameter (--samples, --seed and every override) into `request`.
void add_request_flags(CLI::App& command, std::string& method, std::string& variant, BuildRequest& request);

/// A build's recipe, the scene it builds in (the base scene with the recipe's deltas and
/// stretch) and its builder.
struct LabBuild {
  RoadmapRecipe recipe;
  std::unique_ptr<planning::Scene> scene;  ///< held by address: the builder refers to it
  std::unique_ptr<planning::RoadmapBuilder> builder;
};

/// The build `request` (method and variant given by name) asks for on `base`, on `threads`
/// threads. Throws InputError (file `file`) naming the first bad choice, as make_recipe does.
[[nodiscard]] LabBuild make_lab_build(const planning::Scene& base, std::string_view method, std::string_view variant,
                                      BuildRequest request, unsigned threads, std::string_view file);

}  // namespace ispars::lab
