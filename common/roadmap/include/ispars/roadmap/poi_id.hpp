#pragma once
// The id of a point of interest: its index in the scene's POI list. Its own header, so roadmap
// types can name POIs without the visibility machinery (Embree) behind chi(q).

#include <cstdint>

namespace ispars {

/// Index of a point of interest in the scene's POI list.
using PoiId = std::uint32_t;

}  // namespace ispars
