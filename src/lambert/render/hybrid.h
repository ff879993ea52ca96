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

// Render options that add the lights' direct light, reflected by each patch of `mesh` (albedo ρ
// per patch), at every visible sample. The references must outlive the render.
RenderOptions withDirectLight(RenderOptions options, const Scene& scene, const Mesh& mesh, const RayCaster& caster,
                              const std::vector<Rgb>& albedo, const std::vector<Light>& lights);

// indirectRadiosity: per patch, B less the lights' injected ρ·E_direct (W/m²).
Image renderHybrid(const Scene& scene, const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& indirectRadiosity,
                   const std::vector<Rgb>& albedo, const std::vector<Light>& lights, const RenderOptions& options);

}  // namespace lambert
