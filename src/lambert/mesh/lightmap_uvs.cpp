#include "lambert/mesh/lightmap_uvs.h"

// The pipeline (the file head of lightmap_uvs.h says what and why): the file's coordinates where
// they are usable (their overlaps found by mesh/uv_overlap_grid.h), else charts
// (mesh/uv_charts.h, flattened by mesh/lscm.h where curved) packed into atlases
// (mesh/uv_packing.h) at the texel size asked for or the smallest that fits one atlas.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lambert/core/vec2.h"
#include "lambert/core/warning.h"
#include "lambert/mesh/uv_charts.h"
#include "lambert/mesh/uv_overlap_grid.h"
#include "lambert/mesh/uv_packing.h"

namespace lambert {
namespace {

constexpr int kReferenceAtlasSize = 1024;  // defaultTexelSize fills an atlas of this size
constexpr std::size_t kMaxAtlases = 65535;  // LightmapUvs::atlas is 16-bit

// Texel centres covered by faces (each counted once), over all atlases.
double coveredFraction(const LightmapUvs& uvs) {
  const std::size_t side = static_cast<std::size_t>(uvs.size);
  std::vector<std::uint8_t> covered(side * side);
  std::size_t count = 0;
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> facesOf(static_cast<std::size_t>(uvs.numAtlases));
  for (std::uint32_t s = 0; s < uvs.uv.size(); ++s)
    for (std::uint32_t f = 0; f < uvs.uv[s].size(); ++f) facesOf[uvs.atlas[s][f]].emplace_back(s, f);
  for (int a = 0; a < uvs.numAtlases; ++a) {
    std::fill(covered.begin(), covered.end(), 0);
    for (const auto& [s, f] : facesOf[static_cast<std::size_t>(a)]) {
      const auto& c = uvs.uv[s][f];
      for (std::size_t k = 1; k + 1 < c.size(); ++k) {
        const Vec2 t[3] = {{c[0].u * uvs.size, c[0].v * uvs.size}, {c[k].u * uvs.size, c[k].v * uvs.size}, {c[k + 1].u * uvs.size, c[k + 1].v * uvs.size}};
        const double area = cross2(t[1] - t[0], t[2] - t[0]);
        if (area == 0) continue;
        const double sign = area > 0 ? 1 : -1;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].x, t[1].x, t[2].x}) - 0.5)));
        const int x1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0].x, t[1].x, t[2].x}) - 0.5)));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].y, t[1].y, t[2].y}) - 0.5)));
        const int y1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0].y, t[1].y, t[2].y}) - 0.5)));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const Vec2 q{x + 0.5, y + 0.5};
            bool inside = true;
            for (int e = 0; e < 3 && inside; ++e) inside = sign * cross2(t[(e + 1) % 3] - t[e], q - t[e]) >= 0;
            std::uint8_t& texel = covered[static_cast<std::size_t>(y) * side + static_cast<std::size_t>(x)];
            if (inside && !texel) texel = 1, ++count;
          }
      }
    }
  }
  return static_cast<double>(count) / (static_cast<double>(side) * static_cast<double>(side) * uvs.numAtlases);
}

double totalArea(const Scene& scene) {
  double area = 0;
  for (const Surface& s : scene.surfaces) area += surfaceArea(s);
  return area;
}

Status checkOptions(const LightmapUvOptions& options) {
  if (!(options.texelSize >= 0) || !std::isfinite(options.texelSize))
    return Error{"lightmap UVs: the texel size must be a positive number of scene units (0 for the default), not " + std::to_string(options.texelSize)};
  if (options.paddingTexels < 0 || options.paddingTexels > 64)
    return Error{"lightmap UVs: the padding must be 0 to 64 texels, not " + std::to_string(options.paddingTexels)};
  if (options.atlasSize < options.paddingTexels + options.paddingTexels % 2 + 1 || options.atlasSize > 32768)
    return Error{"lightmap UVs: an atlas of " + std::to_string(options.atlasSize) + " texels cannot hold a chart with " +
                 std::to_string(options.paddingTexels) + " texels of padding around it (give an atlas size of " +
                 std::to_string(options.paddingTexels + options.paddingTexels % 2 + 1) + " to 32768)"};
  return Ok{};
}

// ---------------------------------------------------------------------------------------------
// The file's coordinates.

