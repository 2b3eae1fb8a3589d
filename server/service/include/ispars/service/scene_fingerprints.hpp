#pragma once
// The fingerprint of each scene file as this daemon would load it now, remembered per scene
// until one of its files (the YAML, its mesh, its POI file) changes size or modification time.

#include <filesystem>
#include <map>
#include <mutex>
#include <string>

namespace ispars::service {

/// A scene file's current fingerprint (scene_fingerprint() of the scene it builds), or why it
/// has none here (the file is gone, or does not load).
struct CurrentFingerprint {
  std::string fingerprint;  ///< Empty when `problem` says why.
  std::string problem;
};

/// Fingerprints of the scenes of one scene directory, each computed once per version of its files
/// (a scene build: a tenth of a second to a few seconds). Safe to call from many threads.
class SceneFingerprints {
 public:
  explicit SceneFingerprints(std::filesystem::path scene_dir) : scene_dir_(std::move(scene_dir)) {}

  /// The fingerprint of scene `name` as its files are now.
  [[nodiscard]] CurrentFingerprint of(const std::string& name);

 private:
  struct Known {
    std::string stamp;  // sizes and modification times of the scene's files
    CurrentFingerprint value;
  };
  std::filesystem::path scene_dir_;
  std::mutex mutex_;
  std::map<std::string, Known> known_;
};

}  // namespace ispars::service
