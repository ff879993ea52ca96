#include "lambert/scene/regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "lambert/core/warning.h"

namespace lambert {
namespace {

bool isFinite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the lowest piece names the region
  }
};

}  // namespace

void DroppedFaces::add(const DroppedFaces& other) {
  nonFinite += other.nonFinite;
  repeatedVertex += other.repeatedVertex;
  noArea += other.noArea;
  outOfRange += other.outOfRange;
}

std::string DroppedFaces::describe() const {
  if (total() == 0) return "";
  std::string kinds;
  auto kind = [&](std::size_t n, const char* what) {
    if (n == 0) return;
    kinds += (kinds.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  kind(nonFinite, "with a NaN or infinite coordinate");
  kind(repeatedVertex, "with a repeated vertex");
  kind(noArea, "with no area");
  kind(outOfRange, "with a vertex index out of range");
  return std::to_string(total()) + " degenerate face" + (total() == 1 ? "" : "s") + " dropped: " + kinds;
}

Rgb boundedAlbedo(Rgb albedo, const std::string& where) {
  constexpr double kMaxAlbedo = 0.999;
  if (albedo.maxComponent() < 1) return albedo;
  warning(where + ": albedo of 1 or more lowered to 0.999 (a surface cannot reflect all the light it receives)");
  for (int c = 0; c < 3; ++c) albedo[c] = std::fmin(albedo[c], kMaxAlbedo);
  return albedo;
}

std::vector<std::array<std::uint32_t, 3>> triangulatePolygon(const std::vector<Vec3>& polygon, const Vec3& normal) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  const std::size_t n = polygon.size();
  if (n < 3) return triangles;
  // Work in the polygon's plane.
  Vec3 tangent, bitangent;
  orthonormalBasis(normal, tangent, bitangent);
  struct P {
    double x, y;
  };
  std::vector<P> p(n);
  for (std::size_t k = 0; k < n; ++k) p[k] = {dot(polygon[k], tangent), dot(polygon[k], bitangent)};
  auto area2 = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return (p[b].x - p[a].x) * (p[c].y - p[a].y) - (p[c].x - p[a].x) * (p[b].y - p[a].y);
  };
  const double scale = polygonExtent(polygon);
  const double tiny = 1e-14 * scale * scale;
  std::vector<std::uint32_t> left(n);
  std::iota(left.begin(), left.end(), 0u);
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (area2(a, b, c) > tiny) triangles.push_back({a, b, c});
  };
  while (left.size() > 3) {
    const std::size_t m = left.size();
    std::size_t ear = m;
    for (std::size_t k = 0; k < m && ear == m; ++k) {
      const std::uint32_t a = left[(k + m - 1) % m], b = left[k], c = left[(k + 1) % m];
      if (area2(a, b, c) <= tiny) continue;  // reflex or collinear: not an ear
      bool empty = true;
      for (std::uint32_t q : left) {
        if (q == a || q == b || q == c) continue;
        if (area2(a, b, q) >= -tiny && area2(b, c, q) >= -tiny && area2(c, a, q) >= -tiny) {
          empty = false;
          break;
        }
      }
      if (empty) ear = k;
    }
    // A polygon that is not simple has no ear: cut the first convex corner anyway, so the loop
    // ends; the result still covers the polygon's outline.
    if (ear == m)
      for (std::size_t k = 0; k < m && ear == m; ++k)
        if (area2(left[(k + m - 1) % m], left[k], left[(k + 1) % m]) > tiny) ear = k;
    if (ear == m) break;  // every corner collinear: nothing with area remains
    emit(left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]);
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  if (left.size() == 3) emit(left[0], left[1], left[2]);
  return triangles;
}

