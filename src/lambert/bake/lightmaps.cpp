#include "lambert/bake/lightmaps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lambert/bake/adaptive_texels.h"
#include "lambert/bake/lightmap_fill.h"
#include "lambert/core/parallel.h"
#include "lambert/core/progress.h"
#include "lambert/core/timer.h"
#include "lambert/core/vec2.h"
#include "lambert/engine/solution_internals.h"

namespace lambert {
namespace {

// The point of triangle abc nearest p, as barycentric weights (of a, b, c).
std::array<double, 3> nearestInTriangle(Vec2 p, Vec2 a, Vec2 b, Vec2 c) {
  const double area = cross2(b - a, c - a);
  if (area != 0) {
    const double wa = cross2(b - p, c - p) / area, wb = cross2(c - p, a - p) / area, wc = 1 - wa - wb;
    if (wa >= 0 && wb >= 0 && wc >= 0) return {wa, wb, wc};
  }
  // Outside (or degenerate): the nearest point of the three edges.
  std::array<double, 3> best{1, 0, 0};
  double bestDistance = INFINITY;
  const Vec2 corner[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    const Vec2 s = corner[e], t = corner[(e + 1) % 3];
    const Vec2 d = t - s;
    const double len2 = d.x * d.x + d.y * d.y;
    const double u = len2 > 0 ? std::clamp(((p.x - s.x) * d.x + (p.y - s.y) * d.y) / len2, 0.0, 1.0) : 0.0;
    const Vec2 q{s.x + u * d.x, s.y + u * d.y};
    const double distance = (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
    if (distance < bestDistance) {
      bestDistance = distance;
      best = {0, 0, 0};
      best[e] = 1 - u;
      best[(e + 1) % 3] = u;
    }
  }
  return best;
}

}  // namespace

LightmapTexels lightmapTexels(const Scene& scene, const LightmapUvs& uvs) {
  const int size = uvs.size;
  const std::size_t perAtlas = static_cast<std::size_t>(size) * size;
  // Per texel of every atlas: the nearest face so far (its distance from the texel centre in
  // texels, squared) and the point on it.
  struct Best {
    double distance = INFINITY;
    SurfacePoint point;
  };
  std::vector<Best> best(perAtlas * static_cast<std::size_t>(uvs.numAtlases));
  // A texel overlaps a triangle where the triangle comes within half a texel's diagonal of its
  // centre (conservative: every texel the triangle touches, and a few corners beyond).
  const double reach = 0.5 * std::sqrt(2.0);
  const double nudge = 1e-4 * sceneDiagonal(scene);
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    const std::vector<std::vector<std::uint32_t>> faces = surfaceFaces(surface);
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      const std::vector<Vec3> corners = facePositions(surface, faces[f]);
      const Vec3 normal = polygonNormal(corners);
      const std::vector<Uv>& uv = uvs.uv[s][f];
      const std::size_t atlas = uvs.atlas[s][f];
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        const std::array<std::size_t, 3> index{0, k, k + 1};
        std::array<Vec2, 3> t;
        for (int i = 0; i < 3; ++i) t[i] = {uv[index[i]].u * size, uv[index[i]].v * size};
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].x, t[1].x, t[2].x}) - reach)));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].y, t[1].y, t[2].y}) - reach)));
        const int x1 = std::min(size - 1, static_cast<int>(std::floor(std::max({t[0].x, t[1].x, t[2].x}) + reach)));
        const int y1 = std::min(size - 1, static_cast<int>(std::floor(std::max({t[0].y, t[1].y, t[2].y}) + reach)));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const Vec2 centre{x + 0.5, y + 0.5};
            const std::array<double, 3> w = nearestInTriangle(centre, t[0], t[1], t[2]);
            const Vec2 q{w[0] * t[0].x + w[1] * t[1].x + w[2] * t[2].x, w[0] * t[0].y + w[1] * t[1].y + w[2] * t[2].y};
            const double distance = (q.x - centre.x) * (q.x - centre.x) + (q.y - centre.y) * (q.y - centre.y);
            if (distance > reach * reach) continue;
            Best& b = best[atlas * perAtlas + static_cast<std::size_t>(y) * size + x];
            if (!(distance < b.distance)) continue;
            b.distance = distance;
            b.point.point = corners[index[0]] * w[0] + corners[index[1]] * w[1] + corners[index[2]] * w[2];
            // A texel only overlapping the face is baked at the face's point nearest its centre,
            // which lies on the face's rim: moved into the face as a vertex site is (a room's
            // corner line belongs to both walls, and light there depends on the side).
            if (distance > 0) {
              const Vec3 inward = (corners[index[0]] + corners[index[1]] + corners[index[2]]) / 3.0 - b.point.point;
              if (length(inward) > nudge) b.point.point += normalize(inward) * nudge;
            }
            b.point.normal = normal;
            b.point.surface = s;
            b.point.face = f;
          }
      }
    }
  }
  LightmapTexels texels;
  for (std::size_t i = 0; i < best.size(); ++i) {
    if (!(best[i].distance < INFINITY)) continue;
    texels.points.push_back(best[i].point);
    texels.atlas.push_back(static_cast<std::uint32_t>(i / perAtlas));
    texels.texel.push_back(static_cast<std::uint32_t>(i % perAtlas));
  }
  return texels;
}

