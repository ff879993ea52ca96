#pragma once
// What each patch emits and reflects before any light moves: emitted radiosity E = π·L_e of
// emissive surfaces, and the albedo ρ of each patch's material. A material's textures multiply
// both per patch, by their mean over the patch (through the surface's texture coordinates).
#include <array>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

// E_i in W/m² for every patch: π × the surface's emittedRadiance × its material's emission
// texture's mean over the patch (the texture's mean over the whole image where the surface has no
// texture coordinates).
std::vector<Rgb> emittedRadiosity(const Scene& scene, const Mesh& mesh);
// A surface's emitted radiance L_e averaged over its area, W/(m²·sr): emittedRadiance × the
// emission texture's area-weighted mean over its faces. Its power is π × this × its area.
Rgb meanEmittedRadiance(const Scene& scene, const Surface& surface);
// ρ_i for every patch: the material's albedo, times its texture's mean over the patch.
std::vector<Rgb> patchAlbedo(const Scene& scene, const Mesh& mesh);
// The texture coordinates of a patch's corners, interpolated from its face's (zero when its
// surface has none).
std::array<Uv, 4> patchCornerUvs(const Scene& scene, const Mesh& mesh, std::size_t patch);

}  // namespace lambert
