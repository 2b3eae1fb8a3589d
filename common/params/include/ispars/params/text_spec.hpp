#pragma once
// Text and list parameters declared once, as spec.hpp declares numbers: a name, one line of doc,
// a bound on the length, and whether a running daemon must restart to take a change. A text is
// a std::string or a std::filesystem::path (a path in a file is resolved against the file's
// directory); a list is of names.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ispars::params {

/// One text parameter's declaration. Its default is the initialiser of the member it describes.
struct TextSpec {
  std::string_view name;  ///< snake_case; its flag is --name-with-dashes
  std::string_view doc;   ///< one line: what it is
  std::size_t max_length = 4096;
  bool path = false;  ///< a path: a relative one in a file is read from the file's directory
  bool needs_restart = false;
  /// What a value must be besides its length (one of the log levels, say): why not, or empty.
  std::string (*rule)(const std::string& value) = nullptr;
};

/// One list parameter's declaration: names, each at most max_item_length characters.
struct ListSpec {
  std::string_view name;
  std::string_view doc;
  std::size_t max_items = 1024;
  std::size_t max_item_length = 256;
  bool needs_restart = false;
  std::string_view alias = {};  ///< an older name, still accepted as a flag
};

/// Why `text` is not accepted ("is longer than 64 characters", or the rule's words), or empty.
[[nodiscard]] std::string problem(const TextSpec& spec, const std::string& text);
/// Why `items` are not accepted ("has more than 1024 items"), or empty.
[[nodiscard]] std::string problem(const ListSpec& spec, const std::vector<std::string>& items);

}  // namespace ispars::params
