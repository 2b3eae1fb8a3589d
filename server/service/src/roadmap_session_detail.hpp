#pragma once
// What the session's source files share (the session, its record and its build job).

#include <cstdint>

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/scene/scene.hpp"

namespace ispars::session_detail {

/// `scene` with the recipe's roadmap parameters (InputError naming the bad one).
[[nodiscard]] Scene scene_for(const Scene& scene, const RoadmapRecipe& recipe);
/// A new roadmap generation: the wall clock in nanoseconds.
[[nodiscard]] std::uint64_t new_generation();

}  // namespace ispars::session_detail
