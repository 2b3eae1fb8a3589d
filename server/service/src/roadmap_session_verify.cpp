// A session's verify: a reader of the builder's roadmaps that any writer can stop (see
// ReaderGate), within its budget.

#include <fmt/format.h>

#include "ispars/builders/recipe_builder.hpp"
#include "ispars/builders/roadmap_verifier.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars {

VerificationReport RoadmapSession::verify(std::chrono::milliseconds budget) const {
  std::unique_ptr<ReaderGate::Pass> pass;
  try {
    pass = readers_->enter(std::chrono::steady_clock::now() + budget);
  } catch (const ReaderRefused& e) {
    throw InputError(kRequest, "scene", fmt::format("{}; verify later", e.what()));
  }
  const auto job = lock_idle_job<std::shared_lock<std::shared_mutex>>("verify");
  const VerifyKeepGoing keep_going = [&] { return pass->keep_going(); };
  try {
    return verify_locked(keep_going);
  } catch (const VerificationStopped&) {
    const std::string why = pass->keep_going() ? std::string() : pass->why_stopped();
    throw InputError(
        kRequest, "scene",
        fmt::format(
            "the verify of scene '{}' was stopped: {}", name_,
            why == "its time ran out" ? fmt::format("its budget of {:.1f} s ran out", budget.count() / 1000.0) : why));
  }
}

void RoadmapSession::stop_readers(const std::string& why) { readers_->stop_all(why); }

VerificationReport RoadmapSession::verify_locked(const VerifyKeepGoing& keep_going) const {
  std::optional<RoadmapRecipe> recipe;
  std::shared_ptr<const Scene> with_tasks;
  std::uint64_t samples = 0;  // the roadmap's: no job runs (the job lock is held)
  {
    std::lock_guard lock(mutex_);
    recipe = recipe_;
    with_tasks = scene_with_tasks_;
    samples = samples_done_;
  }
  if (!recipe) throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
  const Scene scene = session_detail::scene_for(*with_tasks, *recipe);
  const auto check = [&](const Roadmap& roadmap, const Roadmap* dense, std::span<const VertexId> dense_ids) {
    return verify_recipe_roadmaps(scene, *recipe, samples, roadmap, dense, dense_ids, keep_going);
  };
  if (builder_) return check(builder_->roadmap(), builder_->dense(), builder_->dense_ids());
  if (recovered_) {
    return check(recovered_->roadmap, recovered_->dense ? &*recovered_->dense : nullptr, recovered_->dense_ids);
  }
  // No builder and nothing recovered: a method that resumes from its roadmap, idle, whose
  // published roadmap is the stored one (no job runs: this holds the job lock).
  std::shared_ptr<const Roadmap> published;
  {
    std::lock_guard lock(mutex_);
    if (resumes_from_roadmap(recipe->method) && published_.generation == recipe->generation) {
      published = published_.roadmap;
    }
  }
  if (!published) throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
  return check(*published, nullptr, {});
}

}  // namespace ispars
