#include "ispars/server/status_message.hpp"

namespace ispars::server {

msg::SceneState to_message(service::SessionState state) {
  switch (state) {
    case service::SessionState::empty:
      return msg::SCENE_EMPTY;
    case service::SessionState::idle:
      return msg::SCENE_IDLE;
    case service::SessionState::queued:
      return msg::SCENE_QUEUED;
    case service::SessionState::replaying:
      return msg::SCENE_REPLAYING;
    case service::SessionState::building:
      return msg::SCENE_BUILDING;
    case service::SessionState::failed:
      return msg::SCENE_FAILED;
  }
  return msg::SCENE_FAILED;
}

msg::SceneStatus to_message(const service::SessionStatus& s, const std::string& server_id, std::uint64_t generation) {
  msg::SceneStatus m;
  m.scene(s.scene);
  m.server_id(server_id);
  m.state(to_message(s.state));
  m.generation(generation);
  // The recipe accepted: a queued build's while it waits (with accepted_generation), else the roadmap's.
  if (const auto& recipe = s.accepted ? s.accepted : s.recipe) {
    m.method(std::string(to_string(recipe->method)));
    if (has_variants(recipe->method)) {
      m.variant(std::string(to_string(recipe->variant)));
    }
    m.seed(recipe->seed);
    m.dense_delta(recipe->dense_delta);
    m.sparse_delta(recipe->sparse_delta);
    m.stretch(recipe->stretch);
    m.stretch_slack(recipe->stretch_slack);
    m.stretch_slack_after(recipe->stretch_slack_after);
    m.p_accept(recipe->p_accept);
    m.scene_fingerprint(recipe->scene_fingerprint.substr(0, 64));
    m.builder_version(recipe->builder_version);
  }
  if (s.accepted) m.accepted_generation(s.accepted->generation);
  m.samples_done(s.samples_done);
  m.samples_target(s.samples_target);
  m.version(s.version);
  m.vertices(static_cast<std::uint32_t>(s.vertices));
  m.edges(static_cast<std::uint32_t>(s.edges));
  m.components(static_cast<std::uint32_t>(s.components));
  m.dense_vertices(static_cast<std::uint32_t>(s.dense_vertices));
  m.dense_edges(static_cast<std::uint32_t>(s.dense_edges));
  m.poi_count(static_cast<std::uint32_t>(s.poi_count));
  m.tasks(static_cast<std::uint32_t>(s.tasks));
  m.task_events(s.task_events);
  m.pois_covered(static_cast<std::uint32_t>(s.pois_covered));
  m.pois_covered_root(static_cast<std::uint32_t>(s.pois_covered_root));
  m.last_error(s.last_error);
  return m;
}

std::optional<RoadmapRecipe> recipe_of(const msg::SceneStatus& m) {
  const auto method = parse_build_method(m.method().to_string());
  if (!method) return std::nullopt;
  RoadmapRecipe recipe;
  recipe.scene = m.scene().to_string();
  recipe.method = *method;
  if (const std::string v = m.variant().to_string(); !v.empty()) {
    const auto variant = parse_spars_variant(v);
    if (!variant) return std::nullopt;
    recipe.variant = *variant;
  }
  recipe.seed = m.seed();
  recipe.dense_delta = m.dense_delta();
  recipe.sparse_delta = m.sparse_delta();
  recipe.stretch = m.stretch();
  recipe.stretch_slack = m.stretch_slack();
  recipe.stretch_slack_after = m.stretch_slack_after();
  recipe.p_accept = m.p_accept();
  recipe.generation = m.accepted_generation() != 0 ? m.accepted_generation() : m.generation();
  return recipe;
}

}  // namespace ispars::server
