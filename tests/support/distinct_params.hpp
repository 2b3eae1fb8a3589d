#pragma once
// Declared parameters given values that tell them apart (RocksDB's options_settable_test idea):
// each member a distinct value inside its range and unlike every default, so that an archive
// that drops or swaps a member fails the round trip that carries it.

#include <charconv>
#include <string>
#include <type_traits>

#include "ispars/params/fields.hpp"

namespace ispars::test {

/// A value inside `spec`'s range, distinct for each i >= 1 and from every default.
template <class T>
T value_within(const params::Spec<T>& spec, int i) {
  if constexpr (std::is_same_v<T, double>) {
    return spec.min + (spec.max - spec.min) * i / 17.0;
  } else {
    return spec.min + static_cast<T>(i) + 1000;
  }
}

/// `v` as the shortest text that reads back exactly.
template <class T>
std::string exact_text(T v) {
  char text[64];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

/// `Object` with every declared member set, each to its own distinct value.
template <class Object>
Object distinct_values() {
  Object o{};
  int i = 0;
  params::visit(o, [&](const auto& spec, auto& member) { member = value_within(spec, ++i); });
  return o;
}

}  // namespace ispars::test
