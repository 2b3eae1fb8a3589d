#pragma once
// numpy arrays over the library's contiguous arrays: read-only views kept alive by their owner,
// or arrays that take over a vector. Neither copies element by element nor makes a Python object
// per element.

#include <span>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"
#include "python_module.hpp"

namespace ispars::python {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(sizeof(EdgeEnds) == 2 * sizeof(std::uint32_t), "EdgeEnds must be two packed ids");

/// A read-only rows x cols view of `data`, which `owner` keeps alive (rows may be 0).
template <class T>
py::array_t<T> view(const T* data, std::size_t rows, std::size_t cols, py::handle owner) {
  const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)};
  const std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(cols * sizeof(T)),
                                         static_cast<py::ssize_t>(sizeof(T))};
  static const T empty{};
  py::array_t<T> a(shape, strides, rows == 0 ? &empty : data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// Points as a read-only n x 3 view.
inline py::array_t<double> points_view(std::span<const Vec3> points, py::handle owner) {
  return view(reinterpret_cast<const double*>(points.data()), points.size(), 3, owner);
}

/// A numpy array that takes over `values` (shape `shape`; the product must be values.size()).
template <class T>
py::array_t<T> take(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* held = new std::vector<T>(std::move(values));
  py::capsule free(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  static const T empty{};
  return py::array_t<T>(shape, held->empty() ? &empty : held->data(), free);
}

/// Points taken over as an n x 3 array (writable: the caller owns it).
inline py::array_t<double> take_points(std::vector<Vec3>&& points) {
  auto* held = new std::vector<Vec3>(std::move(points));
  py::capsule free(held, [](void* p) { delete static_cast<std::vector<Vec3>*>(p); });
  static const double empty = 0;
  const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(held->size()), 3};
  return py::array_t<double>(shape, held->empty() ? &empty : reinterpret_cast<const double*>(held->data()), free);
}

/// A point from anything numpy reads as three numbers; TypeError/ValueError otherwise.
Vec3 to_vec3(const py::handle& value, const char* name);
/// An n x 3 array of points (n may be 0) as a vector.
std::vector<Vec3> to_points(const py::handle& value, const char* name);
/// A 1-D array (or sequence) of whole numbers, refused with InputError(file, field) when it holds
/// anything else: a float such as 1.5 is never truncated to an id. Empty sequences are allowed.
std::vector<std::int64_t> to_whole_numbers(const py::handle& value, const char* file, const char* field);
/// A Python int (or numpy integer) in [lo, hi], bool refused; InputError(file, field) naming the
/// range otherwise, never pybind11's TypeError.
std::int64_t to_whole_number(const py::handle& value, const char* file, const char* field, std::int64_t lo,
                             std::int64_t hi);
/// The same for unsigned 64-bit values (seeds): 0 .. 2^64 - 1.
std::uint64_t to_unsigned_64(const py::handle& value, const char* file, const char* field);

}  // namespace ispars::python