Result<BakedLightmaps> bakeLightmaps(const SolutionView& solution, const LightmapBakeOptions& options) {
  Result<LightmapUvs> uvs = lightmapUvs(solution.scene(), options.uvs);
  if (!uvs) return uvs.error();
  return bakeLightmaps(solution, *uvs, options);
}

Result<BakedLightmaps> bakeLightmaps(const SolutionView& solution, const LightmapUvs& uvs, const LightmapBakeOptions& options) {
  Timer timer;
  const Scene& scene = solution.scene();
  LAMBERT_CHECK(uvs.uv.size() == scene.surfaces.size() && uvs.atlas.size() == scene.surfaces.size());
  BakedLightmaps baked;
  baked.uvs = uvs;
  const int size = uvs.size;
  const std::size_t perAtlas = static_cast<std::size_t>(size) * size;
  Progress progress("lightmap texels", 3, options.showProgress);
  const LightmapTexels texels = lightmapTexels(scene, uvs);
  // Every texel's site (where shadow rays start) and the lights' direct light there, traced per
  // texel: a point light's shadow is as sharp as the texels.
  Result<PointGather> sites = pointGather(solution, texels.points, PointGatherRequest::Sites);
  if (!sites) return sites.error();
  std::vector<Rgb> irradiance = directIrradiance(solution, sites->sites, sites->rayEpsilon);
  progress.advance(1);
  // The light from the surfaces where adaptive sampling asks for it (bake/adaptive_texels.h).
  const TexelGather gatherTexels = [&](std::span<const std::uint32_t> asked) -> Result<std::vector<Rgb>> {
    std::vector<SurfacePoint> points(asked.size());
    for (std::size_t i = 0; i < asked.size(); ++i) points[i] = texels.points[asked[i]];
    Result<PointGather> gathered = pointGather(solution, points, PointGatherRequest::Light);
    if (!gathered) return gathered.error();
    return std::move(gathered->fromSurfaces);
  };
  AdaptiveTexelStats sampled;
  Result<std::vector<Rgb>> fromSurfaces = adaptiveTexelValues(texels, size, uvs.numAtlases, gatherTexels, options.sampling, &sampled);
  if (!fromSurfaces) return fromSurfaces.error();
  for (std::size_t i = 0; i < irradiance.size(); ++i) irradiance[i] += (*fromSurfaces)[i];
  baked.texelsGathered = sampled.gathered;
  progress.advance(1);
  baked.irradiance.assign(static_cast<std::size_t>(uvs.numAtlases), Image{size, size, std::vector<Rgb>(perAtlas)});
  baked.covered.assign(static_cast<std::size_t>(uvs.numAtlases), std::vector<std::uint8_t>(perAtlas, 0));
  for (std::size_t i = 0; i < texels.points.size(); ++i) {
    baked.irradiance[texels.atlas[i]].pixels[texels.texel[i]] = irradiance[i];
    baked.covered[texels.atlas[i]][texels.texel[i]] = 1;
  }
  baked.texelsBaked = texels.points.size();
  baked.paddingRings = std::max(1, options.uvs.paddingTexels) + 1;
  LightmapFill::plan(scene, uvs, baked.covered, baked.paddingRings).apply(baked.irradiance);
  progress.advance(1);
  progress.finish();
  baked.seconds = timer.seconds();
  return baked;
}

}  // namespace lambert
