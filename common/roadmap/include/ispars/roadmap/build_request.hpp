#pragma once
// A build as every caller asks for it, typed: the CLI, Python, the lab, the client library and
// the wire all fill this one struct, and make_recipe (builders/recipe_builder.hpp) checks it in
// one place for the daemon, Python and the lab alike.

#include <cstdint>
#include <optional>
#include <string_view>

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"

namespace ispars {

/// The scene parameters a build overrides; an absent one keeps the scene's (or the recipe's
/// default). Declared in roadmap_parameters.hpp; the wire's presence mask numbers them in this
/// order, so a new one is appended.
struct RecipeOverrides {
  std::optional<double> dense_delta;
  std::optional<double> sparse_delta;
  std::optional<double> stretch;
  std::optional<double> stretch_slack;
  std::optional<std::uint64_t> stretch_slack_after;
  std::optional<double> p_accept;

  static void describe(auto& self, auto&& field) { describe_recipe_parameters(self, field); }
  /// Whether any override is given (read from the declarations, so a new one counts too).
  [[nodiscard]] bool any() const {
    bool given = false;
    describe(*this, [&](const auto&, const auto& member) { given = given || member.has_value(); });
    return given;
  }
  bool operator==(const RecipeOverrides&) const = default;
};

/// A build request: the recipe's choices, its overrides and the job's size.
struct BuildRequest {
  BuildMethod method = BuildMethod::ispars;
  /// spars and ispars: the rule set (absent: stretch). Given for another method, it is refused.
  std::optional<SparsVariant> variant{};
  std::uint64_t samples = 0;
  std::uint64_t seed = 1;
  RecipeOverrides overrides{};
  bool replace = false;  ///< rebuild a scene that has a roadmap
  /// 0: a new roadmap, with a new generation. Otherwise the generation of the roadmap this build
  /// makes again (a fleet takeover continuing another daemon's roadmap: the same lineage).
  std::uint64_t generation = 0;

  bool operator==(const BuildRequest&) const = default;
};

/// Sets `request`'s method and variant from their names, as a request or a Python call gives
/// them: `method` one of build_method_names(); `variant` empty (none given) or one of
/// spars_variant_names(). Throws InputError (file `file`, field "method" or "variant").
void set_method(BuildRequest& request, std::string_view method, std::string_view variant, std::string_view file);

/// A request for `samples` samples of `method` (by name, as set_method reads it, file "request"),
/// seed 1 and the scene's parameters.
[[nodiscard]] BuildRequest request_of(std::string_view method, std::uint64_t samples);

}  // namespace ispars
