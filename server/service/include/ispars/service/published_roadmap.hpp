#pragma once
// A roadmap as readers are served it: immutable and shared, with its coverage figures.

#include <cstddef>
#include <cstdint>
#include <memory>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::service {

/// A published roadmap: immutable, shared by every reader that holds it, with its coverage
/// figures computed once when it is published (not on every status query).
struct PublishedRoadmap {
  std::shared_ptr<const Roadmap> roadmap;
  std::uint64_t generation = 0;
  std::uint64_t samples = 0;
  std::size_t pois_covered = 0;
  std::size_t pois_covered_root = 0;
};

/// Publishes `roadmap`: computes its coverage figures.
[[nodiscard]] PublishedRoadmap make_published(std::shared_ptr<const Roadmap> roadmap, std::uint64_t generation,
                                              std::uint64_t samples);

}  // namespace ispars::service
