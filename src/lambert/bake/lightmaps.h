#pragma once
// Lightmaps baked from a solution: per texel of each atlas (mesh/lightmap_uvs.h), the irradiance
// at the texel's point on the input's own faces, gathered over the hierarchy's links as the final
// gather does at vertices (engine/final_gather.h), with the point, spot and directional lights'
// direct light traced per texel (sharp shadows). Radiosity's lightmaps carry no Monte Carlo noise
// of their own, so no denoiser follows.
//
// Texels are found by conservative rasterisation of each face in UV space; a texel's point is its
// centre's place on the face (clamped into the face where the texel only overlaps it), nudged off
// the surface as vertex sites are; texels no face reaches are dilated from their neighbours, and
// texels on both sides of a UV seam (one surface point at two places in the atlas) are given one
// value, so that no step shows along the seam.
#include <cstdint>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/image.h"
#include "lambert/mesh/lightmap_uvs.h"

namespace lambert {

class SolutionView;

struct LightmapBakeOptions {
  LightmapUvOptions uvs;
  bool showProgress = true;  // on a TTY
};

struct BakedLightmaps {
  LightmapUvs uvs;
  // Per atlas: the irradiance E in W/m² per texel (RGB), top row first, uvs.size × uvs.size.
  // Multiply by ρ/π for the outgoing radiance of a diffuse surface.
  std::vector<Image> irradiance;
  // Per atlas, per texel: 1 where a face covers it, 0 where it was dilated or is empty.
  std::vector<std::vector<std::uint8_t>> covered;
  std::size_t texelsBaked = 0;
  double seconds = 0;
};

// Bakes lightmaps of the solved view. Fails only where the UVs cannot be made (lightmapUvs).
Result<BakedLightmaps> bakeLightmaps(const SolutionView& solution, const LightmapBakeOptions& options = {});

}  // namespace lambert
