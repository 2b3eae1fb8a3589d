#pragma once
// A DDS reader of one topic under any type name that keeps each sample's serialized bytes: what a
// test hands to a decoder written elsewhere (an npm package, another vendor) to check what this
// project puts on the wire with nothing of its own IDL.

#include <memory>
#include <string>
#include <vector>

namespace ispars::test {

class RawSampleReader {
 public:
  /// Joins `domain` (localhost only, the default partition) with a reliable, transient-local
  /// reader on `topic` whose type is named `type_name`.
  RawSampleReader(int domain, const std::string& topic, const std::string& type_name);
  ~RawSampleReader();
  RawSampleReader(const RawSampleReader&) = delete;
  RawSampleReader& operator=(const RawSampleReader&) = delete;

  /// The samples that arrived since the last call, oldest first, each as its serialized bytes
  /// (the 4-byte encapsulation header first).
  std::vector<std::string> take();
  /// Whether a writer matched.
  [[nodiscard]] bool matched() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::test
