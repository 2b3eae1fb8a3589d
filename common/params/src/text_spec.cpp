#include "ispars/params/text_spec.hpp"

#include <fmt/format.h>

namespace ispars::params {

std::string problem(const TextSpec& spec, const std::string& text) {
  if (text.size() > spec.max_length) return fmt::format("is longer than {} characters", spec.max_length);
  return spec.rule ? spec.rule(text) : std::string();
}

std::string problem(const ListSpec& spec, const std::vector<std::string>& items) {
  if (items.size() > spec.max_items) return fmt::format("has more than {} items", spec.max_items);
  for (const std::string& item : items) {
    if (item.size() > spec.max_item_length) {
      return fmt::format("has an item longer than {} characters", spec.max_item_length);
    }
  }
  return {};
}

}  // namespace ispars::params
