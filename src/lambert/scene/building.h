#pragma once
// Procedural office buildings for scaling runs (time and memory against face count): storeys of rooms on both sides
// of a corridor, each room with a door, a window in its outer wall, a ceiling light panel and
// furniture blocks; the corridor has its own lights. Deterministic for a given seed. Walls have
// thickness (no two faces back to back), door and window openings are lined by reveals, and
// every face is one-sided, facing the space it bounds. Metres, y up.
#include <cstdint>
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct BuildingOptions {
  int rooms = 8;              // offices in all; 8 per side of a corridor, then another storey
  double faceSize = 0;        // split every rectangle into faces no longer than this (m); 0: whole
  std::uint64_t seed = 1;     // furniture placement
};

// The building as a scene: every rectangle a smooth region of grid faces; a camera inside the
// first room looking at its window.
Result<Scene> generateBuilding(const BuildingOptions& options);

}  // namespace lambert
