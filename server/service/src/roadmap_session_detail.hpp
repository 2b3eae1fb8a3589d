#pragma once
// What the session's two source files share (roadmap_session.cpp: requests and queries;
// roadmap_session_job.cpp: the build job).

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/scene/scene.hpp"

namespace ispars::session_detail {

/// `scene` with the recipe's roadmap parameters (InputError naming the bad one).
[[nodiscard]] Scene scene_for(const Scene& scene, const RoadmapRecipe& recipe);

}  // namespace ispars::session_detail