// Uses a set the file gives (the lightmap set, or the first), when every face of every surface
// has it, inside [0, 1], with area, and no two faces overlapping. Surfaces are given atlases in
// order, each the first whose faces it does not overlap: the lightmap set may span several (one
// per object, as engines export them); the first set must fit one, but for the backs of
// two-sided surfaces, which lie on their fronts' coordinates and go to further atlases. Returns
// why the set was not used ("absent" where no surface has it), or "" where `out` was filled.
std::string fileSet(const Scene& scene, bool lightmapSet, const LightmapUvOptions& options, LightmapUvs& out) {
  const char* name = lightmapSet ? "the file's lightmap coordinates (TEXCOORD_1)" : "the file's texture coordinates";
  auto setOf = [&](const Surface& s) -> const std::vector<std::vector<Uv>>& { return lightmapSet ? s.faceLightmapUvs : s.faceUvs; };
  std::size_t missing = 0, triangles = 0;
  for (const Surface& s : scene.surfaces) {
    const auto& set = setOf(s);
    const std::size_t faces = s.faces.empty() ? 1 : s.faces.size();
    if (set.size() != faces) {
      ++missing;
      continue;
    }
    for (std::size_t f = 0; f < faces; ++f) {
      const std::size_t corners = s.faces.empty() ? s.vertices.size() : s.faces[f].size();
      if (set[f].size() != corners) {
        ++missing;
        break;
      }
      triangles += corners - 2;
    }
  }
  if (missing == scene.surfaces.size()) return "absent";  // nothing to say
  if (missing > 0) return std::string(name) + ": " + std::to_string(missing) + " of " + std::to_string(scene.surfaces.size()) + " surfaces have none";
  const double tolerance = 1e-3 / options.atlasSize;  // a thousandth of a texel at the largest atlas
  std::vector<OverlapGrid> atlases;
  std::vector<std::uint16_t> surfaceAtlas(scene.surfaces.size(), 0);
  double area3 = 0, area2 = 0;
  // Fronts first, then the backs of two-sided surfaces.
  std::vector<std::uint32_t> order;
  for (int pass = 0; pass < 2; ++pass)
    for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s)
      if ((scene.surfaces[s].twin >= 0 && scene.surfaces[s].twin < static_cast<int>(s)) == (pass == 1)) order.push_back(s);
  std::vector<Vec2> tris;
  for (std::uint32_t s : order) {
    const Surface& surface = scene.surfaces[s];
    const auto& set = setOf(surface);
    const auto faces = surfaceFaces(surface);
    tris.clear();
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& c = set[f];
      for (const Uv& uv : c)
        if (!(uv.u >= 0 && uv.u <= 1 && uv.v >= 0 && uv.v <= 1))
          return std::string(name) + ": surface '" + surface.name + "' face " + std::to_string(f) + " has (" + std::to_string(uv.u) + ", " +
                 std::to_string(uv.v) + "), outside [0, 1]";
      const std::vector<Vec3> p = facePositions(surface, faces[f]);
      double a3 = 0, a2 = 0;
      for (std::size_t k = 1; k + 1 < c.size(); ++k) {
        a3 += 0.5 * length(cross(p[k] - p[0], p[k + 1] - p[0]));
        a2 += 0.5 * std::fabs((c[k].u - c[0].u) * (c[k + 1].v - c[0].v) - (c[k + 1].u - c[0].u) * (c[k].v - c[0].v));
        tris.insert(tris.end(), {Vec2{c[0].u, c[0].v}, Vec2{c[k].u, c[k].v}, Vec2{c[k + 1].u, c[k + 1].v}});
      }
      if (!(a2 > 1e-12))
        return std::string(name) + ": surface '" + surface.name + "' face " + std::to_string(f) + " has no area in them";
      area3 += a3, area2 += a2;
    }
    // The surface against itself.
    {
      OverlapGrid self({0, 0}, {1, 1}, tris.size() / 3, tolerance);
      for (std::size_t t = 0; t < tris.size(); t += 3) {
        if (self.overlapping(&tris[t]) >= 0)
          return std::string(name) + ": faces of surface '" + surface.name + "' overlap one another";
        self.insert(&tris[t], s);
      }
    }
    const bool back = surface.twin >= 0 && surface.twin < static_cast<int>(s);
    std::size_t a = 0;
    for (;; ++a) {
      if (a == atlases.size()) {
        if (a >= kMaxAtlases) return std::string(name) + ": more than 65535 atlases would be needed";
        atlases.emplace_back(Vec2{0, 0}, Vec2{1, 1}, triangles, tolerance);
      }
      long other = -1;
      for (std::size_t t = 0; t < tris.size() && other < 0; t += 3) other = atlases[a].overlapping(&tris[t]);
      if (other < 0) break;
      if (!lightmapSet && !back)
        return std::string(name) + ": surface '" + surface.name + "' overlaps surface '" + scene.surfaces[static_cast<std::size_t>(other)].name + "' in them";
    }
    for (std::size_t t = 0; t < tris.size(); t += 3) atlases[a].insert(&tris[t], s);
    surfaceAtlas[s] = static_cast<std::uint16_t>(a);
  }
  out.origin = lightmapSet ? LightmapUvs::Origin::FileLightmapSet : LightmapUvs::Origin::FileFirstSet;
  out.numAtlases = static_cast<int>(std::max<std::size_t>(atlases.size(), 1));
  // The atlas size: the file's mean density at the texel size asked for (a power of two, at most
  // atlasSize), or where none is asked for, the largest power of two at which the atlases
  // together hold no more texels than one of atlasSize, as generated charts fill one. Each
  // object's own Lightmap Pack square at atlasSize gave a small Blender room five 1024² atlases
  // of 5 mm texels (3.35 M texels, a 505 s bake of a room solved in 0.02 s).
  const double texelsPerUnit = std::sqrt(area2 / area3);  // atlas widths per scene unit
  out.size = options.atlasSize;
  while (options.fileSetsShareAtlas && out.size > 16 &&
         static_cast<double>(out.numAtlases) * out.size * out.size > static_cast<double>(options.atlasSize) * options.atlasSize)
    out.size /= 2;
  if (options.texelSize > 0) {
    const double wanted = 1 / (texelsPerUnit * options.texelSize);
    int size = 16;
    while (size < wanted && size < options.atlasSize) size *= 2;
    out.size = std::min(size, options.atlasSize);
  }
  out.texelSize = 1 / (texelsPerUnit * out.size);
  out.uv.resize(scene.surfaces.size());
  out.atlas.resize(scene.surfaces.size());
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    out.uv[s] = setOf(scene.surfaces[s]);
    out.atlas[s].assign(out.uv[s].size(), surfaceAtlas[s]);
  }
  out.charts = 0;
  out.note = std::string("using ") + name + " (" + std::to_string(out.numAtlases) + (out.numAtlases == 1 ? " atlas" : " atlases") + " of " +
             std::to_string(out.size) + "²)";
  return "";
}

}  // namespace

