#pragma once
// Draws what the worker bakes (viewer/solve_worker.h): the scene's own faces lit by their
// lightmaps, and a sphere lit by the light probes at its centre, with the exposure and sRGB
// encoding of the rest of the viewer (and of render/tonemap.h).
//
// Lightmaps: each face fanned into triangles with its lightmap coordinates (mesh/lightmap_uvs.h),
// the atlas's irradiance E read per pixel from a float texture with LINEAR filtering and
// CLAMP_TO_EDGE (as render/lightmap_image.h's sampleLightmap reads it, and the glb's samplers ask
// for), and the outgoing radiance of the diffuse surface L = L_e + ρ/π · E. ρ and L_e are the
// material's albedo and the surface's emission times their textures' means (texture detail is
// not drawn: the lightmaps carry the light, not the albedo).
//
// The probe sphere: per pixel, the irradiance a surface of normal n receives from the L2 SH at
// the sphere's centre, E(n) = Σ_k E_k Y_k(n) clamped at zero, and L = ρ/π · E (Ramamoorthi &
// Hanrahan 2001; bake/probes.h). The sphere neither casts shadows nor enters the lightmaps.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "lambert/bake/probes.h"
#include "lambert/core/error.h"
#include "viewer/mesh_renderer.h"
#include "viewer/solve_worker.h"

namespace lambert::viewer {

class BakedRenderer {
 public:
  // Compiles the shaders and builds the sphere; needs a current OpenGL 3.3 core context.
  static Result<std::unique_ptr<BakedRenderer>> create(const Scene& scene);
  ~BakedRenderer();
  BakedRenderer(const BakedRenderer&) = delete;
  BakedRenderer& operator=(const BakedRenderer&) = delete;

  // Uploads the frame's atlases (and, the first time, the faces) when it is not the one drawn
  // last; returns the seconds that took.
  double upload(const LightmapFrame& frame);
  void drawLightmapped(const LightmapFrame& frame, const Eigen::Matrix4f& viewProjection, const DisplaySettings& settings);
  // A sphere of albedo ρ lit by `irradianceSh` (W/m², bake/probes.h's order).
  void drawSphere(const ShRgb& irradianceSh, const Vec3& centre, double radius, const Rgb& albedo, const Eigen::Matrix4f& viewProjection,
                  const DisplaySettings& settings);

 private:
  explicit BakedRenderer(const Scene& scene) : scene_(&scene) {}
  void buildFaces(const LightmapUvs& uvs);

  const Scene* scene_;
  unsigned lightmapProgram_ = 0, sphereProgram_ = 0;
  unsigned faceArray_ = 0, faceBuffer_ = 0, sphereArray_ = 0, sphereBuffer_ = 0, sphereIndices_ = 0;
  int sphereIndexCount_ = 0;
  std::vector<unsigned> textures_;             // per atlas
  std::vector<std::pair<int, int>> atlasRanges_;  // per atlas: first corner, corners
  const LightmapUvs* facesFor_ = nullptr;
  std::uint64_t uploadedVersion_ = 0;
};

}  // namespace lambert::viewer
