#pragma once
// A DDS writer of arbitrary bytes on one of the service's topics under its type's name: what a
// broken or hostile peer can put on the wire, which no typed writer can (fuzz and security tests).

#include <memory>
#include <string>

namespace ispars::test {

class RawBytesWriter {
 public:
  /// Joins `domain` (localhost only; as the DDS Security identity `security` unless empty) with a
  /// writer on `topic` whose type is named `type_name`. Throws when DDS refuses the writer (a
  /// permission denied, under security).
  explicit RawBytesWriter(int domain, const std::string& security = "", const std::string& topic = "ispars/query",
                          const std::string& type_name = "ispars::msg::QueryRequest");
  ~RawBytesWriter();
  RawBytesWriter(const RawBytesWriter&) = delete;
  RawBytesWriter& operator=(const RawBytesWriter&) = delete;

  /// Waits (up to `seconds`) for a reader to match; false when none did.
  bool wait_matched(int seconds = 30);
  /// Writes `bytes` as one sample's whole serialized payload (encapsulation header included).
  bool write(const std::string& bytes);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::test
