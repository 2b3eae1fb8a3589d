#pragma once
// What the session's source files share (the session, its record and its build job).

#include <cstdint>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"

namespace ispars::service::session_detail {

/// `scene` with the recipe's roadmap parameters (InputError naming the bad one).
[[nodiscard]] planning::Scene scene_for(const planning::Scene& scene, const RoadmapRecipe& recipe);
/// A new roadmap generation: the wall clock in nanoseconds.
[[nodiscard]] std::uint64_t new_generation();

}  // namespace ispars::service::session_detail
