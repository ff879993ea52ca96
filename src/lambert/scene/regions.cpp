#include "lambert/scene/regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <set>

#include "lambert/core/union_find.h"
#include "lambert/core/vec2.h"
#include "lambert/core/warning.h"

namespace lambert {
namespace {

bool isFinite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

void DroppedFaces::add(const DroppedFaces& other) {
  nonFinite += other.nonFinite;
  repeatedVertex += other.repeatedVertex;
  noArea += other.noArea;
  outOfRange += other.outOfRange;
  duplicate += other.duplicate;
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
  kind(duplicate, "duplicating an earlier face");
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
  std::vector<Vec2> p(n);
  for (std::size_t k = 0; k < n; ++k) p[k] = {dot(polygon[k], tangent), dot(polygon[k], bitangent)};
  auto area2 = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return cross2(p[b] - p[a], p[c] - p[a]);
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
    std::vector<Uv> lightmapUvs;  // per corner, or empty
  };
  // Exporters split vertices where normals or UVs differ (Blender's glTF exporter does, for every
  // flat-shaded face): vertices at exactly the same position are one vertex here, so faces
  // meet again and the crease angle alone decides where shading is smooth.
  std::vector<std::uint32_t> welded(mesh.positions.size());
  {
    // Vertices sorted by their coordinates' bits (ties by index): equal positions are adjacent,
    // and each takes the lowest index among them. Bits, so 0 and −0 stay apart; ==, so a NaN
    // never welds.
    auto bits = [&](std::uint32_t v) {
      std::array<std::uint64_t, 3> b;
      std::memcpy(b.data(), &mesh.positions[v].x, 8);
      std::memcpy(b.data() + 1, &mesh.positions[v].y, 8);
      std::memcpy(b.data() + 2, &mesh.positions[v].z, 8);
      return b;
    };
    std::vector<std::pair<std::array<std::uint64_t, 3>, std::uint32_t>> sorted(mesh.positions.size());
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) sorted[v] = {bits(v), v};
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) {
      const std::uint32_t v = sorted[k].second;
      const bool sameAsPrevious = k > 0 && sorted[k - 1].first == sorted[k].first;
      const std::uint32_t first = sameAsPrevious ? welded[sorted[k - 1].second] : v;
      welded[v] = mesh.positions[first] == mesh.positions[v] ? first : v;
    }
  }
  std::vector<Piece> pieces;
  pieces.reserve(mesh.faces.size());
  DroppedFaces dropped;
  std::set<std::vector<std::uint32_t>> seen;  // the faces kept so far, as their rotated corner lists
  std::vector<std::uint32_t> ids;  // one face's welded vertices and their positions, reused
  std::vector<Vec3> polygon;
  for (const PolygonMesh::Face& face : mesh.faces) {
    if (std::any_of(face.vertices.begin(), face.vertices.end(), [&](std::uint32_t i) { return i >= mesh.positions.size(); })) {
      ++dropped.outOfRange;
      continue;
    }
    ids.clear();
    for (std::uint32_t i : face.vertices) ids.push_back(welded[i]);
    polygon.clear();
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
    // The corners from the lowest index on, in the face's order: equal for the same face started
    // at another corner, different for the reversed face.
    std::vector<std::uint32_t> key(ids);
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    if (!seen.insert(std::move(key)).second) {
      ++dropped.duplicate;
      continue;
    }
    const Vec3 normal = normalize(n);
    if (firstConcaveCorner(polygon, normal) == polygon.size()) {
      pieces.push_back({ids, face.material, normal, face.uvs, face.lightmapUvs});
      continue;
    }
    for (const auto& t : triangulatePolygon(polygon, normal)) {
      std::vector<Vec3> corners = {polygon[t[0]], polygon[t[1]], polygon[t[2]]};
      std::vector<Uv> uvs, lightmapUvs;
      if (!face.uvs.empty()) uvs = {face.uvs[t[0]], face.uvs[t[1]], face.uvs[t[2]]};
      if (!face.lightmapUvs.empty()) lightmapUvs = {face.lightmapUvs[t[0]], face.lightmapUvs[t[1]], face.lightmapUvs[t[2]]};
      pieces.push_back({{ids[t[0]], ids[t[1]], ids[t[2]]}, face.material, normalize(polygonAreaVector(corners)), std::move(uvs),
                        std::move(lightmapUvs)});
    }
  }

  // 2. Pieces that share an edge, of one material, within the crease angle, are one region.
  UnionFind regions(pieces.size());
  // Every (edge, piece) pair, sorted: the pieces around one edge are adjacent, in piece order.
  // (A sorted array rather than a hash map of vectors: no allocation per edge.)
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edgePieces;
  {
    std::size_t corners = 0;
    for (const Piece& piece : pieces) corners += piece.vertices.size();
    edgePieces.reserve(corners);
  }
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    const auto& v = pieces[p].vertices;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::uint32_t a = v[k], b = v[(k + 1) % v.size()];
      edgePieces.emplace_back((static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b), p);
    }
  }
  std::sort(edgePieces.begin(), edgePieces.end());
  const double cosCrease = std::cos(options.creaseAngleDegrees * kPi / 180) - 1e-12;
  for (std::size_t first = 0, last = 0; first < edgePieces.size(); first = last) {
    while (last < edgePieces.size() && edgePieces[last].first == edgePieces[first].first) ++last;
    for (std::size_t i = first; i < last; ++i)
      for (std::size_t j = i + 1; j < last; ++j) {
        const Piece &a = pieces[edgePieces[i].second], &b = pieces[edgePieces[j].second];
        if (a.material == b.material && dot(a.normal, b.normal) >= cosCrease) regions.unite(edgePieces[i].second, edgePieces[j].second);
      }
  }

  // 3. One surface per region, in the order of each region's first piece, with its own vertices.
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> surfaceOfRoot(pieces.size(), kNone), surfaceOfPiece(pieces.size());
  std::uint32_t regionCount = 0;
  for (std::uint32_t p = 0; p < pieces.size(); ++p) {
    std::uint32_t& r = surfaceOfRoot[regions.find(p)];
    if (r == kNone) r = regionCount++;
    surfaceOfPiece[p] = r;
  }
  // The pieces grouped by region, each group in piece order (a counting sort), so that one
  // region's vertices are numbered with one pass and a stamp array instead of a map per region.
  std::vector<std::uint32_t> groupStart(regionCount + 1, 0), byRegion(pieces.size());
  for (std::uint32_t r : surfaceOfPiece) ++groupStart[r + 1];
  for (std::uint32_t r = 0; r < regionCount; ++r) groupStart[r + 1] += groupStart[r];
  {
    std::vector<std::uint32_t> next(groupStart.begin(), groupStart.end() - 1);
    for (std::uint32_t p = 0; p < pieces.size(); ++p) byRegion[next[surfaceOfPiece[p]]++] = p;
  }
  const std::size_t firstSurface = scene.surfaces.size();
  scene.surfaces.resize(firstSurface + regionCount);
  std::vector<std::uint32_t> stamp(mesh.positions.size(), kNone), local(mesh.positions.size());
  for (std::uint32_t r = 0; r < regionCount; ++r) {
    Surface& surface = scene.surfaces[firstSurface + r];
    const Piece& first = pieces[byRegion[groupStart[r]]];
    surface.name = regionCount == 1 ? mesh.name : mesh.name + " " + std::to_string(r + 1);
    surface.material = first.material;
    surface.emittedRadiance = emittedRadiance[static_cast<std::size_t>(first.material)];
    surface.faces.reserve(groupStart[r + 1] - groupStart[r]);
    // Lightmap coordinates only where every face of the region has them (zeros would overlap).
    bool allLightmapUvs = true;
    for (std::uint32_t k = groupStart[r]; k < groupStart[r + 1]; ++k) allLightmapUvs = allLightmapUvs && !pieces[byRegion[k]].lightmapUvs.empty();
    if (allLightmapUvs) surface.faceLightmapUvs.reserve(groupStart[r + 1] - groupStart[r]);
    for (std::uint32_t k = groupStart[r]; k < groupStart[r + 1]; ++k) {
      Piece& piece = pieces[byRegion[k]];
      for (std::uint32_t& v : piece.vertices) {
        if (stamp[v] != r) {
          stamp[v] = r;
          local[v] = static_cast<std::uint32_t>(surface.vertices.size());
          surface.vertices.push_back(mesh.positions[v]);
        }
        v = local[v];  // the piece is not needed after this: its vertex list becomes the face
      }
      // UVs for every face of the surface once one has them (zero for faces without): the faces
      // before the first with UVs get zeros, and from that face on every face gets its own.
      const bool uvsSoFar = !surface.faceUvs.empty();
      if (!piece.uvs.empty() && !uvsSoFar) {
        surface.faceUvs.resize(surface.faces.size());
        for (std::size_t f = 0; f < surface.faces.size(); ++f) surface.faceUvs[f].resize(surface.faces[f].size());
      }
      if (uvsSoFar || !piece.uvs.empty())
        surface.faceUvs.push_back(piece.uvs.empty() ? std::vector<Uv>(piece.vertices.size()) : std::move(piece.uvs));
      if (allLightmapUvs) surface.faceLightmapUvs.push_back(std::move(piece.lightmapUvs));
      surface.faces.push_back(std::move(piece.vertices));
    }
  }
  return dropped;
}

}  // namespace lambert
