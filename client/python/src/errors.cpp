// The library's exceptions as Python's: ispars.InputError (a ValueError) with file, field and
// problem, as the CLI prints them; ispars.ClientError (a RuntimeError) with its kind.

#include <string>

#if ISPARS_PYTHON_CLIENT
#include "ispars/client/client.hpp"
#endif
#include "ispars/params/input_error.hpp"
#include "python_module.hpp"

namespace ispars::python {
namespace {

#if ISPARS_PYTHON_CLIENT
std::string kind_name(client::ClientError::Kind kind) {
  switch (kind) {
    case client::ClientError::Kind::no_daemon:
      return "no_daemon";
    case client::ClientError::Kind::timeout:
      return "timeout";
    case client::ClientError::Kind::rejected:
      return "rejected";
    case client::ClientError::Kind::protocol:
      return "protocol";
    case client::ClientError::Kind::forbidden:
      return "forbidden";
  }
  return "unknown";
}
#endif

// Raises an instance of `type` with message `what` and the attributes `fields`.
void raise(PyObject* type, const char* what, const py::dict& fields) {
  py::object error = py::reinterpret_borrow<py::object>(type)(what);
  for (const auto& [key, value] : fields) error.attr(key) = value;
  PyErr_SetObject(type, error.ptr());
}

}  // namespace

void bind_errors(py::module_& m) {
  // Held for the interpreter's life, as pybind11's own registered exceptions are.
  static PyObject* const input_error = PyErr_NewExceptionWithDoc(
      "ispars.InputError",
      "Bad input: a scene file, a roadmap file, or a parameter. str() is 'FILE: FIELD: PROBLEM', "
      "as the CLI prints it; .file, .field and .problem hold the parts.",
      PyExc_ValueError, nullptr);
  static PyObject* const client_error = PyErr_NewExceptionWithDoc(
      "ispars.ClientError",
      "A failed call to isparsd. .kind is 'no_daemon', 'timeout', 'rejected' (the daemon refused; "
      "the message says why), 'protocol' or 'forbidden' (this identity may not send it).",
      PyExc_RuntimeError, nullptr);
  m.add_object("InputError", py::handle(input_error));
  m.add_object("ClientError", py::handle(client_error));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const params::InputError& e) {
      py::dict fields;
      fields["file"] = e.file();
      fields["field"] = e.field();
      fields["problem"] = e.problem();
      raise(input_error, e.what(), fields);
#if ISPARS_PYTHON_CLIENT
    } catch (const client::ClientError& e) {
      py::dict fields;
      fields["kind"] = kind_name(e.kind());
      raise(client_error, e.what(), fields);
#endif
    }
  });
}

}  // namespace ispars::python
