#pragma once
// Creating DDS participants the same way in the daemon, the clients, the tests and benchmarks.

#include <fastdds/dds/domain/DomainParticipant.hpp>

#include <memory>
#include <string>

namespace ispars::wire {

/// How to join a DDS domain.
struct ParticipantOptions {
  int domain = 0;
  /// A Fast DDS XML profiles file. Empty: the built-in localhost-only settings (shared memory
  /// plus UDP bound to 127.0.0.1; nothing leaves the machine).
  std::string profile_file;
  /// The participant profile in profile_file to use.
  std::string profile_name = "ispars";
  std::string name = "ispars";
};

/// Owns a participant and deletes it (with its entities) on destruction.
class Participant {
 public:
  /// Throws std::runtime_error naming the domain and the profile when creation fails.
  explicit Participant(const ParticipantOptions& options,
                       eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  [[nodiscard]] eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::DomainParticipant* operator->() const { return participant_; }

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
};

/// The domain to use: the value given, else $ISPARS_DOMAIN, else 0.
[[nodiscard]] int domain_from_environment();

/// Routes Fast DDS's own log messages (warnings and errors) to spdlog, once per process.
void route_fastdds_log_to_spdlog();

}  // namespace ispars::wire
