// A build request on the wire (wire/build_args.hpp): each override a typed member with its
// presence bit, method and variant by name, and what the typed form cannot hold refused by name.

#include <gtest/gtest.h>

#include <bit>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/wire/build_args.hpp"
#include "support/distinct_params.hpp"

namespace ispars::wire {
namespace {

// The decoding error's "field: problem", or "" when it decodes.
std::string decode_error(const msg::BuildArgs& a) {
  try {
    (void)from_message(a, "request");
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.file(), "request");
    return e.field() + ": " + e.problem();
  }
  return "";
}

TEST(BuildArgs, EveryOverrideCrossesTheWireWithItsOwnValueAndTheRestOfTheRequest) {
  BuildRequest r;
  r.method = BuildMethod::spars;
  r.variant = SparsVariant::alg1;
  r.samples = 5000;
  r.seed = 7;
  r.replace = true;
  r.overrides = test::distinct_values<RecipeOverrides>();
  const msg::BuildArgs m = to_message(r);
  EXPECT_EQ(m.overrides().present(), 0x3fu) << "one bit per declared override";
  EXPECT_EQ(m.overrides().stretch_slack_after(), *r.overrides.stretch_slack_after) << "a count travels as an integer";
  EXPECT_EQ(from_message(m, "request"), r);
  // Each alone: its bit alone, and only it comes back.
  params::visit(r.overrides, [&](const auto& spec, const auto&) {
    BuildRequest one;
    params::set_text(one.overrides, spec.name, "1", "test");
    const msg::BuildArgs alone = to_message(one);
    EXPECT_EQ(std::popcount(alone.overrides().present()), 1) << spec.name;
    EXPECT_EQ(from_message(alone, "request").overrides, one.overrides) << spec.name;
  });
}

TEST(BuildArgs, AnAbsentVariantAndAbsentOverridesStayAbsent) {
  const BuildRequest r = request_of("ispars2", 10);
  const msg::BuildArgs m = to_message(r);
  EXPECT_EQ(m.variant().to_string(), "");
  EXPECT_EQ(m.overrides().present(), 0u);
  const BuildRequest back = from_message(m, "request");
  EXPECT_FALSE(back.variant);
  EXPECT_FALSE(back.overrides.any());
  EXPECT_EQ(back.generation, 0u) << "a request always asks for a new roadmap";
}

TEST(BuildArgs, WhatTheTypedFormCannotHoldIsRefusedByName) {
  msg::BuildArgs a = to_message(request_of("ispars", 10));
  a.method("Dense");
  EXPECT_EQ(decode_error(a), "method: 'Dense' is not one of dense, spars, ispars, irisc, ispars2");
  a.method("ispars");
  a.variant("loose");
  EXPECT_EQ(decode_error(a), "variant: 'loose' is not one of stretch, alg1");
  a.variant("");
  a.overrides().present(1u << 6);
  EXPECT_EQ(decode_error(a),
            "overrides: presence bit 6 names an override this daemon does not know (dense_delta, sparse_delta, "
            "stretch, stretch_slack, stretch_slack_after, p_accept)");
  // Values are make_recipe's to check, not the decoder's.
  a.overrides().present(1u << 2);
  a.overrides().stretch(-4);
  a.samples(0);
  EXPECT_EQ(decode_error(a), "");
}

}  // namespace
}  // namespace ispars::wire
