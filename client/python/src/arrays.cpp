#include "arrays.hpp"

#include <fmt/format.h>

#include <limits>
#include <string>

#include "ispars/params/input_error.hpp"

namespace ispars::python {

Vec3 to_vec3(const py::handle& value, const char* name) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 1 || a.shape(0) != 3) {
    throw py::value_error(std::string(name) + ": expected three numbers (x, y, z)");
  }
  return {a.at(0), a.at(1), a.at(2)};
}

std::vector<Vec3> to_points(const py::handle& value, const char* name) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || (!(a.ndim() == 2 && a.shape(1) == 3) && !(a.ndim() == 1 && a.shape(0) == 0))) {
    throw py::value_error(std::string(name) + ": expected an (n, 3) array of points");
  }
  const auto n = static_cast<std::size_t>(a.ndim() == 2 ? a.shape(0) : 0);
  std::vector<Vec3> out(n);
  const double* d = a.data();
  for (std::size_t i = 0; i < n; ++i) out[i] = Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
  return out;
}

}  // namespace ispars::python

namespace ispars::python {
namespace {

// `value` as a Python int: an int or a numpy integer (anything with __index__), not a bool.
py::int_ as_int(const py::handle& value, const char* file, const char* field) {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) {
    throw params::InputError(file, field,
                             fmt::format("must be a whole number, got {}", py::repr(value).cast<std::string>()));
  }
  PyObject* index = PyNumber_Index(value.ptr());
  if (index == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::int_>(index);
}

}  // namespace

std::vector<std::int64_t> to_whole_numbers(const py::handle& value, const char* file, const char* field) {
  const py::array a = py::array::ensure(value);
  if (!a || a.ndim() != 1) throw params::InputError(file, field, "expected a 1-D array (or list) of whole numbers");
  if (a.size() == 0) return {};
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u') {
    throw params::InputError(file, field,
                             fmt::format("expected whole numbers, got an array of dtype {} (a float is never "
                                         "truncated to an id)",
                                         py::str(a.dtype()).cast<std::string>()));
  }
  if (kind == 'u' && a.itemsize() == 8) {
    const auto big = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (py::ssize_t i = 0; i < big.shape(0); ++i) {
      if (big.at(i) > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        throw params::InputError(file, field, fmt::format("{} is out of range", big.at(i)));
      }
    }
  }
  const auto ints = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  return {ints.data(), ints.data() + ints.shape(0)};
}

std::int64_t to_whole_number(const py::handle& value, const char* file, const char* field, std::int64_t lo,
                             std::int64_t hi) {
  const py::int_ n = as_int(value, file, field);
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(n.ptr(), &overflow);
  if (overflow != 0 || x < lo || x > hi) {
    throw params::InputError(
        file, field,
        fmt::format("must be a whole number in [{}, {}], got {}", lo, hi, py::repr(n).cast<std::string>()));
  }
  return x;
}

std::uint64_t to_unsigned_64(const py::handle& value, const char* file, const char* field) {
  const py::int_ n = as_int(value, file, field);
  const unsigned long long x = PyLong_AsUnsignedLongLong(n.ptr());
  if (PyErr_Occurred() != nullptr) {
    PyErr_Clear();
    throw params::InputError(file, field,
                             fmt::format("must be a whole number in [0, {}], got {}",
                                         std::numeric_limits<std::uint64_t>::max(), py::repr(n).cast<std::string>()));
  }
  return x;
}

}  // namespace ispars::python
