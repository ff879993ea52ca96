#pragma once
// A solved scene as binary glTF 2.0 (.glb), for Blender, three.js and game engines: the solution's
// vertex mesh, positions in metres (as glTF requires), per-vertex normals, and the light baked
// into COLOR_0, under KHR_materials_unlit materials, so that a viewer shows the lit scene with no
// lighting of its own.
//   Irradiance bake (default): COLOR_0 = H/π × 2^exposure, with H = (B − E)/ρ the irradiance at
//     each patch, interpolated to vertices like B (0 where ρ = 0); the base colour is ρ, so a
//     viewer's base colour × COLOR_0 is the reflected radiance ρH/π, and the texture (later) can
//     stay sharp over smooth light.
//   Radiance bake: COLOR_0 = L × 2^exposure, the final radiance, over a white base colour.
//   Emitting patches always carry their radiance L (emission included) over white (a patch emits
//   where its own emission, through an emission texture, is not black).
// COLOR_0 is clipped to [0, 1], as glTF requires, with a warning that counts the clipped values.
// Every primitive also has _RADIANCE, the unscaled linear radiance L = B/π in W/(m²·sr), and
// the file holds the scene's camera; lights are not written (their light is in COLOR_0).
#include <string>

#include "lambert/core/error.h"
#include "lambert/method/solution.h"

namespace lambert {

enum class GltfBake { Irradiance, Radiance };

struct GltfExportOptions {
  GltfBake bake = GltfBake::Irradiance;
  double exposureStops = 0;  // COLOR_0 is scaled by 2^exposureStops
};

// Written atomically; errors name the path.
Status writeGlb(const std::string& path, const SolutionView& solution, const GltfExportOptions& options = {});

}  // namespace lambert
