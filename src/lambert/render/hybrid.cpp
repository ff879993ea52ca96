#include "lambert/render/hybrid.h"

#include "lambert/light/lights.h"

namespace lambert {

Image renderHybrid(const Scene& scene, const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& indirectRadiosity,
                   const std::vector<Rgb>& albedo, const std::vector<Light>& lights, RenderOptions options) {
  if (!lights.empty()) {
    const double epsilon = rayEpsilon(mesh);
    options.directRadiance = [&](const Vec3& position, std::uint32_t patch) {
      return reflectedDirectRadiance(lights, position, mesh.patches[patch].normal, albedo[patch], caster, epsilon,
                                     scene.metresPerUnit);
    };
  }
  return renderRadiance(scene.camera, mesh, indirectRadiosity, options);
}

}  // namespace lambert
