// The build recipe: names and recipe.json (the ranges it checks are declared in roadmap_parameters.hpp).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/build_recipe.hpp"

namespace ispars {
namespace {

TEST(BuildRecipe, NamesRoundTripAndListsComeFromOnePlace) {
  for (const BuildMethod m :
       {BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars, BuildMethod::irisc, BuildMethod::ispars2}) {
    EXPECT_EQ(parse_build_method(to_string(m)), m);
    EXPECT_NE(build_method_names().find(to_string(m)), std::string::npos);
  }
  for (const SparsVariant v : {SparsVariant::stretch, SparsVariant::alg1})
    EXPECT_EQ(parse_spars_variant(to_string(v)), v);
  EXPECT_FALSE(parse_build_method("Dense"));
  EXPECT_FALSE(parse_spars_variant(""));
  EXPECT_EQ(build_method_names(), "dense, spars, ispars, irisc, ispars2");
  EXPECT_TRUE(has_dense_pair(BuildMethod::ispars));
  EXPECT_FALSE(has_dense_pair(BuildMethod::ispars2)) << "ispars2 keeps no dense graph";
  EXPECT_FALSE(has_variants(BuildMethod::ispars2));
  EXPECT_TRUE(has_variants(BuildMethod::spars));
  EXPECT_EQ(spars_variant_names(), "stretch, alg1");
  EXPECT_TRUE(reads_stretch_slack(BuildMethod::ispars2, SparsVariant::stretch));
  EXPECT_TRUE(reads_stretch_slack(BuildMethod::ispars, SparsVariant::stretch));
  EXPECT_TRUE(reads_stretch_slack(BuildMethod::spars, SparsVariant::stretch));
  EXPECT_FALSE(reads_stretch_slack(BuildMethod::ispars, SparsVariant::alg1));
  EXPECT_FALSE(reads_stretch_slack(BuildMethod::dense, SparsVariant::stretch));
  EXPECT_FALSE(reads_stretch_slack(BuildMethod::irisc, SparsVariant::stretch));
}

TEST(BuildRecipe, RecipeJsonRoundTripsAndOldRecipesReadAsAlg1) {
  RoadmapRecipe r{
      "tower", BuildMethod::irisc, 9, 0.3, SparsVariant::alg1, 1.25, 2.5, 1.5, 42, "0123456789abcdef", 7, 0.375, 20000};
  const RoadmapRecipe back = recipe_from_json(recipe_to_json(r));
  // The edits below make files as older versions wrote them (or as a hand edit leaves them):
  // without the seal, which a changed value would fail first (sealed_file.hpp).
  const auto unsealed = [](const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_TRUE(j.contains("crc32"));
    j.erase("crc32");
    return j.dump(2) + "\n";
  };
  EXPECT_EQ(back.stretch_slack, 0.375);
  EXPECT_EQ(back.stretch_slack_after, 20000u);
  // A count is written as an integer; a file from when it was written as a real reads the same.
  std::string written = unsealed(recipe_to_json(r));
  ASSERT_NE(written.find("\"stretch_slack_after\": 20000,"), std::string::npos) << written;
  written.replace(written.find("\"stretch_slack_after\": 20000,"), std::string("\"stretch_slack_after\": 20000").size(),
                  "\"stretch_slack_after\": 20000.0");
  EXPECT_EQ(recipe_from_json(written).stretch_slack_after, 20000u);
  EXPECT_TRUE(same_roadmap(back, r));
  RoadmapRecipe no_slack = r;
  no_slack.stretch_slack = 0.0;
  EXPECT_FALSE(same_roadmap(back, no_slack)) << "the slack changes the roadmap";
  RoadmapRecipe slack_from_start = r;
  slack_from_start.stretch_slack_after = 0;
  EXPECT_FALSE(same_roadmap(back, slack_from_start)) << "where the slack starts changes the roadmap";
  EXPECT_EQ(back.scene, "tower");
  EXPECT_EQ(back.method, BuildMethod::irisc);
  EXPECT_EQ(back.seed, 9u);
  EXPECT_EQ(back.p_accept, 0.3);
  EXPECT_EQ(back.variant, SparsVariant::alg1);
  EXPECT_EQ(back.dense_delta, 1.25);
  EXPECT_EQ(back.sparse_delta, 2.5);
  EXPECT_EQ(back.stretch, 1.5);
  EXPECT_EQ(back.generation, 42u);
  EXPECT_EQ(back.scene_fingerprint, "0123456789abcdef");
  EXPECT_EQ(back.builder_version, 7u);
  // A store of a newer format is refused by name; one that predates fingerprints reads without.
  std::string newer = unsealed(recipe_to_json(r));
  newer.replace(newer.find("\"format\": 1"), std::string("\"format\": 1").size(), "\"format\": 2");
  try {
    (void)recipe_from_json(newer);
    FAIL() << "a newer format was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("format 2, newer than this ispars reads (1)"), std::string::npos) << e.what();
  }
  const RoadmapRecipe old_store = recipe_from_json(
      R"({"scene": "t", "method": "ispars", "seed": 1, "p_accept": 0.2, "dense_delta": 1, "sparse_delta": 2,
          "stretch": 3, "generation": 4, "format": 1})");
  EXPECT_TRUE(old_store.scene_fingerprint.empty());
  EXPECT_EQ(old_store.stretch_slack, 0.0) << "a recipe from before the slack was built without one";
  EXPECT_EQ(old_store.stretch_slack_after, 0u);
  // A slack outside [0, 1] (a damaged or hand-edited file) is refused by name.
  std::string bad = unsealed(recipe_to_json(r));
  bad.replace(bad.find("\"stretch_slack\": 0.375"), std::string("\"stretch_slack\": 0.375").size(),
              "\"stretch_slack\": 4");
  try {
    (void)recipe_from_json(bad);
    FAIL() << "a slack of 4 was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("stretch_slack: must be in [0, 1]"), std::string::npos) << e.what();
  }
  // So is a start that is not a whole sample.
  std::string half = unsealed(recipe_to_json(r));
  half.replace(half.find("\"stretch_slack_after\": 20000,"), std::string("\"stretch_slack_after\": 20000").size(),
               "\"stretch_slack_after\": 2.5");
  try {
    (void)recipe_from_json(half);
    FAIL() << "a start of 2.5 samples was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("stretch_slack_after: must be a whole number"), std::string::npos) << e.what();
  }
  EXPECT_EQ(old_store.builder_version, 0u);
  EXPECT_THROW((void)recipe_from_json("{"), std::runtime_error);
  EXPECT_THROW((void)recipe_from_json(R"({"scene": "t"})"), std::runtime_error);
}

}  // namespace
}  // namespace ispars
