#include "lambert/render/lightmap_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "lambert/core/barycentric.h"
#include "lambert/core/error.h"
#include "lambert/mesh/mesh.h"
#include "lambert/render/rasterizer.h"

namespace lambert {
namespace {

// One fan triangle of a face, as the glb draws it: its corners' indices into the face.
struct FanTriangle {
  std::uint32_t surface = 0, face = 0;
  std::array<std::uint32_t, 3> corner{};
};

Uv interpolate(const std::vector<Uv>& uvs, const FanTriangle& t, const std::array<double, 3>& w) {
  Uv uv;
  for (int i = 0; i < 3; ++i) {
    uv.u += w[i] * uvs[t.corner[i]].u;
    uv.v += w[i] * uvs[t.corner[i]].v;
  }
  return uv;
}

}  // namespace

Rgb sampleLightmap(const Image& atlas, const Uv& uv) {
  LAMBERT_CHECK(atlas.width > 0 && atlas.height > 0);
  const double u = std::isfinite(uv.u) ? uv.u : 0.0, v = std::isfinite(uv.v) ? uv.v : 0.0;
  // Texel centres at (i + ½) / size: the filter's position in texel units, less the half.
  const double x = std::clamp(u, 0.0, 1.0) * atlas.width - 0.5, y = std::clamp(v, 0.0, 1.0) * atlas.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  auto index = [](double i, int n) { return static_cast<int>(std::clamp(i, 0.0, static_cast<double>(n - 1))); };
  const int x0 = index(fx, atlas.width), x1 = index(fx + 1, atlas.width);
  const int y0 = index(fy, atlas.height), y1 = index(fy + 1, atlas.height);
  return (atlas.at(x0, y0) * (1 - ax) + atlas.at(x1, y0) * ax) * (1 - ay) +
         (atlas.at(x0, y1) * (1 - ax) + atlas.at(x1, y1) * ax) * ay;
}

Image renderLightmapped(const Scene& scene, const BakedLightmaps& baked, const Camera& camera, const LightmapImageOptions& options) {
  const LightmapUvs& uvs = baked.uvs;
  LAMBERT_CHECK(uvs.uv.size() == scene.surfaces.size() && uvs.atlas.size() == scene.surfaces.size());
  LAMBERT_CHECK(baked.irradiance.size() == static_cast<std::size_t>(uvs.numAtlases));

  // The faces fanned from their first corners into triangles, as the glb holds them, each a patch
  // of its own (no vertex shared) so that a sample's patch names its triangle.
  Mesh mesh;
  std::vector<FanTriangle> triangles;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    LAMBERT_CHECK(uvs.uv[s].size() == uvs.atlas[s].size());
    for (std::uint32_t f = 0; f < uvs.uv[s].size(); ++f) {
      const std::vector<std::uint32_t> corners = surfaceFace(surface, f);
      LAMBERT_CHECK(uvs.uv[s][f].size() == corners.size());
      for (std::uint32_t k = 1; k + 1 < corners.size(); ++k) {
        const FanTriangle t{s, f, {0, k, k + 1}};
        const Vec3 a = surface.vertices[corners[0]], b = surface.vertices[corners[k]], c = surface.vertices[corners[k + 1]];
        if (!(lengthSquared(cross(b - a, c - a)) > 0)) continue;  // no area: nothing to see
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {a, b, c});
        mesh.vertexSurface.insert(mesh.vertexSurface.end(), 3, s);
        const std::array<std::uint32_t, 3> vertices{first, first + 1, first + 2};
        mesh.patches.push_back(makePatch(mesh.positions, vertices, s));
        mesh.patches.back().face = f;
        triangles.push_back(t);
      }
    }
  }

  RenderOptions render;
  render.width = options.width;
  render.height = options.height;
  render.supersample = options.supersample;
  render.shading = Shading::Flat;
  render.directRadiance = [&](const Vec3& position, std::uint32_t patch) {
    const FanTriangle& t = triangles[patch];
    const Surface& surface = scene.surfaces[t.surface];
    const std::array<double, 3> w = barycentric(position, mesh.positions[3 * patch], mesh.positions[3 * patch + 1], mesh.positions[3 * patch + 2]);
    const Image& atlas = baked.irradiance[uvs.atlas[t.surface][t.face]];
    const Rgb irradiance = sampleLightmap(atlas, interpolate(uvs.uv[t.surface][t.face], t, w));
    const Material& material = scene.materials.at(static_cast<std::size_t>(surface.material));
    const bool hasUvs = !surface.faceUvs.empty();
    auto textured = [&](const std::shared_ptr<const Texture>& texture) {
      if (!texture) return Rgb::gray(1);
      if (!hasUvs) return texture->mean;
      const Uv uv = interpolate(surface.faceUvs[t.face], t, w);
      return texture->sample(uv.u, uv.v);
    };
    const Rgb albedo = material.albedo * textured(material.texture);
    const Rgb emitted = surface.emittedRadiance.maxComponent() > 0 ? surface.emittedRadiance * textured(material.emissionTexture) : Rgb{};
    return emitted + albedo * irradiance / kPi;
  };
  return renderRadiance(camera, mesh, std::vector<Rgb>(mesh.numPatches()), render);
}

}  // namespace lambert
