#pragma once
// A DDS writer of arbitrary bytes on the service's query topic, under the request type's name:
// what a broken or hostile peer can put on the wire, which no typed writer can (fuzz tests).

#include <memory>
#include <string>

namespace ispars::test {

class RawBytesWriter {
 public:
  /// Joins `domain` (localhost only) with a writer on ispars/query.
  explicit RawBytesWriter(int domain);
  ~RawBytesWriter();
  RawBytesWriter(const RawBytesWriter&) = delete;
  RawBytesWriter& operator=(const RawBytesWriter&) = delete;

  /// Waits (up to 30 s) for a reader to match; false when none did.
  bool wait_matched();
  /// Writes `bytes` as one sample's whole serialized payload (encapsulation header included).
  bool write(const std::string& bytes);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::test
