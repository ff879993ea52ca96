#pragma once
// The read-only view of a radiosity solution that every consumer reads: the rasterizer and the
// hybrid renderer (render/solution_image.h), vertex export (io/vertices.h), comparison with the
// path tracer, animation, benchmarks and programs embedding lambert.
//
// Two meshes: mesh() holds the elements B is solved on (uniform patches, or the active cells of
// an adaptive quad-tree); vertexMesh() is the mesh whose vertices carry continuous values for
// Gouraud shading and export (the same mesh for uniform meshing; the quad-tree's finest level,
// with hanging vertices constrained, for adaptive meshing). Units: B, E and injected light in
// W/m² (radiant exitance), radiance L = B/π in W/(m²·sr), albedo ρ dimensionless.
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

class Radiosity;

// A point on one of the scene's own faces where a consumer asks for the light (a lightmap texel).
struct SurfacePoint {
  Vec3 point;   // on the face, scene units
  Vec3 normal;  // the face's front, unit
  std::uint32_t surface = 0, face = 0;  // scene.surfaces[surface], its surfaceFaces()[face]
};

// What the solution gives at each vertex of SolutionView::vertexMesh(), W/m².
enum class VertexQuantity {
  Radiosity,          // B
  IndirectRadiosity,  // B less the direct light ρ·E_direct of every light but a sky (hybrid images
                      // add it per pixel; a sky's, 4096 directions an estimate, stays in B)
  Irradiance,         // E = (B − emission)/ρ: the light a surface receives (where it is interpolated from
                      // the elements, 0 where ρ is 0)
};

class SolutionView {
 public:
  const Scene& scene() const;                // surfaces, materials, camera, metresPerUnit
  const std::vector<Light>& lights() const;  // the point, spot and directional lights solved for

  // The elements and, per element: B, the lights' injected ρ·E_direct, the surfaces' own
  // emission E, and ρ. Before the first solve() B is zero.
  const Mesh& mesh() const;
  const std::vector<Rgb>& radiosity() const;
  const std::vector<Rgb>& injected() const;
  const std::vector<Rgb>& emitted() const;
  const std::vector<Rgb>& albedo() const;
  // B less the injected direct light of every light but a sky: what to interpolate when those
  // are drawn per pixel (the hybrid image; a sky's direct light stays in it).
  std::vector<Rgb> indirectRadiosity() const;
  // Mid-solve, progressive refinement's ambient term (Cohen, Chen, Wallace & Greenberg 1988;
  // the ambient term): the unshot power spread evenly over the scene and reflected to convergence, in
  // W/m². Displaying B_i + ρ_i·ambient shows a shooting solve at its final brightness from the
  // first shot. Zero for the gathering solvers, whose iterates carry no unshot power.
  Rgb ambientRadiosity() const;
  // Visibility over the scene's geometry, for shadow rays.
  const RayCaster& caster() const;

  // Per vertex of vertexMesh(): the solution's B, its indirect part or the irradiance
  // (method/method.h; gathered at the vertices themselves by the hierarchical method, the
  // elements' values interpolated otherwise), continuous values of any per-element quantity,
  // and the outgoing radiance L = B/π; albedo per patch of vertexMesh().
  // neededVertices: empty for every vertex, or one flag per vertex where only the flagged ones
  // are read (a picture's: render/rasterizer.h visiblePatches). The others may then be 0: the
  // hierarchical method gathers the flagged vertices alone, the close sources' corners among the
  // others taking the elements' interpolated radiosity (hierarchical/method.h).
  const Mesh& vertexMesh() const;
  std::vector<Rgb> vertexValues(VertexQuantity quantity, std::span<const std::uint8_t> neededVertices = {}) const;
  // Several at once (one final gather for all of them), in the order asked for.
  std::vector<std::vector<Rgb>> vertexValues(std::span<const VertexQuantity> quantities,
                                             std::span<const std::uint8_t> neededVertices = {}) const;
  std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const;
  std::vector<Rgb> vertexRadiance() const;
  // The irradiance E (W/m²) at points on the scene's faces: from the surfaces, gathered at each
  // point as at the vertices (hierarchical/final_gather.h), and from the lights, traced at each point.
  // The hierarchical method only (the other methods' elements carry no links to gather over):
  // an Error saying so for the others.
  Result<std::vector<Rgb>> pointIrradiance(std::span<const SurfacePoint> points) const;
  const std::vector<Rgb>& vertexMeshAlbedo() const;

 private:
  friend class Radiosity;
  friend struct SolutionInternals;  // engine/radiosity.cpp: the engine's state behind the view
  explicit SolutionView(const Radiosity& engine) : engine_(&engine) {}
  const Radiosity* engine_;
};

}  // namespace lambert
