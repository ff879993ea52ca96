#include "lambert/flat/hemicube.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/formfactor/kernels.h"

namespace lambert {
namespace {

// A face of the hemi-cube as a camera: looking along `forward`, image axes `right` and `up`,
// the face plane at distance 1. Pixels span [-1, 1] along right and [vMin, 1] along up.
struct Face {
  Vec3 forward, right, up;
  double vMin;  // −1 for the top face, 0 for the sides (only the half above the base plane)
  int rows;
};

}  // namespace

Hemicube::Hemicube(int resolution) : resolution_(resolution) {
  LAMBERT_CHECK(resolution >= 2 && resolution % 2 == 0);
  const int r = resolution;
  const double pixel = 2.0 / r;
  top_.resize(static_cast<std::size_t>(r) * r);
  side_.resize(static_cast<std::size_t>(r) * (r / 2));
  const Vec3 origin{0, 0, 0}, up{0, 0, 1};
  for (int y = 0; y < r; ++y)
    for (int x = 0; x < r; ++x) {
      double x0 = -1 + x * pixel, y0 = -1 + y * pixel;
      Vec3 square[4] = {{x0, y0, 1}, {x0, y0 + pixel, 1}, {x0 + pixel, y0 + pixel, 1}, {x0 + pixel, y0, 1}};
      top_[static_cast<std::size_t>(y) * r + x] = pointToPolygonFormFactor(origin, up, square, {0, 0, -1});
    }
  // The side face at +x: the square x = 1, y ∈ [−1, 1], z ∈ [0, 1].
  for (int z = 0; z < r / 2; ++z)
    for (int x = 0; x < r; ++x) {
      double y0 = -1 + x * pixel, z0 = z * pixel;
      Vec3 square[4] = {{1, y0, z0}, {1, y0 + pixel, z0}, {1, y0 + pixel, z0 + pixel}, {1, y0, z0 + pixel}};
      side_[static_cast<std::size_t>(z) * r + x] = pointToPolygonFormFactor(origin, up, square, {-1, 0, 0});
    }
}

double Hemicube::sum() const {
  double total = 0;
  for (double d : top_) total += d;
  for (double d : side_) total += 4 * d;
  return total;
}

void Hemicube::row(const Mesh& mesh, std::size_t i, Scratch& scratch, float* row) const {
  const std::size_t n = mesh.numPatches();
  std::fill(row, row + n, 0.0f);
  const Patch& patch = mesh.patches[i];
  Vec3 t, b;
  orthonormalBasis(patch.normal, t, b);
  // Lift the eye off the patch so its own plane's neighbours do not z-fight with it.
  const double lift = 1e-6 * std::sqrt(patch.area);
  const Vec3 eye = patch.centroid + patch.normal * lift;
  const int r = resolution_;
  const Face faces[5] = {{patch.normal, t, b, -1, r}, {t, b, patch.normal, 0, r / 2}, {-t, -b, patch.normal, 0, r / 2},
                         {b, -t, patch.normal, 0, r / 2}, {-b, t, patch.normal, 0, r / 2}};
  const double nearPlane = 1e-7 * std::sqrt(patch.area);

  for (int f = 0; f < 5; ++f) {
    const Face& face = faces[f];
    const int rows = face.rows;
    scratch.depth.assign(static_cast<std::size_t>(r) * rows, INFINITY);
    scratch.item.assign(static_cast<std::size_t>(r) * rows, -1);
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      PatchCorners corners = mesh.corners(j);
      // View coordinates (u along right, v along up, w depth along forward), clipped to w > near.
      Vec3 view[4], clipped[5];
      bool anyInFront = false;
      for (std::size_t k = 0; k < corners.size(); ++k) {
        Vec3 d = corners[k] - eye;
        view[k] = {dot(d, face.right), dot(d, face.up), dot(d, face.forward)};
        anyInFront |= view[k].z > nearPlane;
      }
      if (!anyInFront) continue;
      std::size_t count = clipAbovePlane(std::span<const Vec3>(view, corners.size()), {0, 0, nearPlane}, {0, 0, 1}, clipped);
      if (count < 3) continue;
      const bool front = dot(mesh.patches[j].normal, eye - corners[0]) > 0;
      if (!front && mesh.patches[j].twinned) continue;  // the twin lying on it is seen instead
      // Project: pixel coordinates px = (u/w + 1)/pixel, py = (v/w − vMin)/pixel.
      const double pixelsPerUnit = r / 2.0;
      double px[5], py[5], invW[5];
      double minX = INFINITY, maxX = -INFINITY, minY = INFINITY, maxY = -INFINITY;
      for (std::size_t k = 0; k < count; ++k) {
        invW[k] = 1 / clipped[k].z;
        px[k] = (clipped[k].x * invW[k] + 1) * pixelsPerUnit;
        py[k] = (clipped[k].y * invW[k] - face.vMin) * pixelsPerUnit;
        minX = std::fmin(minX, px[k]);
        maxX = std::fmax(maxX, px[k]);
        minY = std::fmin(minY, py[k]);
        maxY = std::fmax(maxY, py[k]);
      }
      const int x0 = std::max(0, static_cast<int>(std::ceil(minX - 0.5))), x1 = std::min(r - 1, static_cast<int>(std::floor(maxX - 0.5)));
      const int y0 = std::max(0, static_cast<int>(std::ceil(minY - 0.5))), y1 = std::min(rows - 1, static_cast<int>(std::floor(maxY - 0.5)));
      if (x0 > x1 || y0 > y1) continue;
      // Fan triangles; a pixel centre inside one of them (edge function test) takes the depth
      // interpolated in 1/w, which is linear in screen space.
      for (std::size_t k = 1; k + 1 < count; ++k) {
        const std::size_t a = 0, bb = k, c = k + 1;
        double area = (px[bb] - px[a]) * (py[c] - py[a]) - (px[c] - px[a]) * (py[bb] - py[a]);
        if (area == 0) continue;
        for (int y = y0; y <= y1; ++y) {
          double sy = y + 0.5;
          for (int x = x0; x <= x1; ++x) {
            double sx = x + 0.5;
            double w0 = ((px[bb] - sx) * (py[c] - sy) - (px[c] - sx) * (py[bb] - sy)) / area;
            double w1 = ((px[c] - sx) * (py[a] - sy) - (px[a] - sx) * (py[c] - sy)) / area;
            double w2 = 1 - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            double inverseDepth = w0 * invW[a] + w1 * invW[bb] + w2 * invW[c];
            float depth = static_cast<float>(1 / inverseDepth);
            std::size_t p = static_cast<std::size_t>(y) * r + x;
            if (depth < scratch.depth[p]) {
              scratch.depth[p] = depth;
              scratch.item[p] = front ? static_cast<std::int32_t>(j) : -1;  // a back face hides, gives nothing
            }
          }
        }
      }
    }
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < r; ++x) {
        std::int32_t j = scratch.item[static_cast<std::size_t>(y) * r + x];
        if (j >= 0) row[j] += static_cast<float>(f == 0 ? topDelta(x, y) : sideDelta(x, y));
      }
  }
}

