#include "ispars/service/session_recovery.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "ispars/planning/builders/poi_visibility.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/service/drop_mark.hpp"

namespace ispars::service {

namespace {

std::shared_ptr<const planning::Scene> complete_tasks(const planning::Scene& scene, StoreRecovery& recovery,
                                                      unsigned threads) {
  if (recovery.tasks.empty()) return std::make_shared<const planning::Scene>(scene);
  auto with_tasks = std::make_shared<const planning::Scene>(scene.with_more_pois(task_pois(recovery.tasks)));
  const auto first = static_cast<PoiId>(scene.pois().size());
  planning::see_new_pois(recovery.roadmaps.roadmap, *with_tasks, first, threads);
  if (recovery.roadmaps.dense) planning::see_new_pois(*recovery.roadmaps.dense, *with_tasks, first, threads);
  return with_tasks;
}

std::string torn_tail_note(const StoreRecovery& recovery) {
  if (!recovery.torn_tail) return {};
  return fmt::format("cut a torn journal tail ({}) after commit {}; the cut bytes are kept in {}",
                     recovery.tail_problem, recovery.journal_commits,
                     recovery.tail_set_aside.empty() ? std::string("(nothing)") : recovery.tail_set_aside.string());
}

}  // namespace

RecoveredSession recover_session(const std::string& name, const planning::Scene& scene, const std::string& fingerprint,
                                 const std::filesystem::path& store_dir, const SessionLimits& limits, FileSystem& fs) {
  RecoveredSession r;
  if (!fs.exists(store_dir)) {
    r.dropped_generation = dropped_generation(store_dir, fs);
    return r;
  }
  StoreRecovery recovery;
  try {
    r.store = RoadmapStore::open(store_dir, scene.pois().size(), recovery, fs);
  } catch (const StoreDamage& e) {
    r.refused = e.what();
    return r;
  }
  r.store->set_compact_every(limits.compact_every);
  if (recovery.recipe.scene != name) {
    throw std::runtime_error(
        fmt::format("store {} belongs to scene '{}', not '{}'", store_dir.string(), recovery.recipe.scene, name));
  }
  if (std::string why = stale_store_reason(name, recovery.recipe, fingerprint); !why.empty()) {
    r.store.reset();
    r.refused = std::move(why);
    return r;
  }
  r.stored = serve_recovery(scene, recovery, limits.build_threads, r.resume_from);
  const StoredRoadmap& stored = *r.stored;
  r.note = fmt::format("recovered {} roadmap at version {} ({} samples, {} vertices, {} tasks; {} journal commits)",
                       to_string(stored.recipe.method), stored.published.roadmap->version(), stored.published.samples,
                       stored.published.roadmap->vertex_count(), stored.tasks.size(), recovery.journal_commits);
  r.torn_tail_note = torn_tail_note(recovery);
  if (!r.torn_tail_note.empty()) r.note += "; " + r.torn_tail_note;
  return r;
}

StoredRoadmap serve_recovery(const planning::Scene& scene, StoreRecovery& recovery, unsigned threads,
                             std::optional<planning::BuiltRoadmaps>& resume_from) {
  StoredRoadmap s;
  s.scene_with_tasks = complete_tasks(scene, recovery, threads);
  s.tasks = std::move(recovery.tasks);
  s.recipe = recovery.recipe;
  if (recovery.roadmaps.dense)
    s.dense = {recovery.roadmaps.dense->vertex_count(), recovery.roadmaps.dense->edge_count()};
  // A method that resumes from its roadmap needs no other copy: the published one is moved in,
  // and a builder is resumed from a copy of it when a job needs one.
  const bool resumable = planning::resumes_from_roadmap(s.recipe.method);
  s.published = make_published(resumable ? std::make_shared<const Roadmap>(std::move(recovery.roadmaps.roadmap))
                                         : std::make_shared<const Roadmap>(recovery.roadmaps.roadmap),
                               s.recipe.generation, recovery.roadmaps.samples);
  resume_from.reset();
  if (!resumable) resume_from = std::move(recovery.roadmaps);
  return s;
}

}  // namespace ispars::service
