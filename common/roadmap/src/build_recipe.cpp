#include "ispars/roadmap/build_recipe.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <tuple>

#include "ispars/params/input_error.hpp"
#include "ispars/params/json_archive.hpp"
#include "ispars/roadmap/sealed_file.hpp"

namespace ispars {
namespace {

constexpr std::array<BuildMethod, 5> kMethods{BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars,
                                              BuildMethod::irisc, BuildMethod::ispars2};
constexpr std::array<SparsVariant, 2> kVariants{SparsVariant::stretch, SparsVariant::alg1};

template <typename Items, typename Name>
std::string join_names(const Items& items, Name name) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + std::string(name(item));
  return out;
}

}  // namespace

std::string_view to_string(BuildMethod method) {
  switch (method) {
    case BuildMethod::dense:
      return "dense";
    case BuildMethod::spars:
      return "spars";
    case BuildMethod::ispars:
      return "ispars";
    case BuildMethod::irisc:
      return "irisc";
    case BuildMethod::ispars2:
      return "ispars2";
  }
  return "?";
}

bool has_dense_pair(BuildMethod method) { return method == BuildMethod::spars || method == BuildMethod::ispars; }

bool has_variants(BuildMethod method) { return method == BuildMethod::spars || method == BuildMethod::ispars; }

std::optional<BuildMethod> parse_build_method(std::string_view text) {
  for (const BuildMethod m : kMethods) {
    if (to_string(m) == text) return m;
  }
  return std::nullopt;
}

std::string build_method_names() {
  return join_names(kMethods, [](BuildMethod m) { return to_string(m); });
}

std::string_view to_string(SparsVariant variant) {
  switch (variant) {
    case SparsVariant::stretch:
      return "stretch";
    case SparsVariant::alg1:
      return "alg1";
  }
  return "?";
}

std::optional<SparsVariant> parse_spars_variant(std::string_view text) {
  for (const SparsVariant v : kVariants) {
    if (to_string(v) == text) return v;
  }
  return std::nullopt;
}

std::string spars_variant_names() {
  return join_names(kVariants, [](SparsVariant v) { return to_string(v); });
}

bool reads_stretch_slack(BuildMethod method, SparsVariant variant) {
  return method == BuildMethod::ispars2 || (has_variants(method) && variant == SparsVariant::stretch);
}

void check_stretch_slack(const RoadmapRecipe& recipe, std::string_view file) {
  if (recipe.stretch_slack > 0.0 && !reads_stretch_slack(recipe.method, recipe.variant)) {
    throw params::InputError(
        std::string(file), "overrides.stretch_slack",
        fmt::format(
            "{} given, but {} {} has no stretch rules to slacken (spars and ispars with "
            "variant stretch, and ispars2, have)",
            recipe.stretch_slack, to_string(recipe.method),
            has_variants(recipe.method) ? "variant " + std::string(to_string(recipe.variant)) : std::string("method")));
  }
  if (recipe.stretch_slack_after > 0 && recipe.stretch_slack == 0.0) {
    throw params::InputError(
        std::string(file), "overrides.stretch_slack_after",
        fmt::format("{} given, but there is no stretch_slack to start there", recipe.stretch_slack_after));
  }
}

bool same_roadmap(const RoadmapRecipe& a, const RoadmapRecipe& b) {
  if (a.method != b.method || a.seed != b.seed || (has_variants(a.method) && a.variant != b.variant)) return false;
  const auto values = [](const RoadmapRecipe& r) {
    return std::tuple(r.dense_delta, r.sparse_delta, r.stretch, r.stretch_slack, r.stretch_slack_after, r.p_accept);
  };
  return values(a) == values(b);
}

std::string recipe_to_json(const RoadmapRecipe& r) {
  nlohmann::json j = {{"scene", r.scene},
                      {"method", std::string(to_string(r.method))},
                      {"seed", r.seed},
                      {"variant", std::string(to_string(r.variant))},
                      {"generation", r.generation},
                      {"scene_fingerprint", r.scene_fingerprint},
                      {"builder_version", r.builder_version},
                      {"format", kRecipeFormat}};
  params::write_json(r, j);  // each in its type: a count as an integer
  return seal_json(std::move(j)).dump(2) + "\n";
}

namespace {

// Every parameter from recipe.json, checked as a request's is (the file may have been edited).
// stretch_slack and stretch_slack_after came later: a file without them reads 0 for each, as built.
void read_parameters(const nlohmann::json& j, RoadmapRecipe& r) {
  for (const auto& spec : {kDenseDelta, kSparseDelta, kStretch, kPAccept}) {
    if (!j.contains(std::string(spec.name))) throw std::runtime_error("recipe.json lacks " + std::string(spec.name));
  }
  try {
    params::read_json(j, r, "recipe.json");
  } catch (const params::InputError& e) {
    throw std::runtime_error(fmt::format("recipe.json: {}: {}", e.field(), e.problem()));
  }
}

}  // namespace

RoadmapRecipe recipe_from_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("recipe.json does not parse: ") + e.what());
  }
  if (open_sealed_json(j) == Seal::broken) {
    throw std::runtime_error("recipe.json fails its checksum: it was changed or damaged (left untouched)");
  }
  const auto field = [&](const char* name) -> const nlohmann::json& {
    if (!j.is_object() || !j.contains(name)) throw std::runtime_error(std::string("recipe.json lacks ") + name);
    return j.at(name);
  };
  RoadmapRecipe r;
  try {
    r.scene = field("scene").get<std::string>();
    const auto method = parse_build_method(field("method").get<std::string>());
    if (!method) throw std::runtime_error("recipe.json: unknown method");
    r.method = *method;
    r.seed = field("seed").get<std::uint64_t>();
    r.variant = SparsVariant::alg1;  // recipes written before the variants existed
    if (j.contains("variant")) {
      const auto variant = parse_spars_variant(j.at("variant").get<std::string>());
      if (!variant) throw std::runtime_error("recipe.json: unknown variant");
      r.variant = *variant;
    }
    read_parameters(j, r);
    r.generation = field("generation").get<std::uint64_t>();
    if (j.contains("format") && j.at("format").get<int>() > kRecipeFormat) {
      throw std::runtime_error("recipe.json is format " + std::to_string(j.at("format").get<int>()) +
                               ", newer than this ispars reads (" + std::to_string(kRecipeFormat) + ")");
    }
    if (j.contains("scene_fingerprint")) r.scene_fingerprint = j.at("scene_fingerprint").get<std::string>();
    if (j.contains("builder_version")) r.builder_version = j.at("builder_version").get<std::uint32_t>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("recipe.json has a field of the wrong type: ") + e.what());
  }
  return r;
}

}  // namespace ispars