double defaultTexelSize(const Scene& scene) {
  ChartStats stats;
  const std::vector<Chart> charts = buildCharts(scene, stats);
  const LightmapUvOptions defaults;
  const double area = totalArea(scene);
  const double fitted = fittingTexelSize(charts, area, kReferenceAtlasSize, defaults.paddingTexels);
  return fitted > 0 ? fitted : std::sqrt(area / (0.5 * kReferenceAtlasSize * kReferenceAtlasSize));
}

Result<LightmapUvs> lightmapUvs(const Scene& scene, const LightmapUvOptions& options) {
  if (Status s = checkOptions(options); !s) return s.error();
  // Loaders never make these; a scene built in code might.
  for (const Surface& surface : scene.surfaces) {
    for (const Vec3& v : surface.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        return Error{"lightmap UVs: surface '" + surface.name + "' has a vertex that is not finite"};
    if (surface.vertices.size() < 3) return Error{"lightmap UVs: surface '" + surface.name + "' has fewer than 3 vertices"};
    for (const auto& face : surface.faces)
      if (face.size() < 3 || std::any_of(face.begin(), face.end(), [&](std::uint32_t i) { return i >= surface.vertices.size(); }))
        return Error{"lightmap UVs: surface '" + surface.name + "' has a face with fewer than 3 corners or a vertex index out of range"};
  }
  LightmapUvs result;
  std::string rejected;
  if (options.useFileUvs) {
    for (bool lightmapSet : {true, false}) {
      std::string why = fileSet(scene, lightmapSet, options, result);
      if (why.empty()) {
        result.efficiency = coveredFraction(result);
        if (!rejected.empty()) result.note += "; " + rejected;
        return result;
      }
      if (why != "absent") rejected += (rejected.empty() ? "" : "; ") + why;
    }
  }
  ChartStats stats;
  std::vector<Chart> charts = buildCharts(scene, stats);
  const double area = totalArea(scene);
  const int padding = options.paddingTexels;
  double texelSize = options.texelSize;
  std::vector<Placement> placements;
  std::size_t numAtlases = 0;
  int size = options.atlasSize;
  bool packed = false;
  if (texelSize == 0) {
    PackOrder order = PackOrder::ShortSide;
    texelSize = fittingTexelSize(charts, area, options.atlasSize, padding, &order);
    packed = texelSize > 0 && pack(charts, texelSize, size, padding, 1, placements, numAtlases, order);
    // Too many charts for one atlas at any texel size: half an atlas's area per atlas, several.
    if (!packed) texelSize = std::sqrt(area / (0.5 * options.atlasSize * options.atlasSize));
  }
  if (!packed) {
    // The smallest power of two that holds them all, else atlases of atlasSize.
    for (size = 16; size < options.atlasSize && !packed; size *= 2)
      if (size > 2 * padding)
        for (PackOrder order : kPackOrders)
          if (!packed) packed = pack(charts, texelSize, size, padding, 1, placements, numAtlases, order);
    if (packed) size /= 2;
    if (!packed) {
      size = options.atlasSize;
      packed = pack(charts, texelSize, size, padding, kMaxAtlases, placements, numAtlases);
    }
    if (!packed)
      return Error{"lightmap UVs: " + std::to_string(charts.size()) + " charts do not fit " + std::to_string(kMaxAtlases) + " atlases of " +
                   std::to_string(options.atlasSize) + "² at " + std::to_string(texelSize) +
                   " scene units per texel; give a larger texel size or atlas size"};
  }
  // One warning for all the charts scaled down, naming the first few.
  std::size_t scaled = 0;
  std::string which;
  for (std::size_t c = 0; c < charts.size(); ++c)
    if (placements[c].scale < 1 && ++scaled <= 4)
      which += std::string(scaled > 1 ? ", " : "") + "'" + scene.surfaces[charts[c].surface].name + "' (" + std::to_string(charts[c].width) + " × " +
               std::to_string(charts[c].height) + " scene units, scaled by " + std::to_string(placements[c].scale) + ")";
  if (scaled > 0)
    warning("lightmap UVs: " + std::to_string(scaled) + (scaled == 1 ? " chart is" : " charts are") + " larger than an atlas of " +
            std::to_string(size) + " texels at " + std::to_string(texelSize) + " scene units per texel, and scaled down to fit: " + which +
            (scaled > 4 ? ", …" : "") + " (give a larger texel size or atlas size to keep one texel size)");
  result.origin = LightmapUvs::Origin::Generated;
  result.size = size;
  result.numAtlases = static_cast<int>(numAtlases);
  result.texelSize = texelSize;
  result.charts = charts.size();
  result.conformalCharts = stats.conformal;
  result.uv.resize(scene.surfaces.size());
  result.atlas.resize(scene.surfaces.size());
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const std::size_t faces = scene.surfaces[s].faces.empty() ? 1 : scene.surfaces[s].faces.size();
    result.uv[s].resize(faces);
    result.atlas[s].resize(faces);
  }
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const Chart& chart = charts[c];
    const Placement& p = placements[c];
    const double k = p.scale / texelSize;  // texels per scene unit
    const double w = chart.width * k, h = chart.height * k;
    const int fw = footprint(chart.width * p.scale, texelSize), fh = footprint(chart.height * p.scale, texelSize);
    // The chart centred in its footprint, which starts `padding` texels into its rectangle.
    const int inset = (padding + 1) / 2;
    const double ox = p.x + inset + (p.rotated ? (fh - h) : (fw - w)) / 2, oy = p.y + inset + (p.rotated ? (fw - w) : (fh - h)) / 2;
    for (std::size_t i = 0; i < chart.faces.size(); ++i) {
      std::vector<Uv>& corners = result.uv[chart.surface][chart.faces[i]];
      corners.clear();
      for (std::uint32_t j = chart.cornerStart[i]; j < chart.cornerStart[i + 1]; ++j) {
        const Vec2 q = chart.corners[j];
        const Vec2 t = p.rotated ? Vec2{q.y * k, w - q.x * k} : Vec2{q.x * k, q.y * k};
        corners.push_back({std::clamp((ox + t.x) / size, 0.0, 1.0), std::clamp((oy + t.y) / size, 0.0, 1.0)});
      }
      result.atlas[chart.surface][chart.faces[i]] = static_cast<std::uint16_t>(p.atlas);
    }
  }
  result.efficiency = coveredFraction(result);
  char text[256];
  std::snprintf(text, sizeof text, "generated %zu charts (%zu planar, %zu conformal; %zu splits) in %d atlas%s of %d², %.4g units per texel, %.1f%% covered",
                charts.size(), stats.planar, stats.conformal, stats.splits, result.numAtlases, result.numAtlases == 1 ? "" : "es", size,
                texelSize, 100 * result.efficiency);
  result.note = text;
  if (!rejected.empty()) result.note += "; not used: " + rejected;
  return result;
}

}  // namespace lambert