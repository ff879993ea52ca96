#pragma once
// What each patch emits and reflects before any light moves: emitted radiosity E = π·L_e of
// emissive surfaces, and the albedo ρ of each patch's material.
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

// E_i in W/m² for every patch.
std::vector<Rgb> emittedRadiosity(const Scene& scene, const Mesh& mesh);
// ρ_i for every patch.
std::vector<Rgb> patchAlbedo(const Scene& scene, const Mesh& mesh);

}  // namespace lambert
