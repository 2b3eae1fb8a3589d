#include "ispars/roadmap/build_request.hpp"

#include <fmt/format.h>

#include <string>

#include "ispars/params/input_error.hpp"

namespace ispars {

void set_method(BuildRequest& request, std::string_view method, std::string_view variant, std::string_view file) {
  const auto parsed_method = parse_build_method(method);
  if (!parsed_method) {
    throw params::InputError(std::string(file), "method",
                             fmt::format("'{}' is not one of {}", method.substr(0, 64), build_method_names()));
  }
  request.method = *parsed_method;
  request.variant.reset();
  if (variant.empty()) return;
  const auto parsed_variant = parse_spars_variant(variant);
  if (!parsed_variant) {
    throw params::InputError(std::string(file), "variant",
                             fmt::format("'{}' is not one of {}", variant.substr(0, 64), spars_variant_names()));
  }
  request.variant = *parsed_variant;
}

BuildRequest request_of(std::string_view method, std::uint64_t samples) {
  BuildRequest request;
  set_method(request, method, "", "request");
  request.samples = samples;
  return request;
}

}  // namespace ispars
