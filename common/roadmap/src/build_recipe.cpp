#include "ispars/roadmap/build_recipe.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "ispars/input_error.hpp"
#include "ispars/roadmap/sealed_file.hpp"

namespace ispars {
namespace {

constexpr std::array<BuildMethod, 5> kMethods{BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars,
                                              BuildMethod::irisc, BuildMethod::ispars2};
constexpr std::array<SparsVariant, 2> kVariants{SparsVariant::stretch, SparsVariant::alg1};

constexpr std::array<RecipeParameter, 6> kOverrides{{
    {"dense_delta", 1e-6, 1e6, "positive (at least 1e-6, at most 1e6 metres)",
     "delta, the dense roadmap's connection radius in metres (default: the scene's)", &RoadmapRecipe::dense_delta},
    {"sparse_delta", 1e-6, 1e6, "positive (at least 1e-6, at most 1e6 metres)",
     "Delta, the sparse roadmap's visibility radius in metres (default: the scene's)", &RoadmapRecipe::sparse_delta},
    {"stretch", 1.0, 100.0, "at least 1 and at most 100", "t, the spanner's stretch factor (default: the scene's)",
     &RoadmapRecipe::stretch},
    {"stretch_slack", 0.0, 1.0, "in [0, 1]",
     "the stretch rules' additive slack, a fraction of Delta: bounds t d + slack Delta (default 0; "
     "0.5 keeps a long extend's cost per sample nearly flat, docs/results/ispars2.md)",
     &RoadmapRecipe::stretch_slack, true},
    {"stretch_slack_after", 0.0, 1e12, "a whole number of samples in [0, 1e12]",
     "the sample from which stretch_slack applies (default 0: from the first; the samples before it "
     "grow the roadmap no slack grows)",
     &RoadmapRecipe::stretch_slack_after, true},
    {"p_accept", 0.0, 1.0, "a probability in [0, 1]",
     "IRIS-C: probability of admitting a state that adds no POI (default 0.2)", &RoadmapRecipe::p_accept},
}};

// A count travels as a double (the wire's overrides, get()): exact while its range stays within
// 2^53, which this checks for every count declared above, at compile time.
constexpr bool counts_are_exact_as_doubles() {
  for (const RecipeParameter& p : kOverrides) {
    if (std::holds_alternative<RecipeParameter::CountField>(p.field) && (p.min < 0.0 || p.max > 9007199254740992.0)) {
      return false;
    }
  }
  return true;
}
static_assert(counts_are_exact_as_doubles(), "a count's declared range must lie within [0, 2^53]");

template <typename Items, typename Name>
std::string join_names(const Items& items, Name name) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + std::string(name(item));
  return out;
}

}  // namespace

bool RecipeParameter::accepts(double value) const {
  return std::isfinite(value) && value >= min && value <= max && (!whole() || value == std::floor(value));
}

double RecipeParameter::get(const RoadmapRecipe& recipe) const {
  if (const auto* count = std::get_if<CountField>(&field)) return static_cast<double>(recipe.**count);
  return recipe.*std::get<RealField>(field);
}

void RecipeParameter::set(RoadmapRecipe& recipe, double value) const {
  if (const auto* count = std::get_if<CountField>(&field)) {
    recipe.**count = static_cast<std::uint64_t>(value);
  } else {
    recipe.*std::get<RealField>(field) = value;
  }
}

std::string_view to_string(BuildMethod method) {
  switch (method) {
    case BuildMethod::dense: return "dense";
    case BuildMethod::spars: return "spars";
    case BuildMethod::ispars: return "ispars";
    case BuildMethod::irisc: return "irisc";
    case BuildMethod::ispars2: return "ispars2";
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
    case SparsVariant::stretch: return "stretch";
    case SparsVariant::alg1: return "alg1";
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

std::span<const RecipeParameter> recipe_overrides() { return kOverrides; }

const RecipeParameter& recipe_override(std::string_view name) {
  for (const RecipeParameter& p : kOverrides) {
    if (p.name == name) return p;
  }
  throw std::out_of_range("no recipe parameter " + std::string(name));
}

bool reads_stretch_slack(BuildMethod method, SparsVariant variant) {
  return method == BuildMethod::ispars2 || (has_variants(method) && variant == SparsVariant::stretch);
}

void check_stretch_slack(const RoadmapRecipe& recipe, std::string_view file) {
  if (recipe.stretch_slack > 0.0 && !reads_stretch_slack(recipe.method, recipe.variant)) {
    throw InputError(std::string(file), "overrides.stretch_slack",
                     fmt::format("{} given, but {} {} has no stretch rules to slacken (spars and ispars with "
                                 "variant stretch, and ispars2, have)",
                                 recipe.stretch_slack, to_string(recipe.method),
                                 has_variants(recipe.method) ? "variant " + std::string(to_string(recipe.variant))
                                                             : std::string("method")));
  }
  if (recipe.stretch_slack_after > 0 && recipe.stretch_slack == 0.0) {
    throw InputError(std::string(file), "overrides.stretch_slack_after",
                     fmt::format("{} given, but there is no stretch_slack to start there", recipe.stretch_slack_after));
  }
}

bool same_roadmap(const RoadmapRecipe& a, const RoadmapRecipe& b) {
  if (a.method != b.method || a.seed != b.seed || (has_variants(a.method) && a.variant != b.variant)) return false;
  for (const RecipeParameter& p : kOverrides) {
    if (p.get(a) != p.get(b)) return false;
  }
  return true;
}

std::string recipe_override_names() {
  return join_names(kOverrides, [](const RecipeParameter& p) { return p.name; });
}

void set_recipe_override(RoadmapRecipe& recipe, std::string_view name, double value, std::string_view file) {
  const std::string field = "overrides." + std::string(name.substr(0, 64));
  for (const RecipeParameter& p : kOverrides) {
    if (p.name != name) continue;
    if (!std::isfinite(value)) throw InputError(std::string(file), field, fmt::format("must be finite, got {}", value));
    if (!p.accepts(value)) {
      throw InputError(std::string(file), field, fmt::format("must be {}, got {}", p.range, value));
    }
    p.set(recipe, value);
    return;
  }
  throw InputError(std::string(file), field, fmt::format("unknown parameter (expected {})", recipe_override_names()));
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
  for (const RecipeParameter& p : kOverrides) {  // each in its type: a count as an integer
    std::visit([&](auto field) { j[std::string(p.name)] = r.*field; }, p.field);
  }
  return seal_json(std::move(j)).dump(2) + "\n";
}

namespace {

// Every override from recipe.json, checked as a request's is (the file may have been edited).
void read_overrides(const nlohmann::json& j, RoadmapRecipe& r) {
  for (const RecipeParameter& p : kOverrides) {
    const std::string name(p.name);
    if (!j.contains(name)) {
      if (p.optional_in_file) continue;  // written before the parameter existed: 0, as built
      throw std::runtime_error("recipe.json lacks " + name);
    }
    const nlohmann::json& v = j.at(name);
    if (!v.is_number()) throw std::runtime_error(fmt::format("recipe.json: {} must be a number", name));
    const double value = v.get<double>();
    if (!p.accepts(value)) {
      throw std::runtime_error(fmt::format("recipe.json: {} must be {}, got {}", name, p.range, value));
    }
    p.set(r, value);
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
    read_overrides(j, r);
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
