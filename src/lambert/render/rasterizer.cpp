#include "lambert/render/rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/core/parallel.h"
#include "lambert/render/camera.h"

namespace lambert {
namespace {

// Vertices are snapped to 1/256 pixel and edge functions are evaluated in exact integers, so the
// two triangles on either side of an edge agree exactly on which samples it owns (no cracks, no
// double coverage under the top-left rule).
constexpr int kSubpixelBits = 8;
constexpr std::int64_t kSubpixel = std::int64_t{1} << kSubpixelBits;
// The side clip planes lie this many half-screens from the view axis. Triangles are only cut
// there off screen, so those cuts never show, and snapped coordinates stay small enough that
// edge-function products cannot overflow 64 bits.
constexpr double kGuardBand = 2.0;
// Bands of this many output rows (times the supersampling, in sample rows) are the unit of
// parallel work: each owns whole output rows, so it box-filters them itself with no sharing.
constexpr int kBandRows = 8;
// With the guard band this keeps snapped coordinates within 2^25 and edge functions within
// 2^52, exact in int64 (and in the doubles the barycentrics are taken from).
constexpr int kMaxSamplesPerAxis = 1 << 16;
// The patch of samples that see no face: the background.
constexpr std::uint32_t kNoPatch = UINT32_MAX;

struct ClipVertex {
  Vec3 view;
  Rgb radiance;
};

// A plane in view space; the kept side has a·view + w >= 0.
struct ClipPlane {
  Vec3 a;
  double w = 0;
  double distance(const Vec3& v) const { return dot(a, v) + w; }
};

struct ScreenTriangle {
  std::array<std::int64_t, 3> x, y;  // fixed point, counter-clockwise in the edge-function sense
  std::array<double, 3> invZ;        // 1/depth, linear in screen space
  std::array<Rgb, 3> radianceOverZ;  // L/depth, linear in screen space
  Rgb radiance;                      // the whole triangle's radiance, when constant
  bool constant = false;
  std::uint32_t patch = kNoPatch;    // the mesh patch it is part of, when front-facing
  int minRow = 0, maxRow = 0, minCol = 0, maxCol = 0;  // sample rows/columns it may cover
};

std::int64_t floorDiv(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return -floorDiv(-a, b); }

bool lexicographicallyLess(const Vec3& p, const Vec3& q) {
  if (p.x != q.x) return p.x < q.x;
  if (p.y != q.y) return p.y < q.y;
  return p.z < q.z;
}

// The point where edge (p, q) crosses the plane. It is computed from the endpoints in a fixed
// order, so the triangles on both sides of a shared edge get the very same point.
ClipVertex intersect(const ClipVertex& p, const ClipVertex& q, const ClipPlane& plane) {
  const ClipVertex& a = lexicographicallyLess(p.view, q.view) ? p : q;
  const ClipVertex& b = &a == &p ? q : p;
  double da = plane.distance(a.view), db = plane.distance(b.view);
  double t = da / (da - db);
  return {lerp(a.view, b.view, t), a.radiance + (b.radiance - a.radiance) * t};
}

// Sutherland–Hodgman against one plane; returns the new vertex count.
int clipPolygon(const ClipVertex* in, int count, const ClipPlane& plane, ClipVertex* out) {
  int n = 0;
  for (int i = 0; i < count; ++i) {
    const ClipVertex& cur = in[i];
    const ClipVertex& next = in[(i + 1) % count];
    bool curInside = plane.distance(cur.view) >= 0, nextInside = plane.distance(next.view) >= 0;
    if (curInside) out[n++] = cur;
    if (curInside != nextInside) out[n++] = intersect(cur, next, plane);
  }
  return n;
}

class TriangleSetup {
 public:
  explicit TriangleSetup(const PinholeCamera& camera) : camera_(camera) {
    double gx = kGuardBand * camera.tanHalfFovX, gy = kGuardBand * camera.tanHalfFovY;
    planes_ = {ClipPlane{{0, 0, 1}, -camera.nearDistance}, ClipPlane{{-1, 0, gx}, 0},
               ClipPlane{{1, 0, gx}, 0}, ClipPlane{{0, -1, gy}, 0}, ClipPlane{{0, 1, gy}, 0}};
  }

