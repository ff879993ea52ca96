#include "lambert/render/hybrid.h"

#include "lambert/light/lights.h"

namespace lambert {

RenderOptions withDirectLight(RenderOptions options, const Scene& scene, const Mesh& mesh, const RayCaster& caster,
                              const std::vector<Rgb>& albedo, const std::vector<Light>& lights) {
  if (lights.empty()) return options;
  const double epsilon = rayEpsilon(mesh);
  options.directRadiance = [&scene, &mesh, &caster, &albedo, &lights, epsilon](const Vec3& position, std::uint32_t patch) {
    return reflectedDirectRadiance(lights, position, mesh.patches[patch].normal, albedo[patch], caster, epsilon,
                                   scene.metresPerUnit);
  };
  return options;
}

Image renderHybrid(const Scene& scene, const Mesh& mesh, const RayCaster& caster, const std::vector<Rgb>& indirectRadiosity,
                   const std::vector<Rgb>& albedo, const std::vector<Light>& lights, const RenderOptions& options) {
  return renderRadiance(scene.camera, mesh, indirectRadiosity, withDirectLight(options, scene, mesh, caster, albedo, lights));
}

}  // namespace lambert
