#include "ispars/cli_app/whole_number.hpp"

#include "ispars/params/spec.hpp"

namespace ispars::cli_app {

CLI::Validator whole_number(std::uint64_t min, std::uint64_t max) {
  const params::Spec<std::uint64_t> spec{"", min, max, ""};
  return CLI::Validator([spec](std::string& text) { return params::parse(spec, text).problem; },
                        params::range_text(spec));
}

}  // namespace ispars::cli_app