  // Clips one world-space triangle and appends what is left of it as screen triangles.
  void add(const std::array<Vec3, 3>& world, const std::array<Rgb, 3>& radiance, bool constant,
           std::uint32_t patch, std::vector<ScreenTriangle>& out) const {
    static constexpr int kMaxVertices = 3 + 5;
    std::array<ClipVertex, kMaxVertices> a, b;
    int count = 3;
    bool inside = true;
    for (int i = 0; i < 3; ++i) {
      a[i] = {camera_.toView(world[i]), radiance[i]};
      for (const ClipPlane& plane : planes_) inside = inside && plane.distance(a[i].view) >= 0;
    }
    ClipVertex* polygon = a.data();
    if (!inside) {
      ClipVertex* spare = b.data();
      for (const ClipPlane& plane : planes_) {
        count = clipPolygon(polygon, count, plane, spare);
        std::swap(polygon, spare);
        if (count < 3) return;
      }
    }
    std::array<Projected, kMaxVertices> p;
    for (int i = 0; i < count; ++i) p[i] = project(polygon[i]);
    for (int i = 1; i + 1 < count; ++i) emit(p[0], p[i], p[i + 1], radiance[0], constant, patch, out);
  }

 private:
  struct Projected {
    std::int64_t x, y;
    double invZ;
    Rgb radianceOverZ;
  };

  Projected project(const ClipVertex& v) const {
    ScreenPoint s = camera_.projectView(v.view);
    double invZ = 1.0 / v.view.z;
    return {std::llround(s.x * kSubpixel), std::llround(s.y * kSubpixel), invZ, v.radiance * invZ};
  }

  void emit(Projected v0, Projected v1, Projected v2, const Rgb& radiance, bool constant,
            std::uint32_t patch, std::vector<ScreenTriangle>& out) const {
    std::int64_t area = (v2.x - v0.x) * (v1.y - v0.y) - (v2.y - v0.y) * (v1.x - v0.x);
    if (area == 0) return;
    if (area < 0) std::swap(v1, v2);
    ScreenTriangle t;
    const Projected* v[3] = {&v0, &v1, &v2};
    for (int i = 0; i < 3; ++i) {
      t.x[i] = v[i]->x;
      t.y[i] = v[i]->y;
      t.invZ[i] = v[i]->invZ;
      t.radianceOverZ[i] = v[i]->radianceOverZ;
    }
    t.radiance = radiance;
    t.constant = constant;
    t.patch = patch;
    // Sample (i, j) sits at ((i + ½)·kSubpixel, (j + ½)·kSubpixel).
    constexpr std::int64_t half = kSubpixel / 2;
    auto [xMin, xMax] = std::minmax({t.x[0], t.x[1], t.x[2]});
    auto [yMin, yMax] = std::minmax({t.y[0], t.y[1], t.y[2]});
    std::int64_t c0 = std::max<std::int64_t>(ceilDiv(xMin - half, kSubpixel), 0);
    std::int64_t c1 = std::min<std::int64_t>(floorDiv(xMax - half, kSubpixel), camera_.width - 1);
    std::int64_t r0 = std::max<std::int64_t>(ceilDiv(yMin - half, kSubpixel), 0);
    std::int64_t r1 = std::min<std::int64_t>(floorDiv(yMax - half, kSubpixel), camera_.height - 1);
    if (c0 > c1 || r0 > r1) return;
    t.minCol = static_cast<int>(c0);
    t.maxCol = static_cast<int>(c1);
    t.minRow = static_cast<int>(r0);
    t.maxRow = static_cast<int>(r1);
    out.push_back(t);
  }

