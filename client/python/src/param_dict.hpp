#pragma once
// A struct's declared parameters (params/fields.hpp) from and to Python dicts: each key a
// declared name, a count given as a Python int (read as signed, so -1 is refused by its range,
// never wrapped), a real as an int or a float; a bool is neither. Every refusal an InputError
// naming the key.

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "ispars/params/fields.hpp"

namespace ispars::python {

namespace py = pybind11;

namespace detail {
template <class T>
T python_value(const params::Spec<T>& spec, const py::handle& v, const std::string& file, const std::string& field) {
  const auto fail = [&](const std::string& p) { throw params::InputError(file, field, p); };
  const std::string shown = py::repr(v).cast<std::string>().substr(0, 64);
  if constexpr (std::is_same_v<T, bool>) {
    if (!py::isinstance<py::bool_>(v)) fail("expected True or False, got " + shown);
    return v.cast<bool>();
  } else {
    if (py::isinstance<py::bool_>(v)) fail("expected a number, got " + shown);
    if constexpr (std::is_same_v<T, double>) {
      if (!py::isinstance<py::int_>(v) && !py::isinstance<py::float_>(v)) fail("expected a number, got " + shown);
      const double value = v.cast<double>();
      if (std::string p = params::problem(spec, value); !p.empty()) fail(p);
      return value;
    } else {
      if (!py::isinstance<py::int_>(v)) fail("must be " + params::range_text(spec) + ", got " + shown);
      const params::Parsed<T> parsed = params::parse(spec, py::str(v).cast<std::string>());
      if (!parsed.problem.empty()) fail(parsed.problem);
      return parsed.value;
    }
  }
}
}  // namespace detail

/// Sets each member of `object` that `values` names, read and checked as declared. Throws
/// InputError (file `file`, field prefix + key) for an unknown key or a bad value.
template <class Object>
void read_dict(const py::dict& values, Object& object, const std::string& file, const std::string& prefix) {
  for (const auto& [key, value] : values) {
    const std::string name = py::str(key).cast<std::string>();
    bool found = false;
    params::visit(object, [&](const auto& spec, auto& member) {
      if (spec.name != name) return;
      found = true;
      member = detail::python_value(spec, value, file, prefix + name);
    });
    if (!found) {
      throw params::InputError(file, prefix + name.substr(0, 64),
                               "unknown parameter (expected one of " + params::names<Object>() + ")");
    }
  }
}

/// `overrides` and the keyword arguments `named` in one dict (Builder(scene, stretch=1.5) and
/// Builder(scene, overrides={"stretch": 1.5}) alike). InputError (file `file`, field prefix + name)
/// for a name given both ways.
inline py::dict merged(const py::dict& overrides, const py::kwargs& named, const std::string& file,
                       const std::string& prefix) {
  py::dict out;  // a new dict: `overrides` may be the binding's one default, shared by every call
  for (const auto& [key, value] : overrides) out[key] = value;
  for (const auto& [key, value] : named) {
    if (out.contains(key)) {
      throw params::InputError(file, prefix + py::str(key).cast<std::string>(),
                               "given twice (in overrides and as a keyword)");
    }
    out[key] = value;
  }
  return out;
}

/// Each parameter `Object` declares, as Python reads it: a dict of name, type ("float", "int",
/// "bool"), min, max, range (in words) and doc, in declaration order.
template <class Object>
py::list declarations() {
  py::list out;
  const Object object{};
  params::visit(object, [&](const auto& spec, const auto& member) {
    using T = params::value_type_of<decltype(member)>;
    py::dict d;
    d["name"] = std::string(spec.name);
    d["type"] = std::is_same_v<T, double> ? "float" : std::is_same_v<T, bool> ? "bool" : "int";
    d["min"] = spec.min;
    d["max"] = spec.max;
    d["range"] = params::range_text(spec);
    d["doc"] = std::string(spec.doc);
    out.append(d);
  });
  return out;
}

/// Each declared member of `object` into `out` under its name (an absent optional left out).
template <class Object>
void write_dict(const Object& object, py::dict& out) {
  params::visit(object, [&](const auto& spec, const auto& member) {
    using M = std::remove_cvref_t<decltype(member)>;
    if constexpr (params::is_optional<M>::value) {
      if (member) out[py::str(std::string(spec.name))] = *member;
    } else {
      out[py::str(std::string(spec.name))] = member;
    }
  });
}

}  // namespace ispars::python
