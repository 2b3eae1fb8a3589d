#pragma once
// A struct's parameters, each declared once in its `describe`, and the archives every caller
// shares: the range check, the names, text (a flag's or `--set NAME=VALUE`'s), an overlay of
// optional overrides onto the values they override, and a help text.
//
// A struct declares its parameters as Drake's Serialize visitor does, in one static member:
//
//   struct Tank {
//     double radius = 1.0;
//     std::optional<std::uint64_t> count;  // optional: absent unless given
//     static void describe(auto& self, auto&& field) {
//       field(kRadius, self.radius);        // kRadius: a Spec<double> (spec.hpp)
//       field(kCount, self.count);
//     }
//   };
//
// `field` is called with each declaration and the member it declares, const or not as `self` is.

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "ispars/params/input_error.hpp"
#include "ispars/params/spec.hpp"

namespace ispars::params {

template <class U>
struct is_optional : std::false_type {};
template <class U>
struct is_optional<std::optional<U>> : std::true_type {};

template <class U>
struct unwrap_optional : std::type_identity<U> {};
template <class U>
struct unwrap_optional<std::optional<U>> : std::type_identity<U> {};

/// The value type of a declared member: T for T and for std::optional<T>.
template <class Member>
using value_type_of = typename unwrap_optional<std::remove_cvref_t<Member>>::type;

/// Calls `f(spec, member)` for each parameter `object` declares, in declaration order.
template <class Object, class F>
void visit(Object& object, F&& f) {
  std::remove_const_t<Object>::describe(object, f);
}

/// How many parameters `Object` declares.
template <class Object>
[[nodiscard]] std::size_t field_count() {
  std::size_t n = 0;
  const Object object{};
  visit(object, [&](const auto&, const auto&) { ++n; });
  return n;
}

namespace detail {
struct any_member {
  template <class U>
  operator U() const;  // NOLINT: converts to any member type (declared only, for the count below)
};
template <class T, class... A>
constexpr std::size_t aggregate_size(A... a) {
  if constexpr (requires { T{a..., any_member{}}; }) {
    return aggregate_size<T>(a..., any_member{});
  } else {
    return sizeof...(A);
  }
}
}  // namespace detail

/// How many members the aggregate `T` has (no base classes): a test compares it with
/// field_count<T>() so that a member added without its declaration fails it.
template <class T>
[[nodiscard]] constexpr std::size_t aggregate_size() {
  return detail::aggregate_size<T>();
}

/// The declared names, for help texts and errors: "dense_delta, sparse_delta, stretch".
template <class Object>
[[nodiscard]] std::string names() {
  std::string out;
  const Object object{};
  visit(object, [&](const auto& spec, const auto&) { out += (out.empty() ? "" : ", ") + std::string(spec.name); });
  return out;
}

/// Throws InputError(source, prefix + name, problem) for the first member out of its declared
/// range (an absent optional is not checked).
template <class Object>
void check(const Object& object, std::string_view source, std::string_view prefix = {}) {
  visit(object, [&](const auto& spec, const auto& member) {
    using M = std::remove_cvref_t<decltype(member)>;
    if constexpr (is_optional<M>::value) {
      if (!member) return;
      if (std::string p = problem(spec, *member); !p.empty())
        throw InputError(std::string(source), std::string(prefix) + std::string(spec.name), p);
    } else {
      if (std::string p = problem(spec, member); !p.empty())
        throw InputError(std::string(source), std::string(prefix) + std::string(spec.name), p);
    }
  });
}

/// Sets the member named `name` from `text`, read and range-checked as its declaration says.
/// Throws InputError(source, prefix + name, ...) for an unknown name or a bad value.
template <class Object>
void set_text(Object& object, std::string_view name, std::string_view text, std::string_view source,
              std::string_view prefix = {}) {
  bool found = false;
  const std::string field = std::string(prefix) + std::string(name.substr(0, 64));
  visit(object, [&](const auto& spec, auto& member) {
    if (spec.name != name) return;
    found = true;
    const auto parsed = parse(spec, text);
    if (!parsed.problem.empty()) throw InputError(std::string(source), field, parsed.problem);
    member = parsed.value;
  });
  if (!found) {
    throw InputError(std::string(source), field, "unknown parameter (expected one of " + names<Object>() + ")");
  }
}

/// Calls `f(spec, a_member, b_member)` for each member of `a` and `b` with the same declaration
/// (the same Spec object), in `a`'s order; returns how many of `a`'s members had one in `b`.
template <class A, class B, class F>
std::size_t for_matching(A& a, B& b, F&& f) {
  std::size_t matched = 0;
  visit(a, [&](const auto& spec, auto& a_member) {
    visit(b, [&](const auto& b_spec, auto& b_member) {
      if constexpr (std::is_same_v<decltype(&spec), decltype(&b_spec)>) {
        if (&spec == &b_spec) {
          f(spec, a_member, b_member);
          ++matched;
        }
      }
    });
  });
  return matched;
}

/// Copies each override `from` gives onto the member of `to` with the same declaration.
/// std::logic_error when `to` lacks one of `from`'s declarations: a programming error.
template <class From, class To>
void overlay(const From& from, To& to) {
  const std::size_t matched = for_matching(from, to, [](const auto&, const auto& given, auto& member) {
    if (given) member = *given;
  });
  if (matched != field_count<From>()) throw std::logic_error("an override with no member to override");
}

/// One line per parameter: "  name (TYPE): doc; range".
template <class Object>
[[nodiscard]] std::string help() {
  std::string out;
  const Object object{};
  visit(object, [&](const auto& spec, const auto& member) {
    using T = value_type_of<decltype(member)>;
    out += "\n  " + std::string(spec.name) + " (" + std::string(type_name<T>()) + "): " + std::string(spec.doc) + "; " +
           range_text(spec);
  });
  return out;
}

}  // namespace ispars::params