void hemisphereRow(const Mesh& mesh, const RayCaster& caster, std::size_t i, int rays, std::uint64_t seed, float* row) {
  const std::size_t n = mesh.numPatches();
  std::fill(row, row + n, 0.0f);
  const Patch& patch = mesh.patches[i];
  const PatchCorners corners = mesh.corners(i);
  Vec3 t, b;
  orthonormalBasis(patch.normal, t, b);
  const double epsilon = rayEpsilon(mesh);
  Pcg32 rng(seed, i);
  const std::uint32_t su = rng.nextUint(), sv = rng.nextUint(), du = rng.nextUint(), dv = rng.nextUint(),
                      pairing = rng.nextUint();
  std::vector<std::uint32_t> hits(n, 0);
  for (int k = 0; k < rays; ++k) {
    auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
    Vec3 origin = sampleConvexPolygon(corners, u, v) + patch.normal * epsilon;
    // Cosine-distributed direction (Malley): a uniform point on the unit disk lifted to the
    // hemisphere, drawn through a shuffled index so it is independent of the point.
    auto [s, w] = scrambledZeroTwo(shuffledIndex(static_cast<std::uint32_t>(k), pairing), du, dv);
    double radius = std::sqrt(s), phi = 2 * kPi * w;
    double x = radius * std::cos(phi), y = radius * std::sin(phi), z = std::sqrt(std::fmax(0.0, 1 - s));
    Vec3 direction = t * x + b * y + patch.normal * z;
    if (auto hit = caster.intersect(Ray{origin, direction, 0, INFINITY}); hit && hit->frontFace && hit->patch != i) ++hits[hit->patch];
  }
  for (std::size_t j = 0; j < n; ++j) row[j] = static_cast<float>(static_cast<double>(hits[j]) / rays);
}

}  // namespace lambert
