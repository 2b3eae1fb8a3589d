#pragma once
// What the client library hands its callers: scenes, statuses, daemons and the answers to each
// request, as plain values. The wire's messages (ispars.idl) stay inside the library; the
// conversion is in ispars/client/wire_calls.hpp.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::client {

/// Where a scene stands on the daemon that owns it.
enum class SceneState {
  empty,      ///< loaded, no roadmap
  idle,       ///< a roadmap, no job
  queued,     ///< a job waits for a worker
  replaying,  ///< rebuilding the builder from its recipe after a restart
  building,   ///< a build or extend runs
  failed,     ///< the last job failed (SceneStatus::last_error says why)
  unloaded,   ///< no longer held by its daemon
};

/// The state's name as the CLI and the daemon's log print it ("idle", "building", ...).
[[nodiscard]] std::string_view to_string(SceneState state);
/// Whether a job is queued or running (queued, replaying, building).
[[nodiscard]] bool busy(SceneState state);

/// A scene's status as its owner published it: the job, the roadmap's size and coverage, and the
/// recipe that makes the roadmap again.
struct SceneStatus {
  std::string scene;
  std::string server_id;         ///< the owner
  std::uint64_t status_seq = 0;  ///< increases with every status the owner issues
  SceneState state = SceneState::empty;
  std::string method;
  std::string variant;  ///< spars, ispars: the rule set ("stretch" or "alg1")
  std::uint64_t seed = 0;
  std::uint64_t generation = 0;  ///< changes when the roadmap is rebuilt or dropped
  std::uint64_t samples_done = 0;
  std::uint64_t samples_target = 0;
  std::uint64_t version = 0;
  std::uint32_t vertices = 0;
  std::uint32_t edges = 0;
  std::uint32_t components = 0;
  std::uint32_t dense_vertices = 0;
  std::uint32_t dense_edges = 0;
  std::uint32_t poi_count = 0;
  std::uint32_t pois_covered = 0;
  std::uint32_t pois_covered_root = 0;
  double dense_delta = 0;
  double sparse_delta = 0;
  double stretch = 0;
  double stretch_slack = 0;               ///< a fraction of Delta (0: none)
  std::uint64_t stretch_slack_after = 0;  ///< the sample from which the slack applies (0: the first)
  double p_accept = 0;
  std::string last_error;
  std::string scene_fingerprint;  ///< of the scene file the roadmap was built on (empty: no roadmap)
  std::uint32_t builder_version = 0;
  std::uint32_t tasks = 0;  ///< inspection tasks added to the roadmap (poi_count includes theirs)
  /// A build accepted and not started (queued): the generation it makes (the recipe fields
  /// above are its recipe, samples_target its samples); 0 when none waits.
  std::uint64_t accepted_generation = 0;
};

/// An inspection task of a scene's roadmap: its POIs' ids and how many of them the roadmap sees.
struct TaskEntry {
  std::string name;
  std::uint32_t first_poi = 0;  ///< its POIs are ids first_poi .. first_poi + poi_count - 1
  std::uint32_t poi_count = 0;
  std::uint32_t pois_covered = 0;       ///< seen by some vertex
  std::uint32_t pois_covered_root = 0;  ///< seen by some vertex in the root's component
};

/// One scene of one daemon, as listed by `ispars scenes`.
struct SceneEntry {
  std::string scene;
  bool loaded = false;
  bool has_roadmap = false;
  std::string server_id;
  std::string note;  ///< what the fleet decided about this daemon's copy, if anything
};

/// A roadmap a daemon can serve (stored, or held and committed), as the fleet's rule weighs it.
struct StoredRoadmap {
  std::string scene;
  std::uint64_t generation = 0;
  std::uint64_t samples = 0;  ///< committed to the daemon's store
  std::uint64_t target = 0;   ///< accepted (a running or handed-over job), >= samples
  std::uint32_t builder_version = 0;
  std::string fingerprint;  ///< of the scene file it was built on
  std::string yielded_to;   ///< handed to that daemon: not a candidate while it lives
};

