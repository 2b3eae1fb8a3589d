// Declared parameters to and from JSON: typed, checked, absent optionals left out.

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>

#include "ispars/params/json_archive.hpp"

namespace ispars::params {
namespace {

constexpr Spec<double> kValveRadius{"radius", 0.0, 10.0, "the radius", Lower::open};
constexpr Spec<std::uint64_t> kValveCount{"count", 0, 1'000'000'000'000, "the count"};
constexpr Spec<bool> kValveOpen{"open", false, true, "whether it is open"};

struct Valve {
  std::optional<double> radius;
  std::optional<std::uint64_t> count;
  bool open = false;
  static void describe(auto& self, auto&& field) {
    field(kValveRadius, self.radius);
    field(kValveCount, self.count);
    field(kValveOpen, self.open);
  }
  bool operator==(const Valve&) const = default;
};

std::string valve_read_error(const std::string& text) {
  Valve v;
  try {
    read_json(nlohmann::json::parse(text), v, "valve.json");
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamJson, EveryMemberRoundTripsInItsTypeAndAbsentOnesStayOut) {
  const Valve v{2.5, 123'456'789'012, true};
  nlohmann::json j = nlohmann::json::object();
  write_json(v, j);
  EXPECT_EQ(j.dump(), R"({"count":123456789012,"open":true,"radius":2.5})");
  Valve back;
  read_json(j, back, "valve.json");
  EXPECT_EQ(back, v);
  nlohmann::json empty = nlohmann::json::object();
  write_json(Valve{}, empty);
  EXPECT_EQ(empty.dump(), R"({"open":false})");
}

TEST(ParamJson, ACountWrittenAsAWholeRealReadsTheSameAndEveryBadValueIsNamed) {
  Valve v;
  read_json(nlohmann::json::parse(R"({"count": 20000.0})"), v, "valve.json");
  EXPECT_EQ(v.count, 20000u);
  EXPECT_EQ(valve_read_error(R"({"count": 2.5})"),
            "valve.json: count: must be a whole number in [0, 1000000000000], got 2.5");
  EXPECT_EQ(valve_read_error(R"({"count": -1})"),
            "valve.json: count: must be a whole number in [0, 1000000000000], got -1");
  EXPECT_EQ(valve_read_error(R"({"count": "5"})"), "valve.json: count: expected a whole number, got \"5\"");
  EXPECT_EQ(valve_read_error(R"({"radius": 0})"), "valve.json: radius: must be in (0, 10], got 0");
  EXPECT_EQ(valve_read_error(R"({"radius": true})"), "valve.json: radius: expected a number, got true");
  EXPECT_EQ(valve_read_error(R"({"open": 1})"), "valve.json: open: expected true or false, got 1");
  EXPECT_EQ(valve_read_error(R"([1])"), "valve.json: : expected a JSON object");
}

}  // namespace
}  // namespace ispars::params
