#include "lambert/render/solution_image.h"

#include <algorithm>

#include "lambert/light/lights.h"

namespace lambert {
namespace {

// Render options that add the lights' direct light reflected by each patch of `mesh` (albedo ρ
// per patch) at every visible sample. The references must outlive the render.
RenderOptions withDirectLight(RenderOptions options, const SolutionView& solution, const Mesh& mesh,
                              const std::vector<Rgb>& albedo) {
  const double epsilon = rayEpsilon(mesh);
  const double metresPerUnit = solution.scene().metresPerUnit;
  std::vector<Light> lights;
  for (const Light& light : solution.lights())
    if (light.kind != LightKind::Sky) lights.push_back(light);
  const RayCaster& caster = solution.caster();
  options.directRadiance = [&mesh, &caster, &albedo, lights = std::move(lights), epsilon, metresPerUnit](const Vec3& position, std::uint32_t patch) {
    return reflectedDirectRadiance(lights, position, mesh.patches[patch].normal, albedo[patch], caster, epsilon, metresPerUnit);
  };
  return options;
}

}  // namespace

bool drawsLightsPerPixel(const SolutionView& solution, const SolutionImageOptions& options) {
  // A sky's direct light costs Light::skyDirections rays per estimate (4096 by default): per pixel
  // that is hours, so a sky stays in the solution (VertexQuantity::IndirectRadiosity keeps it)
  // while the sun, points, spots and luminaires are drawn per pixel over it, with their edges.
  const auto& lights = solution.lights();
  const bool pixelLight = std::any_of(lights.begin(), lights.end(), [](const Light& l) { return l.kind != LightKind::Sky; });
  return options.lighting == Lighting::Hybrid && pixelLight;
}

Image renderSolution(const SolutionView& solution, const SolutionImageOptions& options) {
  const bool hybrid = drawsLightsPerPixel(solution, options);
  const Camera& camera = options.camera ? *options.camera : solution.scene().camera;
  RenderOptions render;
  render.width = options.width;
  render.height = options.height;
  render.shading = options.shading;
  render.supersample = options.supersample;
  if (options.shading == Shading::Flat) {
    if (hybrid) render = withDirectLight(render, solution, solution.mesh(), solution.albedo());
    return renderRadiance(camera, solution.mesh(), hybrid ? solution.indirectRadiosity() : solution.radiosity(), render);
  }
  const Mesh& mesh = solution.vertexMesh();
  // The values of the vertices the picture shows, alone: a camera in one room of a building sees
  // a few per cent of its vertices (RenderPark's hospital: 2.5%), and the hierarchical method
  // gathers each vertex asked for (hierarchical/final_gather.h).
  const std::vector<std::uint8_t> seen = visiblePatches(camera, mesh, render);
  std::vector<std::uint8_t> needed(mesh.numVertices(), 0);
  for (std::size_t i = 0; i < seen.size(); ++i)
    if (seen[i])
      for (std::uint32_t v : mesh.cornerIndices(i)) needed[v] = 1;
  if (hybrid) render = withDirectLight(render, solution, mesh, solution.vertexMeshAlbedo());
  return renderVertexRadiosity(camera, mesh,
                               solution.vertexValues(hybrid ? VertexQuantity::IndirectRadiosity : VertexQuantity::Radiosity, needed),
                               render);
}

}  // namespace lambert
