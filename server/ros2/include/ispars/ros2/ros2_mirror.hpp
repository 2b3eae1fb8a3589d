#pragma once
// The daemon's ROS 2 mirror (`isparsd --ros2`): a participant of its own on the daemon's domain
// that publishes each loaded scene's roadmap as visualization_msgs/MarkerArray on
// rt/ispars/<scene>/roadmap and its last flown tour as nav_msgs/Path on rt/ispars/<scene>/tour
// (ros2_markers.hpp), under their REP-2008 type names, with the QoS a latched ROS 2 topic has
// (reliable, transient local, the last sample): RViz2, foxglove_bridge or `ros2 topic echo`
// see the topics with no ispars code. A participant apart from the daemon's own, so the daemon's
// rejoins and partitions never touch it. One thread publishes: the daemon's calls only mark a
// scene, never wait on DDS, and a scene's roadmap is drawn at most once a period, from its
// latest published copy.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"
#include "ispars/wire/participant_options.hpp"

namespace ispars::ros2 {

/// A scene's roadmap as the mirror draws it: the published roadmap and its POIs' positions (the
/// scene's, then its tasks').
struct MirroredRoadmap {
  std::shared_ptr<const Roadmap> roadmap;
  std::vector<Vec3> pois;
};
/// The scene's current roadmap, or nullopt when the scene is not loaded or has none.
using RoadmapSource = std::function<std::optional<MirroredRoadmap>(const std::string& scene)>;

/// How the mirror joins and draws.
struct Ros2MirrorOptions {
  wire::ParticipantOptions participant;   ///< the daemon's domain and profile; the name is set here
  std::string frame = "map";              ///< the frame_id of every header
  std::chrono::milliseconds period{500};  ///< a scene's roadmap is published at most this often
};

/// What the mirror has written, for logs and tests.
struct Ros2Counts {
  std::uint64_t roadmaps = 0;  ///< MarkerArray samples of a roadmap
  std::uint64_t tours = 0;     ///< Path samples
  std::uint64_t clears = 0;    ///< DELETEALL samples (a roadmap dropped, a scene unloaded)
  std::uint64_t refused = 0;   ///< scenes not mirrored: their ROS name is another loaded scene's
};

class Ros2Mirror {
 public:
  /// Joins the domain and starts the publishing thread; throws std::runtime_error when DDS
  /// refuses the participant.
  Ros2Mirror(Ros2MirrorOptions options, RoadmapSource source);
  /// Stops the thread (within one sample's write) and leaves the domain.
  ~Ros2Mirror();
  /// Stops the thread (within one sample's write): the source is not called again, and later
  /// calls below are ignored. Idempotent.
  void stop();
  Ros2Mirror(const Ros2Mirror&) = delete;
  Ros2Mirror& operator=(const Ros2Mirror&) = delete;

  /// The scene's roadmap changed (a commit, a load): it is drawn again within a period.
  void roadmap_changed(const std::string& scene);
  /// A tour of the scene was flown: `stops`, closed at the root, replace its last tour.
  void tour_flown(const std::string& scene, std::vector<Vec3> stops);
  /// The scene's roadmap is gone (dropped, unloaded): viewers are told to clear it.
  void scene_gone(const std::string& scene);

  [[nodiscard]] Ros2Counts counts() const;

 private:
  struct Pending {
    bool gone = false;
    bool roadmap = false;
    std::optional<std::vector<Vec3>> tour;
  };
  // The copy a scene's last markers were drawn from (the published copy is immutable: a new
  // commit is a new copy).
  struct Drawn {
    const Roadmap* roadmap = nullptr;
    std::uint64_t version = 0;
    std::size_t pois = 0;
    bool operator==(const Drawn&) const = default;
  };
  class Writers;
  void run();
  void publish(const std::string& scene, Pending& work);

  const Ros2MirrorOptions options_;
  const RoadmapSource source_;
  std::unique_ptr<Writers> writers_;    // the participant and its writers: the thread's alone
  std::map<std::string, Drawn> drawn_;  // the thread's alone
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, Pending> pending_;
  Ros2Counts counts_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace ispars::ros2
