// The typed build request: its overrides declared once, settable through every archive (RocksDB's
// options_settable_test idea: each member a distinct value through each one), and its method and
// variant read by name.

#include <gtest/gtest.h>

#include <string>

#include "ispars/params/fields.hpp"
#include "ispars/params/json_archive.hpp"
#include "ispars/roadmap/build_request.hpp"
#include "support/distinct_params.hpp"

namespace ispars {
namespace {

TEST(BuildRequestTypes, EveryOverrideMemberIsDeclaredAndEveryDeclarationIsARecipeParameter) {
  EXPECT_EQ(params::aggregate_size<RecipeOverrides>(), params::field_count<RecipeOverrides>())
      << "a member added to RecipeOverrides without its declaration in describe()";
  EXPECT_EQ(params::field_count<RoadmapRecipe>(), params::field_count<RecipeOverrides>());
  EXPECT_EQ(params::names<RecipeOverrides>(),
            "dense_delta, sparse_delta, stretch, stretch_slack, stretch_slack_after, p_accept");
}

TEST(BuildRequestTypes, EachOverrideSurvivesTextJsonAndTheRecipeWithItsOwnValue) {
  const RecipeOverrides given = test::distinct_values<RecipeOverrides>();
  EXPECT_TRUE(given.any());
  RecipeOverrides from_text;
  params::visit(given, [&](const auto& spec, const auto& member) {
    params::set_text(from_text, spec.name, test::exact_text(*member), "--set");
  });
  EXPECT_EQ(from_text, given);
  nlohmann::json j = nlohmann::json::object();
  params::write_json(given, j);
  RecipeOverrides from_json;
  params::read_json(j, from_json, "pending job");
  EXPECT_EQ(from_json, given);
  RoadmapRecipe recipe;
  params::overlay(given, recipe);
  const std::size_t matched = params::for_matching(
      given, recipe, [](const auto& spec, const auto& o, const auto& r) { EXPECT_EQ(*o, r) << spec.name; });
  EXPECT_EQ(matched, params::field_count<RecipeOverrides>());
}

TEST(BuildRequestTypes, MethodAndVariantAreReadByNameAndABadOneIsNamed) {
  BuildRequest r;
  set_method(r, "spars", "alg1", "request");
  EXPECT_EQ(r.method, BuildMethod::spars);
  EXPECT_EQ(r.variant, SparsVariant::alg1);
  set_method(r, "dense", "", "request");
  EXPECT_FALSE(r.variant) << "no variant given";
  try {
    set_method(r, "fast", "", "request");
    FAIL();
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.field(), "method");
    EXPECT_EQ(e.problem(), "'fast' is not one of dense, spars, ispars, irisc, ispars2");
  }
  EXPECT_THROW(set_method(r, "ispars", "loose", "request"), params::InputError);
  EXPECT_EQ(request_of("irisc", 5).samples, 5u);
}

}  // namespace
}  // namespace ispars
