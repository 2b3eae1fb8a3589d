#pragma once
// The one exception type for bad user input: it names the file and the field at fault.

#include <stdexcept>
#include <string>

namespace ispars::params {

/// Bad input from a user (a scene file, a mesh, a request). what() is one line:
/// "FILE: FIELD: PROBLEM", so a tool can print it as it is and exit with code 2.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::string field, std::string problem);

  /// The file (or request) that holds the bad value.
  [[nodiscard]] const std::string& file() const { return file_; }
  /// The field at fault, dotted for nested fields ("pois.count"), or "yaml" for syntax errors.
  [[nodiscard]] const std::string& field() const { return field_; }
  /// What is wrong, without the file and field.
  [[nodiscard]] const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string field_;
  std::string problem_;
};

}  // namespace ispars::params
