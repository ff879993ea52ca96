#pragma once
// Adaptive sampling of a lightmap's texels: the light is gathered on a coarse lattice of each
// atlas, and a lattice cell's texels are interpolated bilinearly between its four corners where
// the corners, the cell's centre and its four edge midpoints lie on one plane of one surface and
// the light gathered at those five probes is what the corners interpolate there (within
// AdaptiveTexelOptions::tolerance); elsewhere the cell is halved (the probes are the halves'
// corners, so nothing gathered is wasted) down to single texels, which are gathered. It is
// irradiance caching's bet (Ward, Rubinstein & Clear 1988: the light from the surfaces varies
// slowly except near other surfaces, so gather sparsely and interpolate) laid on the texel grid,
// each cell checked by its own points as quadtree-adaptive image sampling refines a picture
// (Painter & Sloan 1989). A straight shadow edge through a cell always leaves corners or probes
// on both of its sides; the centre finds a dip in the middle, the midpoints a saddle. The
// lights' direct light (their sharp shadows) is not interpolated: the lightmap bake traces it at
// every texel (bake/lightmaps.h).
//
// What it can miss: light that changes only between the nine points of a cell (a contact shadow
// under a quarter of a cell across, away from all of them). The first cells are `coarsestStep`
// texels wide, about 10 cm at the default texel size (mesh/lightmap_uvs.h); a coarsestStep of 1
// gathers every texel.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "lambert/bake/lightmaps.h"
#include "lambert/core/error.h"
#include "lambert/core/rgb.h"

namespace lambert {

// The light (any Rgb quantity) at the texels asked for, by index into LightmapTexels::points.
using TexelGather = std::function<Result<std::vector<Rgb>>(std::span<const std::uint32_t> texels)>;

struct AdaptiveTexelStats {
  std::size_t texels = 0, gathered = 0, interpolated = 0;
  int passes = 0;  // calls of the gather
};

// Per texel of `texels` (lightmapTexels over atlases of `size`² texels): its value, gathered by
// `gather` (called with indices into texels, twice per cell size) or interpolated between
// gathered ones. The gather must give a texel the same value whichever batch it comes in.
Result<std::vector<Rgb>> adaptiveTexelValues(const LightmapTexels& texels, int size, int numAtlases, const TexelGather& gather,
                                             const AdaptiveTexelOptions& options = {}, AdaptiveTexelStats* stats = nullptr);

}  // namespace lambert
