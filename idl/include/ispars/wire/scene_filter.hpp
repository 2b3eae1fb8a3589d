#pragma once
// A content filter on roadmap updates by scene: a replica of one scene subscribes through a
// filtered topic and receives no other scene's batches: its reader evaluates the filter before
// any sample reaches the application. The daemon registers the same filter class, but its updates
// writer does not filter for its readers (updates_writer_qos says why), so every batch crosses the
// network to each client that follows a scene.
//
// The filter reads only a batch's scene, the first member of UpdateBatch (its key), from the
// serialized sample (XCDR1, either byte order). A sample too short to hold one passes, and the
// reader's own check of the scene (replica.cpp) stands behind it.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ispars::wire {

/// The filter's class name and its one expression; the parameter is the scene, as 'NAME'.
inline constexpr const char* kSceneFilterClass = "ISPARS_SCENE";
inline constexpr const char* kSceneFilterExpression = "scene = %0";

/// Registers the scene filter on `participant` (a no-op when it is there). False when DDS
/// refused.
bool register_scene_filter(eprosima::fastdds::dds::DomainParticipant* participant);

/// Makes a filtered topic named `name` over `updates` that passes `scene`'s batches only
/// (registering the filter first). Null when DDS refused.
eprosima::fastdds::dds::ContentFilteredTopic* scene_filtered_topic(
    eprosima::fastdds::dds::DomainParticipant* participant, eprosima::fastdds::dds::Topic* updates,
    const std::string& name, const std::string& scene);

/// The scene a serialized UpdateBatch names (its first member); nullopt-like empty view with
/// `ok` false when the bytes cannot hold one.
struct SceneInPayload {
  bool ok = false;
  std::string_view scene;
};
[[nodiscard]] SceneInPayload scene_of_serialized(const std::uint8_t* data, std::size_t length);

}  // namespace ispars::wire