  const PinholeCamera& camera_;
  std::array<ClipPlane, 5> planes_;
};

// Samples of one band of rows: radiance, 1/depth (0 = nothing drawn yet) and, when direct light
// is to be added, the front-facing patch seen (kNoPatch for none).
struct Band {
  int rowBegin = 0, rowEnd = 0, width = 0;
  std::vector<Rgb> radiance;
  std::vector<double> invZ;
  std::vector<std::uint32_t> patch;
};

template <bool kRecordPatch>
void rasterize(const ScreenTriangle& t, Band& band) {
  constexpr std::int64_t half = kSubpixel / 2;
  std::array<std::int64_t, 3> stepX, stepY, bias, originX, originY;
  for (int k = 0; k < 3; ++k) {
    int k1 = (k + 1) % 3;
    // E(p) = (p.x - a.x)·(b.y - a.y) - (p.y - a.y)·(b.x - a.x), positive inside.
    std::int64_t dx = t.x[k1] - t.x[k], dy = t.y[k1] - t.y[k];
    stepX[k] = dy;
    stepY[k] = -dx;
    originX[k] = t.x[k];
    originY[k] = t.y[k];
    // y grows downward: a top edge runs leftward, a left edge runs downward. Samples exactly on
    // any other edge belong to the neighbour across it.
    bool topLeft = (dy == 0 && dx < 0) || dy > 0;
    bias[k] = topLeft ? 0 : -1;
  }
  // Edge k runs from vertex k to k+1, so it weighs the vertex opposite, k+2.
  double area = static_cast<double>((t.x[2] - t.x[0]) * stepX[0] + (t.y[2] - t.y[0]) * stepY[0]);
  double invArea = 1.0 / area;
  int r0 = std::max(t.minRow, band.rowBegin), r1 = std::min(t.maxRow, band.rowEnd - 1);
  for (int row = r0; row <= r1; ++row) {
    std::int64_t py = row * kSubpixel + half, px = t.minCol * kSubpixel + half;
    std::array<std::int64_t, 3> e;
    for (int k = 0; k < 3; ++k) {
      e[k] = (px - originX[k]) * stepX[k] + (py - originY[k]) * stepY[k] + bias[k];
    }
    std::size_t rowOffset = static_cast<std::size_t>(row - band.rowBegin) * band.width;
    for (int col = t.minCol; col <= t.maxCol; ++col) {
      if ((e[0] | e[1] | e[2]) >= 0) {
        double w0 = static_cast<double>(e[1] - bias[1]) * invArea;
        double w1 = static_cast<double>(e[2] - bias[2]) * invArea;
        double w2 = static_cast<double>(e[0] - bias[0]) * invArea;
        double invZ = w0 * t.invZ[0] + w1 * t.invZ[1] + w2 * t.invZ[2];
        std::size_t i = rowOffset + col;
        if (invZ > band.invZ[i]) {
          band.invZ[i] = invZ;
          band.radiance[i] = t.constant ? t.radiance
                                        : (t.radianceOverZ[0] * w0 + t.radianceOverZ[1] * w1 +
                                           t.radianceOverZ[2] * w2) / invZ;
          if constexpr (kRecordPatch) band.patch[i] = t.patch;
        }
      }
      for (int k = 0; k < 3; ++k) e[k] += stepX[k] * kSubpixel;
    }
  }
}

// Adds the direct light at every sample of a rasterized band that sees the front of a patch, at
// the point the sample sees: where the ray through the sample centre meets the patch's plane.
// That is the sample's depth in the z-buffer, except that the depth belongs to the triangle as
// snapped to the subpixel grid, whose plane is off the patch's by up to a few 1e-6 of the depth
// where the view grazes it; lights want their shadow rays to leave from the surface itself.
void addDirect(const PinholeCamera& camera, const Mesh& mesh, const DirectRadianceFn& direct, Band& band) {
  // Where the ray meets the plane and the depth disagree by more than this, the sample is
  // covered only through snapping, its ray (nearly) parallel to the patch: it gets the point at
  // its depth, moved onto the plane along the normal, which stays within the snapped triangle.
  constexpr double kDepthTolerance = 1e-3;
  const double invFocal = 1.0 / camera.focalPixels;
  const double halfWidth = 0.5 * camera.width, halfHeight = 0.5 * camera.height;
  for (int row = band.rowBegin; row < band.rowEnd; ++row) {
    // The ray direction through a sample centre, scaled so its component along forward is 1
    // (the inverse of PinholeCamera::projectView), is rowDirection + right·x.
    const Vec3 rowDirection = camera.forward - camera.up * ((row + 0.5 - halfHeight) * invFocal);
    const std::size_t rowOffset = static_cast<std::size_t>(row - band.rowBegin) * band.width;
    // The plane of the patch last seen: normal·(p - origin) = 0, and along the ray
    // normal·(eye + direction·t - origin) = offset + t·(normalDotRow + x·normalDotRight).
    std::uint32_t planePatch = kNoPatch;
    Vec3 normal, origin;
    double offset = 0, normalDotRow = 0, normalDotRight = 0;
    for (int col = 0; col < band.width; ++col) {
      const std::size_t i = rowOffset + col;
      const std::uint32_t patch = band.patch[i];
      if (patch == kNoPatch) continue;
      if (patch != planePatch) {
        planePatch = patch;
        normal = mesh.patches[patch].normal;
        origin = mesh.positions[mesh.patches[patch].vertices[0]];
        offset = dot(normal, camera.eye - origin);
        normalDotRow = dot(normal, rowDirection);
        normalDotRight = dot(normal, camera.right);
      }
      const double x = (col + 0.5 - halfWidth) * invFocal;
      const Vec3 direction = rowDirection + camera.right * x;
      const double depth = -offset / (normalDotRow + x * normalDotRight);
      Vec3 position;
      if (std::fabs(depth * band.invZ[i] - 1) <= kDepthTolerance) {
        position = camera.eye + direction * depth;
      } else {
        position = camera.eye + direction * (1.0 / band.invZ[i]);
        position -= normal * dot(position - origin, normal);
      }
      band.radiance[i] += direct(position, patch);
    }
  }
}

}  // namespace


namespace {

// The one pipeline behind every entry point: the mesh's front-facing triangles set up and
// z-buffered band by band, each band handed to finish(band) once its samples are final.
// radiance holds L = B/π per vertex when perVertex (Gouraud), else per patch (flat), or nothing
// where only the patches seen are wanted (the samples' radiance is then 0); recordPatch
// keeps the patch each sample sees (Band::patch).
template <class Finish>
void rasterizeBands(const PinholeCamera& pinhole, const Mesh& mesh, const std::vector<Rgb>& radiance, bool perVertex,
                    bool recordPatch, int supersample, Finish&& finish) {
  LAMBERT_CHECK(mesh.numPatches() < kNoPatch);
  const int ss = supersample;
  const int sampleWidth = pinhole.width, sampleHeight = pinhole.height;

  // Set up triangles in chunks, in parallel; concatenating in chunk order keeps the draw order
  // (and so which of two equally near samples wins) independent of the thread count.
  constexpr std::size_t kChunk = 2048;
  const std::size_t numChunks = (mesh.numPatches() + kChunk - 1) / kChunk;
  std::vector<std::vector<ScreenTriangle>> chunks(numChunks);
  const TriangleSetup setup(pinhole);
  parallelFor(0, numChunks, [&](std::size_t c) {
    std::size_t end = std::min(mesh.numPatches(), (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) {
      PatchCorners corners = mesh.corners(i);
      std::span<const std::uint32_t> indices = mesh.cornerIndices(i);
      // Back faces are culled, as RenderPark, game engines and Blender's "Backface Culling" draw:
      // a camera outside a room sees in through the near wall. A two-sided face's back is its
      // twin's front, drawn in its place. (Light transport still treats backs as black and
      // opaque; this is only what the camera shows.)
      const bool front = dot(cross(corners[1] - corners[0], corners[2] - corners[0]), pinhole.eye - corners[0]) > 0;
      if (!front) continue;
      const bool constant = !perVertex;
      const auto patch = static_cast<std::uint32_t>(i);
      // A convex patch is a fan of triangles around its first corner.
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        std::array<Vec3, 3> world{corners[0], corners[k], corners[k + 1]};
        std::array<Rgb, 3> vertexRadiance;
        if (!perVertex) {
          vertexRadiance.fill(radiance.empty() ? Rgb{} : radiance[i]);
        } else {
          vertexRadiance = {radiance[indices[0]], radiance[indices[k]], radiance[indices[k + 1]]};
        }
        setup.add(world, vertexRadiance, constant, patch, chunks[c]);
      }
    }
  });
  std::vector<ScreenTriangle> triangles;
  for (auto& chunk : chunks) triangles.insert(triangles.end(), chunk.begin(), chunk.end());

  const int bandSampleRows = kBandRows * ss;
  const int numBands = (sampleHeight / ss + kBandRows - 1) / kBandRows;
  std::vector<std::vector<std::uint32_t>> bins(numBands);
  for (std::uint32_t i = 0; i < triangles.size(); ++i) {
    for (int b = triangles[i].minRow / bandSampleRows; b <= triangles[i].maxRow / bandSampleRows; ++b)
      bins[b].push_back(i);
  }
  parallelFor(0, static_cast<std::size_t>(numBands), [&](std::size_t b) {
    Band band;
    band.rowBegin = static_cast<int>(b) * bandSampleRows;
    band.rowEnd = std::min(band.rowBegin + bandSampleRows, sampleHeight);
    band.width = sampleWidth;
    std::size_t samples = static_cast<std::size_t>(band.rowEnd - band.rowBegin) * sampleWidth;
    band.radiance.assign(samples, Rgb{});
    band.invZ.assign(samples, 0.0);
    if (recordPatch) {
      band.patch.assign(samples, kNoPatch);
      for (std::uint32_t i : bins[b]) rasterize<true>(triangles[i], band);
    } else {
      for (std::uint32_t i : bins[b]) rasterize<false>(triangles[i], band);
    }
    finish(band);
  });
}

// The camera over the options' samples (supersample × width by supersample × height).
PinholeCamera sampleCamera(const Camera& camera, const RenderOptions& options) {
  LAMBERT_CHECK(options.width > 0 && options.height > 0 && options.supersample >= 1);
  const int ss = options.supersample;
  LAMBERT_CHECK(options.width <= kMaxSamplesPerAxis / ss && options.height <= kMaxSamplesPerAxis / ss);
  return PinholeCamera(camera, options.width * ss, options.height * ss);
}

Image render(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& radiance, bool perVertex,
             const RenderOptions& options) {
  const PinholeCamera pinhole = sampleCamera(camera, options);
  const int ss = options.supersample, sampleWidth = pinhole.width;
  Image image{options.width, options.height,
              std::vector<Rgb>(static_cast<std::size_t>(options.width) * options.height)};
  const double sampleWeight = 1.0 / (ss * ss);
  const DirectRadianceFn& direct = options.directRadiance;
  rasterizeBands(pinhole, mesh, radiance, perVertex, static_cast<bool>(direct), ss, [&](Band& band) {
    if (direct) addDirect(pinhole, mesh, direct, band);
    for (int y = band.rowBegin / ss; y < band.rowEnd / ss; ++y) {
      for (int x = 0; x < options.width; ++x) {
        Rgb sum;
        for (int sy = 0; sy < ss; ++sy) {
          const Rgb* row = &band.radiance[static_cast<std::size_t>(y * ss + sy - band.rowBegin) * sampleWidth];
          for (int sx = 0; sx < ss; ++sx) sum += row[x * ss + sx];
        }
        image.at(x, y) = sum * sampleWeight;
      }
    }
  });
  return image;
}

}  // namespace

std::vector<std::uint8_t> visiblePatches(const Camera& camera, const Mesh& mesh, const RenderOptions& options) {
  const PinholeCamera pinhole = sampleCamera(camera, options);
  // Bands run in parallel: each collects the patches it saw, merged under a lock.
  std::mutex merge;
  std::vector<std::uint8_t> seen(mesh.numPatches(), 0);
  rasterizeBands(pinhole, mesh, {}, false, true, options.supersample, [&](Band& band) {
    std::sort(band.patch.begin(), band.patch.end());
    band.patch.erase(std::unique(band.patch.begin(), band.patch.end()), band.patch.end());
    const std::lock_guard<std::mutex> lock(merge);
    for (std::uint32_t patch : band.patch)
      if (patch != kNoPatch) seen[patch] = 1;
  });
  return seen;
}

Image renderRadiance(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& patchRadiosity,
                     const RenderOptions& options) {
  LAMBERT_CHECK(patchRadiosity.size() == mesh.numPatches());
  const bool gouraud = options.shading == Shading::Gouraud;
  std::vector<Rgb> radiance;
  if (gouraud) {
    radiance = vertexRadiosity(mesh, patchRadiosity);
  } else {
    // What is seen of a partly covered patch is its open part (geometry/coverage.h).
    radiance.resize(mesh.numPatches());
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      double f = mesh.patches[i].openFraction;
      radiance[i] = f > 0 ? patchRadiosity[i] / f : Rgb{};
    }
  }
  for (Rgb& l : radiance) l = l / kPi;
  return render(camera, mesh, radiance, gouraud, options);
}

Image renderVertexRadiosity(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& vertexB,
                            const RenderOptions& options) {
  LAMBERT_CHECK(vertexB.size() == mesh.numVertices());
  const bool gouraud = options.shading == Shading::Gouraud;
  std::vector<Rgb> radiance;
  if (gouraud) {
    radiance = vertexB;
  } else {
    radiance.resize(mesh.numPatches());
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      std::span<const std::uint32_t> indices = mesh.cornerIndices(i);
      for (std::uint32_t v : indices) radiance[i] += vertexB[v];
      radiance[i] = radiance[i] / static_cast<double>(indices.size());
    }
  }
  for (Rgb& l : radiance) l = l / kPi;
  return render(camera, mesh, radiance, gouraud, options);
}

}  // namespace lambert
