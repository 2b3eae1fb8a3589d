#pragma once
// How a roadmap is built, in one typed form from the request to the store: the method, the rule
// set, the seed and the scene parameters a build may override (each declared once, in
// roadmap_parameters.hpp), and recipe.json, the store's copy of it.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "ispars/roadmap/roadmap_parameters.hpp"

namespace ispars {

/// The roadmap a build grows. `ispars2` is Inspection-SPARS with the `stretch` rules and no
/// dense graph: the same sparse roadmap as `ispars` (whose default rules never read the dense
/// graph), in memory proportional to the sparse roadmap alone.
enum class BuildMethod { dense, spars, ispars, irisc, ispars2 };

[[nodiscard]] std::string_view to_string(BuildMethod method);
/// "dense", "spars", "ispars", "irisc" or "ispars2"; nothing for anything else.
[[nodiscard]] std::optional<BuildMethod> parse_build_method(std::string_view text);
/// Whether `method` keeps a dense roadmap beside its own (spars and ispars).
[[nodiscard]] bool has_dense_pair(BuildMethod method);
/// Whether `method` has rule-set variants (spars and ispars).
[[nodiscard]] bool has_variants(BuildMethod method);
/// The method names, for help texts and errors: "dense, spars, ispars, irisc, ispars2".
[[nodiscard]] std::string build_method_names();

/// The rule set of the spars and ispars sparse roadmaps (spars_builder.hpp, SparsRules).
/// `stretch` (the default) bounds the routes between sparse vertices within Delta in view, and
/// between the members of a sample's W, by t (not between far ones: docs/sparse-stretch.md);
/// `alg1` is the paper's Alg. 1 read literally, kept to reproduce the paper.
enum class SparsVariant { stretch, alg1 };

[[nodiscard]] std::string_view to_string(SparsVariant variant);
/// "stretch" or "alg1"; nothing for anything else.
[[nodiscard]] std::optional<SparsVariant> parse_spars_variant(std::string_view text);
/// The variant names, for help texts and errors: "stretch, alg1".
[[nodiscard]] std::string spars_variant_names();
/// Whether a build of `method` (with `variant`, where it has one) reads stretch_slack: the
/// `stretch` rules of spars and ispars, and ispars2.
[[nodiscard]] bool reads_stretch_slack(BuildMethod method, SparsVariant variant);

/// The parameters of a recipe a build may override, in their one order, for a struct with a member
/// of each name: RoadmapRecipe (the values) and RecipeOverrides (build_request.hpp, each optional).
void describe_recipe_parameters(auto& self, auto&& field) {
  field(kDenseDelta, self.dense_delta);
  field(kSparseDelta, self.sparse_delta);
  field(kStretch, self.stretch);
  field(kStretchSlack, self.stretch_slack);
  field(kStretchSlackAfter, self.stretch_slack_after);
  field(kPAccept, self.p_accept);
}

/// What a roadmap is built from: enough to rebuild it exactly.
struct RoadmapRecipe {
  std::string scene;
  BuildMethod method = BuildMethod::ispars;
  std::uint64_t seed = 1;
  double p_accept = 0.2;
  /// spars and ispars: the rule set. A recipe.json without one predates the variants and was
  /// built with Alg. 1's rules, so it reads as alg1 (and replays byte for byte).
  SparsVariant variant = SparsVariant::stretch;
  double dense_delta = 0.0;      ///< delta used (the scene's, or an override)
  double sparse_delta = 0.0;     ///< Delta used
  double stretch = 0.0;          ///< t used
  std::uint64_t generation = 0;  ///< Distinguishes successive roadmaps of one scene.
  /// scene_fingerprint() of the scene it was built on; empty in stores that predate it (then
  /// unchecked).
  std::string scene_fingerprint;
  /// kBuilderVersion when it was built; 0 in stores that predate it (then unchecked).
  std::uint32_t builder_version = 0;
  /// spars, ispars, ispars2 with the stretch rules: the additive slack of the stretch bounds,
  /// as a fraction of Delta (0, the default: the bounds are t times the distance alone).
  double stretch_slack = 0.0;
  /// The sample from which the slack applies (0: from the first). The first stretch_slack_after
  /// samples grow the roadmap that no slack grows.
  std::uint64_t stretch_slack_after = 0;

  /// The recipe's parameters (roadmap_parameters.hpp), in recipe.json under their names.
  static void describe(auto& self, auto&& field) { describe_recipe_parameters(self, field); }
};

/// Whether two recipes build the same roadmap: method, seed, the variant where the method has
/// one, the deltas, the stretch, its slack and p_accept (scene, generation and versions aside).
[[nodiscard]] bool same_roadmap(const RoadmapRecipe& a, const RoadmapRecipe& b);

/// Throws InputError (file `file`, field "overrides.stretch_slack" or ".stretch_slack_after")
/// when a recipe gives a slack to a build that does not read one, or a start to no slack: values
/// that would be stored and ignored.
void check_stretch_slack(const RoadmapRecipe& recipe, std::string_view file);

/// Bumped whenever a builder's output for the same recipe changes: a stored roadmap of another
/// builder version is not replayed or extended (it would not match), only rebuilt or dropped.
inline constexpr std::uint32_t kBuilderVersion = 1;
/// The recipe.json format this code writes; it refuses to read a newer one.
inline constexpr int kRecipeFormat = 1;

/// recipe.json: the recipe and a format number.
[[nodiscard]] std::string recipe_to_json(const RoadmapRecipe& recipe);
/// Throws std::runtime_error naming what is missing or wrong.
[[nodiscard]] RoadmapRecipe recipe_from_json(const std::string& text);

}  // namespace ispars
