#include "ispars/ros2/ros2_mirror.hpp"

#include <spdlog/spdlog.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <set>
#include <utility>

#include "ispars/ros2/ros2_markers.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "ros2PubSubTypes.h"

namespace ispars::ros2 {
namespace fdds = eprosima::fastdds::dds;

namespace {

// A latched ROS 2 topic's QoS (what `ros2 topic pub --qos-durability transient_local` and the
// robot_state_publisher use): reliable, transient local, the last sample; written asynchronously
// so a viewer slow to take a large marker array never holds up the thread.
fdds::DataWriterQos latched_qos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 1;
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  return qos;
}

wire::ParticipantOptions named(wire::ParticipantOptions options) {
  options.name = "ispars ros2 mirror";
  return options;
}

}  // namespace

// The participant, its publisher and one pair of writers per ROS name, made on first use.
class Ros2Mirror::Writers {
 public:
  explicit Writers(const wire::ParticipantOptions& options)
      : participant_(named(options)),
        markers_type_(new visualization_msgs::msg::dds_::MarkerArray_PubSubType()),
        path_type_(new nav_msgs::msg::dds_::Path_PubSubType()) {
    // The default partition (ROS 2 puts none on its endpoints) and no filtering.
    publisher_ = wire::created(participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT), "ROS 2 publisher");
  }
  ~Writers() { participant_->delete_contained_entities(); }

  struct Pair {
    fdds::DataWriter* roadmap = nullptr;
    fdds::DataWriter* tour = nullptr;
  };
  // The writers of `scene`, or nullptr when its ROS name belongs to another scene.
  Pair* of(const std::string& scene) {
    const std::string token = ros_token(scene);
    const auto [owner, fresh] = owners_.try_emplace(token, scene);
    if (owner->second != scene) {
      if (warned_.insert(scene).second) {
        spdlog::warn("ros2: scene '{}' is not mirrored: its ROS name /ispars/{} is scene '{}''s", scene, token,
                     owner->second);
      }
      return nullptr;
    }
    auto [it, made] = pairs_.try_emplace(token);
    if (made) {
      it->second.roadmap = writer(markers_type_, roadmap_topic(token));
      it->second.tour = writer(path_type_, tour_topic(token));
      spdlog::info("ros2: scene '{}' on /ispars/{}/roadmap and /ispars/{}/tour", scene, token, token);
    }
    return &it->second;
  }
  [[nodiscard]] std::uint64_t refused() const { return warned_.size(); }
  // The scene is gone: its ROS name is free for another scene (its writers stay, for reuse).
  void release(const std::string& scene) {
    const auto it = owners_.find(ros_token(scene));
    if (it != owners_.end() && it->second == scene) owners_.erase(it);
    warned_.erase(scene);
  }

 private:
  fdds::DataWriter* writer(fdds::TypeSupport& type, const std::string& topic) {
    fdds::Topic* t = wire::find_or_create_topic(participant_.get(), type, topic.c_str());
    return wire::created(publisher_->create_datawriter(t, latched_qos()), "ROS 2 writer on " + topic);
  }

  wire::Participant participant_;
  fdds::TypeSupport markers_type_;
  fdds::TypeSupport path_type_;
  fdds::Publisher* publisher_ = nullptr;
  std::map<std::string, std::string> owners_;  // ROS name -> the scene mirrored under it
  std::map<std::string, Pair> pairs_;          // ROS name -> its writers
  std::set<std::string> warned_;               // scenes refused (each logged once)
};

Ros2Mirror::Ros2Mirror(Ros2MirrorOptions options, RoadmapSource source)
    : options_(std::move(options)),
      source_(std::move(source)),
      writers_(std::make_unique<Writers>(options_.participant)),
      thread_([this] { run(); }) {}

Ros2Mirror::~Ros2Mirror() {
  stop();
  writers_.reset();
}

void Ros2Mirror::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    pending_.clear();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Ros2Mirror::roadmap_changed(const std::string& scene) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    pending_[scene].roadmap = true;
  }
  wake_.notify_all();
}

void Ros2Mirror::tour_flown(const std::string& scene, std::vector<Vec3> stops) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    pending_[scene].tour = std::move(stops);
  }
  wake_.notify_all();
}

void Ros2Mirror::scene_gone(const std::string& scene) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    Pending& p = pending_[scene];
    p = Pending{};  // what was marked before is of the roadmap now gone
    p.gone = true;
  }
  wake_.notify_all();
}

Ros2Counts Ros2Mirror::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

void Ros2Mirror::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait(lock, [&] { return stopping_ || !pending_.empty(); });
    if (stopping_) break;
    std::map<std::string, Pending> work = std::exchange(pending_, {});
    lock.unlock();
    for (auto& [scene, p] : work) {
      try {
        publish(scene, p);
      } catch (const std::exception& e) {  // a writer DDS refused: this scene only, logged
        spdlog::error("ros2: scene '{}': {}", scene, e.what());
      }
    }
    lock.lock();
    // At most one round a period: a build's commits in between are drawn once, from the latest.
    wake_.wait_for(lock, options_.period, [&] { return stopping_; });
  }
}

void Ros2Mirror::publish(const std::string& scene, Pending& work) {
  Writers::Pair* pair = writers_->of(scene);
  if (pair == nullptr) {
    if (work.gone) writers_->release(scene);
    std::lock_guard lock(mutex_);
    counts_.refused = writers_->refused();
    return;
  }
  const auto now = std::chrono::system_clock::now();
  Ros2Counts wrote;
  if (work.gone) {
    MarkerArray cleared = cleared_markers(options_.frame, now);
    Path empty = tour_path({}, options_.frame, now);
    pair->roadmap->write(&cleared);
    pair->tour->write(&empty);
    ++wrote.clears;
    if (!work.roadmap && !work.tour) writers_->release(scene);
  }
  if (work.gone) drawn_.erase(scene);
  if (work.roadmap) {
    if (const std::optional<MirroredRoadmap> drawn = source_(scene); drawn && drawn->roadmap) {
      const Drawn key{drawn->roadmap.get(), drawn->roadmap->version(), drawn->pois.size()};
      const auto last = drawn_.find(scene);
      if (last == drawn_.end() || !(last->second == key)) {  // a status with no change draws nothing
        MarkerArray markers = roadmap_markers(*drawn->roadmap, drawn->pois, options_.frame, now);
        pair->roadmap->write(&markers);
        drawn_[scene] = key;
        ++wrote.roadmaps;
      }
    }
  }
  if (work.tour) {
    Path path = tour_path(*work.tour, options_.frame, now);
    pair->tour->write(&path);
    ++wrote.tours;
  }
  std::lock_guard lock(mutex_);
  counts_.roadmaps += wrote.roadmaps;
  counts_.tours += wrote.tours;
  counts_.clears += wrote.clears;
}

}  // namespace ispars::ros2
