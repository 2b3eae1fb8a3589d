#include "ispars/wire/scene_filter.hpp"

#include <fastdds/dds/topic/IContentFilter.hpp>
#include <fastdds/dds/topic/IContentFilterFactory.hpp>

#include <cstring>
#include <memory>

#include "isparsPubSubTypes.h"

namespace ispars::wire {
namespace fdds = eprosima::fastdds::dds;

namespace {

// Fast DDS's filter interfaces have no virtual destructor; each is deleted here as its own class.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnon-virtual-dtor"

// Passes the batches of one scene.
class SceneFilter final : public fdds::IContentFilter {
 public:
  explicit SceneFilter(std::string scene) : scene_(std::move(scene)) {}
  bool evaluate(const SerializedPayload& payload, const FilterSampleInfo&, const GUID_t&) const override {
    const SceneInPayload found = scene_of_serialized(payload.data, payload.length);
    return !found.ok || found.scene == scene_;
  }
  void set(std::string scene) { scene_ = std::move(scene); }

 private:
  std::string scene_;
};

// 'NAME' -> NAME (DDS-SQL parameters are quoted strings); a bare NAME is taken as it is.
std::string unquoted(const char* parameter) {
  std::string value = parameter == nullptr ? "" : parameter;
  if (value.size() >= 2 && value.front() == '\'' && value.back() == '\'') value = value.substr(1, value.size() - 2);
  return value;
}

class SceneFilterFactory final : public fdds::IContentFilterFactory {
 public:
  ReturnCode_t create_content_filter(const char*, const char* type_name, const fdds::TopicDataType*,
                                     const char* expression, const ParameterSeq& parameters,
                                     fdds::IContentFilter*& filter) override {
    static const std::string update_type = msg::UpdateBatchPubSubType().getName();
    if (type_name == nullptr || update_type != type_name) return ReturnCode_t::RETCODE_BAD_PARAMETER;
    if (expression != nullptr && std::strcmp(expression, kSceneFilterExpression) != 0) {
      return ReturnCode_t::RETCODE_BAD_PARAMETER;
    }
    if (parameters.length() != 1) return ReturnCode_t::RETCODE_BAD_PARAMETER;
    const std::string scene = unquoted(parameters[0]);
    if (filter != nullptr) {  // new parameters for an existing filter
      static_cast<SceneFilter*>(filter)->set(scene);
    } else {
      filter = new SceneFilter(scene);
    }
    return ReturnCode_t::RETCODE_OK;
  }
  ReturnCode_t delete_content_filter(const char*, fdds::IContentFilter* filter) override {
    delete static_cast<SceneFilter*>(filter);
    return ReturnCode_t::RETCODE_OK;
  }
};

#pragma GCC diagnostic pop

SceneFilterFactory& factory() {
  static SceneFilterFactory instance;  // outlives every participant (never destroyed before them)
  return instance;
}

}  // namespace

SceneInPayload scene_of_serialized(const std::uint8_t* data, std::size_t length) {
  // The encapsulation header (2 bytes kind, 2 options), then the string: a 4-byte length that
  // counts the terminating NUL, the characters and the NUL.
  constexpr std::size_t kHeader = 4;
  if (data == nullptr || length < kHeader + 4) return {};
  const bool little = (data[1] & 0x01) != 0;
  const std::uint8_t* at = data + kHeader;
  const std::uint32_t size =
      little
          ? (std::uint32_t{at[0]} | std::uint32_t{at[1]} << 8 | std::uint32_t{at[2]} << 16 | std::uint32_t{at[3]} << 24)
          : (std::uint32_t{at[3]} | std::uint32_t{at[2]} << 8 | std::uint32_t{at[1]} << 16 |
             std::uint32_t{at[0]} << 24);
  if (size == 0 || size > length - kHeader - 4) return {};
  return {true, std::string_view(reinterpret_cast<const char*>(at + 4), size - 1)};
}

bool register_scene_filter(fdds::DomainParticipant* participant) {
  if (participant->lookup_content_filter_factory(kSceneFilterClass) != nullptr) return true;
  return participant->register_content_filter_factory(kSceneFilterClass, &factory()) == ReturnCode_t::RETCODE_OK;
}

fdds::ContentFilteredTopic* scene_filtered_topic(fdds::DomainParticipant* participant, fdds::Topic* updates,
                                                 const std::string& name, const std::string& scene) {
  if (!register_scene_filter(participant)) return nullptr;
  return participant->create_contentfilteredtopic(name, updates, kSceneFilterExpression, {"'" + scene + "'"},
                                                  kSceneFilterClass);
}

}  // namespace ispars::wire
