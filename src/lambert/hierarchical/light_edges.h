#pragma once
// The first refinement pass's splits at light edges (hierarchical/method.h, step 1).
// Splits leaves, breadth first, while the direct light of some light varies across one by more
// than the threshold allows (ρ · (E_max − E_min) · A over its centre, its corners drawn a
// hundredth of the way in and its edges' midpoints a tenth): a spot's cone edge or a shadow edge
// crosses it.
// Cost: per wave, each leaf's bound on every light, and the shadow rays of the lights whose
// unoccluded light could split it (few: most are far, or outside their cones). Its own file: an
// algorithm of its own, before the links' refinement (hierarchical/refiner.h).
#include <cstdint>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/method/hierarchical_options.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct LightEdgeSplits {
  std::uint64_t splits = 0;   // elements split
  std::uint64_t samples = 0;  // points × lights evaluated (not culled by their bounds)
  std::uint64_t rays = 0;     // shadow rays
};

// The lights with each sky asked at a sixteenth of its directions, kSkyGuideDirections at least:
// for the estimates that guide refinement (where a sky's light varies over a leaf, the first
// pass's radiosity), which need its shape, not the precision of the light it injects
// (light/injection.h asks it at every direction).
std::vector<Light> withGuideSkies(const std::vector<Light>& lights);
inline constexpr int kSkyGuideDirections = 256;

// Splits the hierarchy's leaves (leafMesh: its leaf mesh, for the leaves' albedo) at the lights'
// edges, down to the minimum element area the link options give; numbers the new leaves before
// returning. threshold: W, what ρ · (E_max − E_min) · A may reach (the link error's share of the
// scene's power).
LightEdgeSplits splitAtLightEdges(ElementHierarchy& hierarchy, const Scene& scene, const Mesh& leafMesh,
                                  const std::vector<Light>& lights, const RayCaster& caster, double rayEpsilon,
                                  const LinkOptions& options, double threshold);

}  // namespace lambert
