#pragma once
// Seed 000's hybrid image: the lights' direct light computed per pixel, with a shadow ray per
// light (crisp spot edges, hard shadows), over indirect light interpolated from the radiosity
// solution. Point, spot and directional lights are drawn this way; emissive surfaces stay in the
// radiosity, since their light is already part of B.
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/render/rasterizer.h"
#include "lambert/scene/scene.h"

namespace lambert {

// indirectRadiosity: per patch, B less the lights' injected ρ·E_direct (W/m²).
// albedo: ρ per patch. lights: as they are in this frame.
Image renderHybrid(const Scene& scene, const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& indirectRadiosity,
                   const std::vector<Rgb>& albedo, const std::vector<Light>& lights, RenderOptions options);

}  // namespace lambert
