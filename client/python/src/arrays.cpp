#include "arrays.hpp"

#include <string>

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