DroppedFaces addSmoothRegions(Scene& scene, const PolygonMesh& mesh, const std::vector<Rgb>& emittedRadiance,
                              const RegionOptions& options) {
  // 1. Clean faces, and split the non-convex ones into triangles: convex pieces with a normal each.
  struct Piece {
    std::vector<std::uint32_t> vertices;  // into mesh.positions
    int material;
    Vec3 normal;
    std::vector<Uv> uvs;  // per corner, or empty
  };
  // Exporters split vertices where normals or UVs differ (Blender's glTF exporter does, for every
  // flat-shaded face): vertices at exactly the same position are one vertex here, so faces
  // meet again and the crease angle alone decides where shading is smooth.
  std::vector<std::uint32_t> welded(mesh.positions.size());
  {
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> byHash;
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3& p = mesh.positions[v];
      std::uint64_t bits[3];
      std::memcpy(bits, &p.x, 8);
      std::memcpy(bits + 1, &p.y, 8);
      std::memcpy(bits + 2, &p.z, 8);
      const std::uint64_t hash = bits[0] * 0x9e3779b97f4a7c15ULL ^ (bits[1] + 0x632be59bd9b4e019ULL) * 0xbf58476d1ce4e5b9ULL ^ bits[2];
      std::vector<std::uint32_t>& same = byHash[hash];
      welded[v] = v;
      for (std::uint32_t u : same)
        if (mesh.positions[u] == p) {
          welded[v] = u;
          break;
        }
      if (welded[v] == v) same.push_back(v);
    }
  }
  std::vector<Piece> pieces;
  DroppedFaces dropped;
  for (const PolygonMesh::Face& face : mesh.faces) {
    if (std::any_of(face.vertices.begin(), face.vertices.end(), [&](std::uint32_t i) { return i >= mesh.positions.size(); })) {
      ++dropped.outOfRange;
      continue;
    }
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i : face.vertices) ids.push_back(welded[i]);
    std::vector<Vec3> polygon;
    for (std::uint32_t i : ids) polygon.push_back(mesh.positions[i]);
    if (!std::all_of(polygon.begin(), polygon.end(), isFinite)) {
      ++dropped.nonFinite;
      continue;
    }
    bool repeated = false;
    for (std::size_t a = 0; a < polygon.size() && !repeated; ++a)
      for (std::size_t b = a + 1; b < polygon.size() && !repeated; ++b) repeated = ids[a] == ids[b] || polygon[a] == polygon[b];
    if (repeated) {
      ++dropped.repeatedVertex;
      continue;
    }
    const Vec3 n = polygonAreaVector(polygon);
    const double size = polygon.size() >= 3 ? polygonExtent(polygon) : 0;
    if (polygon.size() < 3 || !(length(n) > 1e-12 * size * size)) {
      ++dropped.noArea;
      continue;
    }
    const Vec3 normal = normalize(n);
    if (firstConcaveCorner(polygon, normal) == polygon.size()) {
      pieces.push_back({ids, face.material, normal, face.uvs});
      continue;
    }
    for (const auto& t : triangulatePolygon(polygon, normal)) {
      std::vector<Vec3> corners = {polygon[t[0]], polygon[t[1]], polygon[t[2]]};
      std::vector<Uv> uvs;
      if (!face.uvs.empty()) uvs = {face.uvs[t[0]], face.uvs[t[1]], face.uvs[t[2]]};
      pieces.push_back({{ids[t[0]], ids[t[1]], ids[t[2]]}, face.material, normalize(polygonAreaVector(corners)), std::move(uvs)});
    }
  }

  // 2. Pieces that share an edge, of one material, within the crease angle, are one region.
  UnionFind regions(pieces.size());
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> edgePieces;
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    const auto& v = pieces[p].vertices;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::uint32_t a = v[k], b = v[(k + 1) % v.size()];
      edgePieces[(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b)].push_back(p);
    }
  }
  const double cosCrease = std::cos(options.creaseAngleDegrees * kPi / 180) - 1e-12;
  for (const auto& [edge, around] : edgePieces)
    for (std::size_t i = 0; i < around.size(); ++i)
      for (std::size_t j = i + 1; j < around.size(); ++j) {
        const Piece &a = pieces[around[i]], &b = pieces[around[j]];
        if (a.material == b.material && dot(a.normal, b.normal) >= cosCrease) regions.unite(around[i], around[j]);
      }

  // 3. One surface per region, in the order of each region's first piece, with its own vertices.
  std::vector<std::uint32_t> roots;
  std::unordered_map<std::uint32_t, std::size_t> surfaceOf;
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    const std::uint32_t root = regions.find(p);
    if (surfaceOf.try_emplace(root, roots.size()).second) roots.push_back(root);
  }
  const std::size_t firstSurface = scene.surfaces.size();
  scene.surfaces.resize(firstSurface + roots.size());
  std::vector<std::unordered_map<std::uint32_t, std::uint32_t>> remap(roots.size());
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    const std::size_t r = surfaceOf[regions.find(p)];
    Surface& surface = scene.surfaces[firstSurface + r];
    if (surface.faces.empty()) {
      surface.name = roots.size() == 1 ? mesh.name : mesh.name + " " + std::to_string(r + 1);
      surface.material = pieces[p].material;
      surface.emittedRadiance = emittedRadiance[static_cast<std::size_t>(pieces[p].material)];
    }
    std::vector<std::uint32_t> face;
    for (std::uint32_t v : pieces[p].vertices) {
      auto [it, inserted] = remap[r].try_emplace(v, static_cast<std::uint32_t>(surface.vertices.size()));
      if (inserted) surface.vertices.push_back(mesh.positions[v]);
      face.push_back(it->second);
    }
    if (!pieces[p].uvs.empty()) {  // UVs for every face of the surface once one has them
      surface.faceUvs.resize(surface.faces.size());
      for (std::size_t f = 0; f < surface.faces.size(); ++f) surface.faceUvs[f].resize(surface.faces[f].size());
      surface.faceUvs.push_back(pieces[p].uvs);
    } else if (!surface.faceUvs.empty()) {
      surface.faceUvs.emplace_back(face.size());
    }
    surface.faces.push_back(std::move(face));
  }
  return dropped;
}

}  // namespace lambert
