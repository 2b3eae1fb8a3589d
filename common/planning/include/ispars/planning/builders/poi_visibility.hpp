#pragma once
// chi for POIs added to a built roadmap (an inspection task): which of the new POIs each vertex
// sees, found as a build in the widened scene finds them.

#include <functional>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/poi_set.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// Thrown by a task addition stopped by its `keep_going` (a cancel, the daemon's stop). With
/// `builder_changed` the builder's roadmaps are part way and must be discarded; without it the
/// addition stopped while it was still finding what the vertices see, and changed nothing.
struct AdditionStopped : std::runtime_error {
  AdditionStopped(const std::string& what, bool changed) : std::runtime_error(what), builder_changed(changed) {}
  bool builder_changed;
};

/// For each vertex of `roadmap`, the POIs of `widened` from `first` on that it sees, as ids
/// relative to `first`: the candidates within sensor range, each with its own ray. The same rows
/// a build in `widened` gives its vertices for those POIs (SparsTask tests). Runs on `threads`
/// threads (the rows do not depend on it), 256 vertices each between two asks of `keep_going`;
/// throws AdditionStopped (nothing changed) when it says no.
[[nodiscard]] PoiSetTable new_poi_visibility(const Scene& widened, const Roadmap& roadmap, PoiId first,
                                             const std::function<bool()>& keep_going = {}, unsigned threads = 1);

/// Widens `roadmap` to `widened`'s POIs (when narrower) and adds each vertex's POIs from `first`
/// on (new_poi_visibility, on `threads` threads). Adding what a vertex sees already changes
/// nothing, so it is safe on vertices that were built seeing them; version() does not move.
void see_new_pois(Roadmap& roadmap, const Scene& widened, PoiId first, unsigned threads = 1);

}  // namespace ispars::planning
