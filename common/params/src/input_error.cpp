#include "ispars/params/input_error.hpp"

#include <utility>

namespace ispars::params {

InputError::InputError(std::string file, std::string field, std::string problem)
    : std::runtime_error(file + ": " + field + ": " + problem),
      file_(std::move(file)),
      field_(std::move(field)),
      problem_(std::move(problem)) {}

}  // namespace ispars::params
