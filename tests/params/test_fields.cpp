// A struct's declared parameters: the range check, names, text, overlays and the count of its
// members against its declarations.

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "ispars/params/fields.hpp"

namespace ispars::params {
namespace {

constexpr Spec<double> kTankRadius{"radius", 0.0, 10.0, "the radius", Lower::open};
constexpr Spec<std::uint64_t> kTankCount{"count", 0, 100, "the count"};
constexpr Spec<double> kStrayUnused{"unused", 0.0, 1.0, "declared by no target"};

struct Tank {
  double radius = 1.0;
  std::uint64_t count = 3;
  static void describe(auto& self, auto&& field) {
    field(kTankRadius, self.radius);
    field(kTankCount, self.count);
  }
};

struct TankOverrides {
  std::optional<double> radius;
  std::optional<std::uint64_t> count;
  static void describe(auto& self, auto&& field) {
    field(kTankRadius, self.radius);
    field(kTankCount, self.count);
  }
};

struct Stray {
  std::optional<double> unused;
  static void describe(auto& self, auto&& field) { field(kStrayUnused, self.unused); }
};

std::string fields_error_of(auto&& f) {
  try {
    f();
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamFields, NamesCountsAndHelpComeFromTheDeclarations) {
  EXPECT_EQ(names<Tank>(), "radius, count");
  EXPECT_EQ(field_count<Tank>(), 2u);
  EXPECT_EQ(aggregate_size<Tank>(), 2u);
  EXPECT_EQ(aggregate_size<TankOverrides>(), 2u);
  EXPECT_NE(help<Tank>().find("count (INT): the count; a whole number in [0, 100]"), std::string::npos) << help<Tank>();
}

TEST(ParamFields, TheCheckNamesTheFirstMemberOutOfRangeAndSkipsAbsentOnes) {
  Tank t;
  EXPECT_EQ(fields_error_of([&] { check(t, "tank.yaml"); }), "");
  t.radius = 0.0;
  EXPECT_EQ(fields_error_of([&] { check(t, "tank.yaml", "tank."); }),
            "tank.yaml: tank.radius: must be in (0, 10], got 0");
  TankOverrides o;
  EXPECT_EQ(fields_error_of([&] { check(o, "request"); }), "") << "absent optionals are not checked";
  o.count = 101;
  EXPECT_EQ(fields_error_of([&] { check(o, "request"); }),
            "request: count: must be a whole number in [0, 100], got 101");
}

TEST(ParamFields, TextSetsTheNamedMemberAsDeclaredOrNamesWhatIsWrong) {
  TankOverrides o;
  set_text(o, "count", "7", "--set");
  EXPECT_EQ(o.count, 7u);
  EXPECT_FALSE(o.radius);
  EXPECT_EQ(fields_error_of([&] { set_text(o, "count", "-7", "--set"); }),
            "--set: count: must be a whole number in [0, 100], got -7");
  EXPECT_EQ(fields_error_of([&] { set_text(o, "colour", "1", "--set"); }),
            "--set: colour: unknown parameter (expected one of radius, count)");
  EXPECT_LT(fields_error_of([&] { set_text(o, std::string(10'000, 'x'), "1", "--set"); }).size(), 200u)
      << "a long unknown name is cut, not echoed";
  EXPECT_EQ(o.count, 7u) << "a refused value changes nothing";
}

TEST(ParamFields, AnOverlayCopiesWhatIsGivenOntoTheSameDeclaration) {
  Tank t;
  TankOverrides o;
  o.count = 9;
  overlay(o, t);
  EXPECT_EQ(t.count, 9u);
  EXPECT_EQ(t.radius, 1.0) << "an absent override keeps the value";
  const Stray stray{0.5};
  EXPECT_THROW(overlay(stray, t), std::logic_error) << "an override with no member to override";
}

}  // namespace
}  // namespace ispars::params
