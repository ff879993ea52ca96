#include "lambert/light/emission.h"

#include <array>
#include <cmath>

#include "lambert/core/barycentric.h"
#include "lambert/scene/texture.h"

namespace lambert {

std::array<Uv, 4> patchCornerUvs(const Scene& scene, const Mesh& mesh, std::size_t patch) {
  const Patch& p = mesh.patches[patch];
  const Surface& surface = scene.surfaces[p.surface];
  std::array<Uv, 4> uvs{};
  if (surface.faceUvs.empty()) return uvs;
  const std::vector<std::uint32_t> face = surfaceFace(surface, p.face);
  const std::vector<Uv>& faceUvs = surface.faceUvs[p.face];
  // Each corner's UV from the fan triangle of the face that holds that corner: UVs are linear over
  // each fan triangle (as glTF and OBJ interpolate them), and a patch of a quad face (a
  // hierarchical leaf, a quad-tree cell) may straddle the fan's diagonal, where a non-affine
  // mapping bends.
  const PatchCorners corners = mesh.corners(patch);
  for (std::size_t c = 0; c < corners.size(); ++c) {
    std::size_t best = 1;
    std::array<double, 3> bestWeights{1, 0, 0};
    double bestInside = -INFINITY;
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      auto w = barycentric(corners[c], surface.vertices[face[0]], surface.vertices[face[k]], surface.vertices[face[k + 1]]);
      const double inside = std::fmin(w[0], std::fmin(w[1], w[2]));
      if (inside > bestInside) bestInside = inside, best = k, bestWeights = w;
    }
    const auto& w = bestWeights;
    uvs[c] = {w[0] * faceUvs[0].u + w[1] * faceUvs[best].u + w[2] * faceUvs[best + 1].u,
              w[0] * faceUvs[0].v + w[1] * faceUvs[best].v + w[2] * faceUvs[best + 1].v};
  }
  return uvs;
}

namespace {

Rgb meanOverPatch(const Texture& texture, const Scene& scene, const Mesh& mesh, std::size_t patch) {
  const PatchCorners corners = mesh.corners(patch);
  const std::array<Uv, 4> uvs = patchCornerUvs(scene, mesh, patch);
  return meanTextureOver(texture, corners, std::span<const Uv>(uvs.data(), corners.size()));
}

}  // namespace

std::vector<Rgb> emittedRadiosity(const Scene& scene, const Mesh& mesh) {
  std::vector<Rgb> emitted(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Surface& surface = scene.surfaces[mesh.patches[i].surface];
    emitted[i] = surface.emittedRadiance * kPi;
    const Texture* texture = scene.materials[static_cast<std::size_t>(surface.material)].emissionTexture.get();
    if (!texture || !(emitted[i].maxComponent() > 0)) continue;
    emitted[i] = emitted[i] * (surface.faceUvs.empty() ? texture->mean : meanOverPatch(*texture, scene, mesh, i));
  }
  return emitted;
}

Rgb meanEmittedRadiance(const Scene& scene, const Surface& surface) {
  const Texture* texture = scene.materials[static_cast<std::size_t>(surface.material)].emissionTexture.get();
  if (!texture || !(surface.emittedRadiance.maxComponent() > 0)) return surface.emittedRadiance;
  if (surface.faceUvs.empty()) return surface.emittedRadiance * texture->mean;
  Rgb sum;
  double totalArea = 0;
  const std::vector<std::vector<std::uint32_t>> faces = surfaceFaces(surface);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::vector<Vec3> corners = facePositions(surface, faces[f]);
    const double area = 0.5 * length(polygonAreaVector(corners));
    if (!(area > 0) || surface.faceUvs[f].size() != corners.size()) continue;
    sum += meanTextureOver(*texture, corners, surface.faceUvs[f]) * area;
    totalArea += area;
  }
  return totalArea > 0 ? surface.emittedRadiance * (sum * (1 / totalArea)) : surface.emittedRadiance * texture->mean;
}

std::vector<Rgb> patchAlbedo(const Scene& scene, const Mesh& mesh) {
  std::vector<Rgb> albedo(mesh.numPatches());
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Surface& surface = scene.surfaces[mesh.patches[i].surface];
    const Material& material = scene.materials[static_cast<std::size_t>(surface.material)];
    albedo[i] = material.albedo;
    if (!material.texture || surface.faceUvs.empty()) continue;
    albedo[i] = albedo[i] * meanOverPatch(*material.texture, scene, mesh, i);
  }
  return albedo;
}

}  // namespace lambert
