#pragma once
// What the `ispars` command prints: a scene's status (text or JSON), live progress, and files.

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "ispars/wire/convert.hpp"

namespace ispars::cli {

/// A scene's status as one JSON object.
[[nodiscard]] nlohmann::json status_json(const msg::SceneStatus& s);
/// A scene's status as a few lines of text.
void print_status(const msg::SceneStatus& s);

/// One line of live progress: redrawn in place on a terminal, one line per second otherwise.
class Progress {
 public:
  explicit Progress(bool enabled);
  void operator()(const msg::SceneStatus& s);
  void finish();

 private:
  bool enabled_;
  bool tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

/// Writes `text` to `path`, throwing CLI::ValidationError("--out", ...) on failure.
void write_text(const std::string& path, const std::string& text);

}  // namespace ispars::cli
