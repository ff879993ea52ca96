#pragma once
// How far one radiance field is from another (a radiosity solution from the reference path
// tracer), over vertices or pixels. Errors pool the three channels; "relative" divides by the
// reference's mean, or per value where the reference is bright enough to divide by.
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/io/vertices.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct RadianceError {
  std::size_t count = 0;           // values compared (× 3 channels)
  double meanReference = 0;        // W/(m²·sr)
  double meanValue = 0;            // W/(m²·sr); meanValue / meanReference − 1 is the overall bias
  double rmse = 0;                 // W/(m²·sr)
  double relativeRmse = 0;         // rmse / meanReference
  double maxAbsolute = 0;          // W/(m²·sr)
  double maxRelative = 0;          // max |v − r| / r over values with r ≥ 1% of the largest r
};

// include: optional per-element mask (empty: every element).
RadianceError radianceError(std::span<const Rgb> value, std::span<const Rgb> reference, std::span<const char> include = {});

// A mask that leaves out points within `distance` (scene units) of any emissive surface: its rim
// is where a finite-element solution and the truth differ most and least meaningfully.
std::vector<char> awayFromEmitters(const Scene& scene, std::span<const Vec3> points, double distance);

struct VertexComparison {
  RadianceError error;        // away from emitters' rims, and not inside geometry
  RadianceError everywhere;   // every vertex
  std::size_t nearEmitters = 0;
  std::size_t covered = 0;    // vertices inside solid geometry (the floor under a block): the truth is black there
};

// Compares per-vertex radiance with a reference at the same vertices (same mesh, same order: an
// error otherwise). rimDistance in scene units; negative means 5% of the scene's diagonal.
Result<VertexComparison> compareVertices(const Scene& scene, std::span<const VertexSample> value,
                                         std::span<const VertexSample> reference, double rimDistance = -1);

}  // namespace lambert
