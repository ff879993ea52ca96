#include "lambert/geometry/face_contacts.h"

#include <algorithm>
#include <cmath>

namespace lambert {
namespace {

std::uint64_t cellKey(std::int64_t x, std::int64_t y) { return static_cast<std::uint64_t>(x) << 32 ^ static_cast<std::uint64_t>(y); }

// A grid coordinate's cell, clamped so that a point far off the grid stays a valid integer.
std::int64_t cellOf(double coordinate, double lo, double cell) {
  const double c = std::floor((coordinate - lo) / cell);
  return static_cast<std::int64_t>(std::isfinite(c) ? std::clamp(c, -1e12, 1e12) : -1.0);
}

// Whether q lies inside the convex polygon (counter-clockwise or clockwise alike), up to `slack`
// (scene units) outside its edges.
bool insideConvex(const std::array<Vec2, 4>& corners, std::size_t count, Vec2 q, double slack) {
  double area = 0;
  for (std::size_t k = 0; k < count; ++k) area += cross2(corners[k], corners[(k + 1) % count]);
  const double sign = area < 0 ? -1 : 1;
  for (std::size_t k = 0; k < count; ++k) {
    const Vec2 a = corners[k], b = corners[(k + 1) % count];
    const Vec2 edge = b - a;
    if (sign * cross2(edge, q - a) < -slack * std::hypot(edge.x, edge.y)) return false;
  }
  return true;
}

}  // namespace

std::size_t FaceContacts::PlaneKeyHash::operator()(const PlaneKey& k) const {
  std::uint64_t h = static_cast<std::uint64_t>(k.offset) * 0x9e3779b97f4a7c15ull;
  for (std::int32_t c : {k.nx, k.ny, k.nz}) h = (h ^ static_cast<std::uint32_t>(c)) * 0x100000001b3ull;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

FaceContacts::PlaneKey FaceContacts::keyOf(const Vec3& normal, const Vec3& point) const {
  // Clamped, so that no offset, however far out or fine the tolerance, overflows the key.
  const double offset = std::clamp(std::floor(dot(normal, point) / tolerance_), -1e18, 1e18);
  return {static_cast<std::int32_t>(std::lround(normal.x * 1e4)), static_cast<std::int32_t>(std::lround(normal.y * 1e4)),
          static_cast<std::int32_t>(std::lround(normal.z * 1e4)), static_cast<std::int64_t>(std::isfinite(offset) ? offset : 0.0)};
}

FaceContacts::FaceContacts(const Mesh& mesh, const Scene& scene, double planeTolerance)
    : mesh_(mesh), tolerance_(planeTolerance > 0 ? planeTolerance : 1e-12) {
  for (const Surface& s : scene.surfaces) twinOf_.push_back(s.twin);
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Patch& patch = mesh.patches[p];
    if (!(patch.area > 0)) continue;
    Plane& plane = planes_[keyOf(patch.normal, patch.centroid)];
    if (plane.patches.empty()) {
      const Vec3 helper = std::fabs(patch.normal.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      plane.u = normalize(cross(helper, patch.normal));
      plane.v = cross(patch.normal, plane.u);
    }
    plane.patches.push_back(p);
  }
  // Each plane's grid: cells the size of its mean face, at most 256 across, so that a large
  // face over many small ones fills a bounded number.
  for (auto& [key, plane] : planes_) {
    Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
    std::vector<std::array<Vec2, 2>> bounds;
    double extent = 0;
    for (std::uint32_t p : plane.patches) {
      const PatchCorners c = mesh.corners(p);
      std::array<Vec2, 4> flat{};
      Vec2 flo{INFINITY, INFINITY}, fhi{-INFINITY, -INFINITY};
      for (std::size_t k = 0; k < c.size(); ++k) {
        flat[k] = {dot(c[k], plane.u), dot(c[k], plane.v)};
        flo = {std::fmin(flo.x, flat[k].x), std::fmin(flo.y, flat[k].y)};
        fhi = {std::fmax(fhi.x, flat[k].x), std::fmax(fhi.y, flat[k].y)};
      }
      plane.corners.push_back(flat);
      bounds.push_back({flo, fhi});
      extent += std::fmax(fhi.x - flo.x, fhi.y - flo.y);
      lo = {std::fmin(lo.x, flo.x), std::fmin(lo.y, flo.y)};
      hi = {std::fmax(hi.x, fhi.x), std::fmax(hi.y, fhi.y)};
    }
    plane.lo = lo;
    plane.cell = std::max({extent / static_cast<double>(plane.patches.size()), (hi.x - lo.x) / 256, (hi.y - lo.y) / 256, 1e-30});
    for (std::uint32_t i = 0; i < plane.patches.size(); ++i) {
      const std::int64_t x0 = cellOf(bounds[i][0].x, lo.x, plane.cell), y0 = cellOf(bounds[i][0].y, lo.y, plane.cell);
      const std::int64_t x1 = cellOf(bounds[i][1].x, lo.x, plane.cell), y1 = cellOf(bounds[i][1].y, lo.y, plane.cell);
      for (std::int64_t x = x0; x <= x1; ++x)
        for (std::int64_t y = y0; y <= y1; ++y) plane.grid[cellKey(x, y)].push_back(i);
    }
  }
}

bool FaceContacts::inContact(const Vec3& x, std::uint32_t self) const {
  const Patch& patch = mesh_.patches[self];
  const Vec3 facing = -patch.normal;
  PlaneKey key = keyOf(facing, x);
  const int twin = patch.surface < twinOf_.size() ? twinOf_[patch.surface] : -1;
  for (std::int64_t step : {0, -1, 1}) {
    PlaneKey k = key;
    k.offset += step;
    const auto it = planes_.find(k);
    if (it == planes_.end()) continue;
    const Plane& plane = it->second;
    const Vec2 q{dot(x, plane.u), dot(x, plane.v)};
    const auto cell = plane.grid.find(cellKey(cellOf(q.x, plane.lo.x, plane.cell), cellOf(q.y, plane.lo.y, plane.cell)));
    if (cell == plane.grid.end()) continue;
    for (std::uint32_t i : cell->second) {
      const Patch& other = mesh_.patches[plane.patches[i]];
      if (other.surface == patch.surface || static_cast<int>(other.surface) == twin) continue;
      // Only a face as the file gives it touches: a twin lying back to back on a face turns
      // into that face's object (a slab's inner top, under the floor that lies on the slab).
      if (twinOf_[other.surface] >= 0 && twinOf_[other.surface] < static_cast<int>(other.surface)) continue;
      if (dot(other.normal, facing) < 1 - 1e-6 || std::fabs(dot(other.normal, other.centroid) - dot(facing, x)) > tolerance_) continue;
      if (insideConvex(plane.corners[i], other.numCorners, q, 0)) return true;
    }
  }
  return false;
}

}  // namespace lambert