/// A daemon on the domain, as it announces itself.
struct DaemonInfo {
  std::string server_id;
  std::uint16_t protocol = 0;  ///< its protocol version
  std::string host;
  std::int32_t pid = 0;
  std::string version;                 ///< its release ("0.1.0")
  std::vector<std::string> available;  ///< scene names in its scene directory
  std::vector<std::string> loaded;     ///< scenes it owns (claimed, loading or loaded)
  std::vector<std::string> stored;     ///< scenes with a roadmap in its data directory
  std::uint64_t joined_ms = 0;         ///< when it joined the domain (ms since the Unix epoch)
  std::uint32_t builder_version = 0;
  std::vector<StoredRoadmap> roadmaps;
};

/// A daemon's answer to a request it served: who answered, its note, and the scene's status
/// after the request. A refused request throws ClientError instead.
struct Reply {
  std::string server_id;
  std::string message;
  SceneStatus status;
};

/// A collision-free path on the roadmap between two points.
struct Path {
  std::vector<Vec3> waypoints;
  double length = 0;
};

/// What `verify` found: each count is of problems the method promises to avoid (0: verified).
struct Verification {
  std::uint64_t violations = 0;  ///< the total
  std::uint64_t invalid_vertices = 0;
  std::uint64_t invalid_edges = 0;
  std::uint64_t wrong_costs = 0;
  std::uint64_t sparse_not_dense = 0;
  std::uint64_t invariant_violations = 0;
  std::uint64_t invariant_vertices = 0;  ///< dense vertices (ispars2: fresh samples) with an Invariant 1 violation
  bool invariant_promised = false;       ///< Inspection-SPARS promises Invariant 1; the others do not
};

/// One stage of the tour pipeline: "walk", "shortcut", "corridor" or "refine"; the flown length
/// after it and the seconds since the tour began at its end.
struct TourStage {
  std::string name;
  double cost = 0;
  double seconds = 0;
};

/// An inspection tour found on a roadmap, with its proven lower bound.
struct Tour {
  std::vector<std::uint32_t> walk;  ///< roadmap vertex ids of the closed walk
  std::vector<Vec3> waypoints;      ///< their positions
  double cost = 0;                  ///< the walk's length
  std::uint32_t covered = 0;        ///< targets seen
  std::uint32_t target_count = 0;
  double lower_bound = 0;                     ///< proven: no roadmap tour seeing the targets is shorter (0: none)
  bool valid = false;                         ///< the walk and the shortcut path passed independent validations
  std::vector<double> trace;                  ///< seconds, cost, ... at each improvement
  std::vector<double> bound_trace;            ///< seconds, bound, ... at each rise of the proven bound
  bool bound_complete = false;                ///< the LP bound was solved over all its cuts
  std::uint64_t version = 0;                  ///< the roadmap version searched
  std::vector<std::uint32_t> shortcut_stops;  ///< the walk's vertices the shortcut tour keeps, in order
  std::vector<Vec3> shortcut_path;            ///< their positions: the tour as flown
  double shortcut_cost = 0;                   ///< its length (<= cost; every target still seen from a stop)
  /// The flown tour: the shortcut improved by corridor densification and viewpoint refinement (its
  /// stops need not be roadmap vertices), closed at the root, straight checked segments between.
  std::vector<Vec3> flown_path;
  std::vector<std::vector<std::uint32_t>> flown_sees;  ///< per stop: the target POI ids it sees
  double flown_cost = 0;                               ///< its length (<= shortcut_cost)
  std::vector<TourStage> stages;                       ///< the pipeline's stages, in order
  std::uint64_t graph_vertices = 0;                    ///< the graph the flown tour was last searched on
  std::uint64_t graph_edges = 0;
};

/// The answers that carry more than a status.
struct PathReply : Reply {
  Path path;
};
struct VerifyReply : Reply {
  Verification verify;
};
struct TourReply : Reply {
  Tour tour;
};

}  // namespace ispars::client
