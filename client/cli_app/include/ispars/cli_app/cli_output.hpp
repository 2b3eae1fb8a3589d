#pragma once
// What the `ispars` command prints: a scene's status (text or JSON), live progress, and files.

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "ispars/client/client.hpp"

namespace ispars::cli_app {

/// A scene's status as one JSON object.
[[nodiscard]] nlohmann::json status_json(const client::SceneStatus& s);
/// A scene's status as a few lines of text.
void print_status(const client::SceneStatus& s);

/// One line of live progress: redrawn in place on a terminal, one line per second otherwise.
class Progress {
 public:
  explicit Progress(bool enabled);
  void operator()(const client::SceneStatus& s);
  void finish();

 private:
  bool enabled_;
  bool tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

/// After a build or extend request: its reply's message (unless `json`), then with `wait` its
/// progress until the scene is idle, then the final status (text, or JSON with `json`). Exit
/// code 1 when a followed job failed, else 0.
int follow_job(client::Client& client, const std::string& scene, const client::Reply& reply, bool wait, bool json);

/// Writes `text` to `path`, throwing CLI::ValidationError("--out", ...) on failure.
void write_text(const std::string& path, const std::string& text);

}  // namespace ispars::cli_app
