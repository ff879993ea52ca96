#pragma once
// Lightmaps baked from a solution: per texel of each atlas (mesh/lightmap_uvs.h), the irradiance
// at the texel's point on the input's own faces, gathered over the hierarchy's links as the final
// gather does at vertices (hierarchical/final_gather.h), with the point, spot and directional lights'
// direct light traced per texel (sharp shadows). The light from the surfaces is gathered where it
// varies and interpolated where it does not (bake/adaptive_texels.h). Radiosity's lightmaps carry
// no Monte Carlo noise of their own, so no denoiser follows.
//
// Texels are found by conservative rasterisation of each face in UV space; a texel's point is its
// centre's place on the face (clamped into the face where the texel only overlaps it), nudged off
// the surface as vertex sites are; texels no face reaches are dilated from their neighbours, and
// the texels under a UV seam's two sides (one surface line at two places in the atlas) are moved
// until bilinear reads on both sides agree, so that no step shows along the seam
// (bake/lightmap_fill.h).
#include <cstdint>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/image.h"
#include "lambert/method/solution.h"
#include "lambert/mesh/lightmap_uvs.h"

namespace lambert {

struct AdaptiveTexelOptions {
  // Texels between the points where the light from the surfaces is gathered first (a power of
  // two; 1 gathers every texel). See bake/adaptive_texels.h.
  int coarsestStep = 8;
  // A cell is interpolated where, in every channel, the light at its centre and its edges'
  // midpoints is within this share of what its corners interpolate there (a share of the larger
  // of the two, or of `floorShare` × the first lattice's mean light, whichever is larger: dark
  // cells are not halved for differences no one can see).
  double tolerance = 0.02;
  double floorShare = 0.05;
};

struct LightmapBakeOptions {
  LightmapUvOptions uvs;
  AdaptiveTexelOptions sampling;
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
  std::size_t texelsGathered = 0;  // those whose light from the surfaces was gathered, not interpolated
  int paddingRings = 0;  // rings of empty texels dilated around the charts (bake/lightmap_fill.h)
  double seconds = 0;
};

// Bakes lightmaps of the solved view over UVs made by lightmapUvs(scene, options.uvs). Fails
// where the UVs cannot be made or the method cannot gather at points (SolutionView::pointIrradiance).
Result<BakedLightmaps> bakeLightmaps(const SolutionView& solution, const LightmapBakeOptions& options = {});
// The same over given UVs (uv and atlas laid out as LightmapUvs says).
Result<BakedLightmaps> bakeLightmaps(const SolutionView& solution, const LightmapUvs& uvs, const LightmapBakeOptions& options = {});

// Where lightmap texels lie on the faces: per atlas texel, the face (surface, face) and the point
// the texel is baked at, found by conservative rasterisation in UV space (a texel any face
// overlaps takes the face nearest its centre, and the point of that face nearest its centre).
struct LightmapTexels {
  std::vector<SurfacePoint> points;  // one per rasterised texel
  std::vector<std::uint32_t> atlas;  // per point: its atlas
  std::vector<std::uint32_t> texel;  // per point: y × size + x in its atlas
};
LightmapTexels lightmapTexels(const Scene& scene, const LightmapUvs& uvs);

}  // namespace lambert
