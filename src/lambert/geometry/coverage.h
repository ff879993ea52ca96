#pragma once
// Which parts of a mesh are covered by other geometry: the floor under the Cornell box's blocks,
// the ceiling above its light panel. Radiosity there is zero (no light reaches it), but a patch
// that is partly covered solves for its area-averaged radiosity B, so the part anyone can see is
// brighter, B / f with f its open fraction. Drawing and vertex averaging use that (the
// Figure 7: a dark vertex under a box darkens the visible floor around it).
#include <cstdint>
#include <span>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

// Sets every patch's openFraction: the share of `samplesPerPatch` low-discrepancy points on it
// whose first surface along the normal is not seen from behind (seeing a back face first means
// the point is inside a closed object or under a panel). The renderer and vertexRadiosity then
// show a patch's open part at B / f and weight it by its open area A·f.
void measureOpenFractions(Mesh& mesh, const RayCaster& caster, int samplesPerPatch = 16);
// The same for the patches whose `measure` entry is non-zero (one per patch); the others keep
// their openFraction. A patch's points depend on its index only, so a patch of the same corners
// at the same index measures the same whenever it is measured.
void measureOpenFractions(Mesh& mesh, const RayCaster& caster, std::span<const std::uint8_t> measure, int samplesPerPatch = 16);

// Whether the point x on a surface with normal n is covered: the first surface along n, from x
// lifted by epsilon, is seen from behind.
bool isCovered(const RayCaster& caster, const Vec3& x, const Vec3& n, double epsilon);
// Whether the first surface along n from x lifted by epsilon lies inside a closed object: x is
// inside one (the floor under a two-sided block standing on it). False where the caster knows of
// no closed object.
bool isInsideClosedObject(const RayCaster& caster, const Vec3& x, const Vec3& n, double epsilon);

}  // namespace lambert
