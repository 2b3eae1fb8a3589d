#pragma once
// A struct's declared parameters (fields.hpp) to and from JSON: each under its name, a count as
// a JSON integer, a real as a number, a switch as a boolean; an absent optional is left out.

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <string_view>

#include "ispars/params/fields.hpp"

namespace ispars::params {

/// Each declared member of `object` into `out`, under its name.
template <class Object>
void write_json(const Object& object, nlohmann::json& out) {
  visit(object, [&](const auto& spec, const auto& member) {
    using M = std::remove_cvref_t<decltype(member)>;
    if constexpr (is_optional<M>::value) {
      if (member) out[std::string(spec.name)] = *member;
    } else {
      out[std::string(spec.name)] = member;
    }
  });
}

namespace detail {
template <class T>
T json_value(const Spec<T>& spec, const nlohmann::json& v, std::string_view source, const std::string& field) {
  const auto fail = [&](const std::string& p) { throw InputError(std::string(source), field, p); };
  T value{};
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) fail("expected true or false, got " + v.dump());
    value = v.get<bool>();
  } else if constexpr (std::is_same_v<T, double>) {
    if (!v.is_number()) fail("expected a number, got " + v.dump());
    value = v.get<double>();
  } else {
    if (v.is_number_float() && v.get<double>() != std::floor(v.get<double>()))
      fail("must be " + range_text(spec) + ", got " + v.dump());
    if (!v.is_number() || (v.is_number_integer() && !v.is_number_unsigned()) || v.get<double>() < 0.0 ||
        v.get<double>() > static_cast<double>(spec.max)) {
      fail(v.is_number() ? "must be " + range_text(spec) + ", got " + v.dump()
                         : "expected a whole number, got " + v.dump());
    }
    value = v.is_number_unsigned() ? static_cast<T>(v.get<std::uint64_t>()) : static_cast<T>(v.get<double>());
  }
  if (std::string p = problem(spec, value); !p.empty()) fail(p);
  return value;
}
}  // namespace detail

/// Each declared member that `in` holds, read and checked as declared. Members `in` lacks keep
/// their values; keys `in` holds beyond the declared ones are the caller's. Throws InputError
/// (source, prefix + name) for a value of the wrong type or out of range.
template <class Object>
void read_json(const nlohmann::json& in, Object& object, std::string_view source, std::string_view prefix = {}) {
  if (!in.is_object()) throw InputError(std::string(source), std::string(prefix), "expected a JSON object");
  visit(object, [&](const auto& spec, auto& member) {
    const auto it = in.find(std::string(spec.name));
    if (it == in.end()) return;
    member = detail::json_value(spec, *it, source, std::string(prefix) + std::string(spec.name));
  });
}

}  // namespace ispars::params
