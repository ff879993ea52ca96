#pragma once
// The ground truth lambert measures itself against: an unbiased Monte Carlo path tracer
// for exactly the physics the radiosity solves. Surfaces are one-sided Lambertian polygons (the
// back is black and opaque), albedo ρ per material; emissive surfaces emit radiance L_e from their
// front only; point, spot and directional lights give E = I cosθ / r² (r in metres, through
// scene.metresPerUnit) or E⊥ cosθ, evaluated by lambert::irradiance, the very function the
// radiosity injects them with.
//
// Estimator. At every surface vertex y of a path (front faces only; a ray that meets a back face
// or leaves the scene carries nothing):
//   * every point/spot/directional light adds ρ/π · irradiance(light, y) (one shadow ray each);
//   * area emitters are sampled by next-event estimation: an emissive patch of the geometry mesh
//     is picked in proportion to its area, a uniform point on it, a shadow ray;
//   * the path goes on in a cosine-weighted direction, throughput *= ρ (cos/pdf cancels π);
//     Russian roulette after minBounces with survival min(0.95, max throughput component).
// The two estimates of the emitters' light (next-event and the cosine-sampled ray that happens to
// hit an emitter's front) are combined by multiple importance sampling with the power heuristic
// (Veach & Guibas 1995): each gets weight p_own²/(p_light² + p_cosine²), with p_light the
// solid-angle density r²/(A_emitters cosθ_emitter) of the area sampling and p_cosine = cosθ/π.
// The weights sum to one for every direction, so the estimate stays unbiased, and a next-event
// sample contributes at most π·L_e/2 (times ρ/π). Next-event estimation alone (no MIS) has a
// cosθ cosθ'/r² weight that is unbounded near an edge shared with an emitter, and its variance
// grows without bound as the point nears that edge; with MIS the estimate converges next to
// emitting walls, edges and corners, and small emitters are still sampled mostly by next-event
// estimation. Camera rays (depth 0) see L_e in full.
//
// Bias: none, except that paths are cut after maxBounces reflections: light that has been
// reflected more than maxBounces times is missing (at most ρ_max^maxBounces of the total; about
// 1e-8 for ρ = 0.75 and the default 64). Results depend only on (seed, stream): every vertex and
// every pixel has its own Pcg32 stream, so they are identical whatever the thread count.
#include <cstdint>
#include <memory>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/sampling.h"
#include "lambert/core/vec3.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/core/image.h"
#include "lambert/scene/scene.h"

namespace lambert {

class Pcg32;

struct ReferenceOptions {
  int samplesPerPixel = 64;  // image: samples per pixel, stratified in the pixel
  int vertexSamples = 1024;  // per vertex estimate: cosine-weighted directions, and as many emitter samples
  int minBounces = 3;        // Russian roulette starts after this many bounces
  int maxBounces = 64;       // hard cap on reflections per path: the estimator's only bias
  std::uint64_t seed = 1;
  bool showProgress = true;
};

class ReferenceRenderer {
 public:
  // Builds its own Embree caster over a copy of `geometry`: any mesh of the scene's surfaces (e.g.
  // subdivideScene(scene, large)) whose patches index scene.surfaces. Its emissive patches are
  // what next-event estimation samples.
  ReferenceRenderer(const Scene& scene, const Mesh& geometry, ReferenceOptions options = {});
  ~ReferenceRenderer();
  ReferenceRenderer(ReferenceRenderer&&) noexcept;
  ReferenceRenderer& operator=(ReferenceRenderer&&) noexcept;

  // Outgoing radiance L_o in W/(m²·sr) leaving the front of point x on surface `surface` (unit
  // normal n): L_e + ρ/π · E(x), with E the irradiance from everything (the lights exactly, the
  // emitters and the indirect light from vertexSamples stratified (0,2)-sequence cosine directions
  // and as many stratified emitter samples; the first bounce is never rouletted). Deterministic in
  // (options.seed, stream).
  Rgb outgoingRadiance(const Vec3& x, const Vec3& n, std::uint32_t surface, std::uint64_t stream) const;
  // The irradiance E in W/m² at the front of that point, of which outgoingRadiance is L_e + ρ/π·E
  // (the same estimate, stream for stream): what a light meter on the surface reads.
  Rgb irradianceAt(const Vec3& x, const Vec3& n, std::uint32_t surface, std::uint64_t stream) const;

  // (b) outgoingRadiance at every vertex of a radiosity mesh, stream = vertex index. The normal is
  // that of the vertex's patches (their mean; the surface's plane for a planar surface). So as not
  // to evaluate exactly on an edge shared with a perpendicular surface (where the irradiance
  // jumps), the point is moved 1e-4 of the scene diagonal toward the centroid of the vertex's
  // adjacent patches' centroids, into its own surface. Vertices no patch uses get zero, as in
  // vertexRadiosity. Parallel over vertices; deterministic per (seed, vertex).
  std::vector<Rgb> vertexRadiance(const Mesh& radiosityMesh) const;

  // (a) Linear radiance image from scene.camera, width × height, samplesPerPixel paths per pixel
  // (pixel positions, first emitter sample and first bounce each a (0,2)-sequence, paired through
  // random permutations of their indices so the pixel estimate converges as spp grows). Camera
  // rays see L_e of the emitter they hit and pass through the backs of one-sided faces (culled,
  // as the rasterizer draws); the background is black. Parallel over
  // rows; deterministic per (seed, pixel).
  Image render(int width, int height) const;

  // Rays traced by this renderer since construction (intersections and shadow rays).
  std::uint64_t raysCast() const;

  const ReferenceOptions& options() const { return options_; }

 private:
  struct Vertex {
    Vec3 position;
    Vec3 normal;
    std::uint32_t surface = 0;
  };

  Rgb lightIrradiance(const Vertex& v) const;
  Rgb emitterIrradiance(const Vertex& v, UnitSquarePoint sample) const;
  double cosineWeight(double cosAtVertex, double distanceSquared, double cosAtEmitter) const;
  Rgb reflected(Vertex v, int bounce, Pcg32& rng, const UnitSquarePoint* firstLight,
                const UnitSquarePoint* firstDirection) const;

  Scene scene_;
  ReferenceOptions options_;
  std::unique_ptr<Mesh> geometry_;  // heap-held: the caster keeps a reference to it
  std::unique_ptr<RayCaster> caster_;
  double epsilon_ = 0;
  std::vector<Rgb> albedo_;   // per surface
  std::vector<Rgb> emitted_;  // L_e per surface (an emission texture enters as its mean over the surface)
  std::vector<std::uint32_t> emitterPatches_;  // emissive patches of geometry_
  std::vector<double> emitterCdf_;             // running sum of their areas (scene units²)
  double emitterArea_ = 0;
};

}  // namespace lambert
