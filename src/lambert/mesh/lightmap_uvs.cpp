#include "lambert/mesh/lightmap_uvs.h"

// Charts, parameterisation and packing (the file head of lightmap_uvs.h says what and why).
//
// Charts. Per surface (a smooth region: faces of different surfaces never share a chart), faces
// are grown into planar charts from the largest face outwards, over edges shared by two faces,
// taking every face whose normal is within kPlanarDegrees of the seed's. A planar chart is kept
// when at most half of its outline runs along other faces of its surface (a wall, a floor, the
// flat side of a block); the others are strips of a curved region (a cylinder's facets, a
// sphere's). The faces of those are grown again into charts whose normals stay within
// kConeDegrees of their seed's (a disc-like piece, never a closed tube or sphere), nearest the
// seed first so that charts come out round, and each is flattened by the least-squares conformal
// map (Lévy, Petitjean, Ray & Maillot 2002, "Least squares conformal maps for automatic texture
// atlas generation"): per fan triangle, the Cauchy-Riemann residual of the map in the triangle's
// own frame, weighted by its area, two vertices pinned, solved by the normal equations
// (Eigen's SimplicialLDLT). A chart whose map flips a triangle, stretches area by more than
// kMaxAreaStretch between its triangles, or overlaps itself is split in two (a breadth-first
// race from its two farthest faces) and each half flattened again; a single face is projected
// onto its own plane. Every chart is turned to its minimum-area bounding rectangle (rotating
// calipers over its convex hull: Freeman & Shapira 1975) and scaled to scene units: planar
// charts exactly, conformal ones so that their area is their faces' area.
//
// Packing. Each chart is a rectangle of whole texels: its footprint at the texel size (the
// texels its bounding box reaches) with paddingTexels more in each direction, the footprint
// ⌈padding / 2⌉ in from the rectangle's low sides. Any two charts' footprints are then
// paddingTexels apart, and each is ⌈padding / 2⌉ from the atlas's edges: every chart has at
// least half the padding of its own on every side for dilation (bilinear filtering reads one
// texel beyond a footprint), also where the atlas repeats. Rectangles are placed tallest first on a skyline, each at the lowest, then leftmost, place
// in either orientation (Jylänki 2010, "A thousand ways to pack the bin", SKYLINE-BL).
//
// Cost: linear in faces for the charts (plus the conformal maps' sparse solves, about linear
// in the curved faces), O(charts × skyline segments) per packing; the automatic texel size
// packs about a dozen times.
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <queue>

#include "lambert/core/warning.h"

namespace lambert {
namespace {

constexpr double kPlanarDegrees = 2;     // a planar chart's faces lie within this of its seed's plane
constexpr double kConeDegrees = 50;      // a conformal chart's normals stay within this of its seed's
constexpr double kMaxAreaStretch = 4;    // a conformal chart's largest / smallest triangle area ratio
constexpr int kReferenceAtlasSize = 1024;  // defaultTexelSize fills an atlas of this size
constexpr std::size_t kMaxAtlases = 65535;  // LightmapUvs::atlas is 16-bit

struct P2 {
  double x = 0, y = 0;
};
P2 operator-(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
double cross2(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }

// ---------------------------------------------------------------------------------------------
// Overlap of triangles in the plane.

// Whether two triangles' interiors overlap by more than `tolerance` (a separating-axis test over
// the six edge normals: touching along an edge or at a corner is no overlap). Either winding.
bool trianglesOverlap(const P2* a, const P2* b, double tolerance) {
  for (int which = 0; which < 2; ++which) {
    const P2* t = which == 0 ? a : b;
    for (int e = 0; e < 3; ++e) {
      const P2 d = t[(e + 1) % 3] - t[e];
      const double len = std::hypot(d.x, d.y);
      if (!(len > 0)) continue;
      const P2 axis{-d.y / len, d.x / len};
      double aLo = INFINITY, aHi = -INFINITY, bLo = INFINITY, bHi = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double pa = axis.x * a[k].x + axis.y * a[k].y, pb = axis.x * b[k].x + axis.y * b[k].y;
        aLo = std::min(aLo, pa), aHi = std::max(aHi, pa), bLo = std::min(bLo, pb), bHi = std::max(bHi, pb);
      }
      if (aHi - bLo <= tolerance || bHi - aLo <= tolerance) return false;
    }
  }
  return true;
}

// Triangles inserted one by one into a uniform grid of buckets over a box; a query tests only the
// triangles in the buckets its bounding box touches (each once). Linear in the triangles for
// triangles of similar size, instead of all pairs.
class OverlapGrid {
 public:
  OverlapGrid(P2 lo, P2 hi, std::size_t expectedTriangles, double tolerance) : lo_(lo), tolerance_(tolerance) {
    const double w = std::max(hi.x - lo.x, 1e-300), h = std::max(hi.y - lo.y, 1e-300);
    const double cells = std::clamp(static_cast<double>(expectedTriangles), 1.0, 262144.0);
    const double cell = std::sqrt(w * h / cells);
    nx_ = std::clamp(static_cast<int>(w / cell) + 1, 1, 1024);
    ny_ = std::clamp(static_cast<int>(h / cell) + 1, 1, 1024);
    sx_ = nx_ / w, sy_ = ny_ / h;
    buckets_.resize(static_cast<std::size_t>(nx_) * ny_);
  }
  // The owner of a triangle already inserted that `t` overlaps, or -1.
  long overlapping(const P2* t) {
    ++query_;
    long found = -1;
    forCells(t, [&](std::vector<std::uint32_t>& bucket) {
      for (std::uint32_t id : bucket) {
        if (stamp_[id] == query_) continue;
        stamp_[id] = query_;
        if (trianglesOverlap(t, &triangles_[3 * static_cast<std::size_t>(id)], tolerance_)) {
          found = owners_[id];
          return false;
        }
      }
      return true;
    });
    return found;
  }
  void insert(const P2* t, long owner) {
    const auto id = static_cast<std::uint32_t>(owners_.size());
    triangles_.insert(triangles_.end(), t, t + 3);
    owners_.push_back(owner);
    stamp_.push_back(0);
    forCells(t, [&](std::vector<std::uint32_t>& bucket) {
      bucket.push_back(id);
      return true;
    });
  }

 private:
  template <class F>
  void forCells(const P2* t, F&& f) {
    double xl = std::min({t[0].x, t[1].x, t[2].x}), xh = std::max({t[0].x, t[1].x, t[2].x});
    double yl = std::min({t[0].y, t[1].y, t[2].y}), yh = std::max({t[0].y, t[1].y, t[2].y});
    auto cell = [](double v, int n) { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
    const int x0 = cell((xl - lo_.x) * sx_, nx_), x1 = cell((xh - lo_.x) * sx_, nx_);
    const int y0 = cell((yl - lo_.y) * sy_, ny_), y1 = cell((yh - lo_.y) * sy_, ny_);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (!f(buckets_[static_cast<std::size_t>(y) * nx_ + x])) return;
  }

  P2 lo_;
  double tolerance_;
  int nx_ = 1, ny_ = 1;
  double sx_ = 1, sy_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::vector<P2> triangles_;
  std::vector<long> owners_;
  std::vector<std::uint64_t> stamp_;
  std::uint64_t query_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Per-surface geometry: faces, their normals, areas, centroids and edge neighbours.

struct SurfaceGeometry {
  const Surface* surface = nullptr;
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<Vec3> normal, centroid;
  std::vector<double> area;
  // Neighbours across edges shared by exactly two faces: face f's are neighbours[start[f] .. start[f + 1]).
  std::vector<std::uint32_t> start;
  std::vector<std::pair<std::uint32_t, double>> neighbours;  // (face, shared edge length)
  std::vector<double> perimeter;

  explicit SurfaceGeometry(const Surface& s) : surface(&s), faces(surfaceFaces(s)) {
    const std::size_t n = faces.size();
    normal.resize(n), centroid.resize(n), area.resize(n), perimeter.assign(n, 0);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    for (std::uint32_t f = 0; f < n; ++f) {
      const auto& face = faces[f];
      const std::vector<Vec3> p = facePositions(s, face);
      const Vec3 a = polygonAreaVector(p);
      area[f] = 0.5 * length(a);
      normal[f] = area[f] > 0 ? normalize(a) : Vec3{0, 0, 1};
      Vec3 c;
      for (const Vec3& q : p) c += q;
      centroid[f] = c * (1.0 / static_cast<double>(p.size()));
      for (std::size_t k = 0; k < face.size(); ++k) {
        const std::uint32_t u = face[k], v = face[(k + 1) % face.size()];
        perimeter[f] += length(s.vertices[v] - s.vertices[u]);
        edges.emplace_back((static_cast<std::uint64_t>(std::min(u, v)) << 32) | std::max(u, v), f);
      }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (face, neighbour), both ways
    for (std::size_t i = 0, j = 0; i < edges.size(); i = j) {
      while (j < edges.size() && edges[j].first == edges[i].first) ++j;
      if (j - i != 2 || edges[i].second == edges[i + 1].second) continue;
      pairs.emplace_back(edges[i].second, edges[i + 1].second);
      pairs.emplace_back(edges[i + 1].second, edges[i].second);
    }
    std::sort(pairs.begin(), pairs.end());
    start.assign(n + 1, 0);
    for (const auto& [f, g] : pairs) ++start[f + 1];
    for (std::size_t f = 0; f < n; ++f) start[f + 1] += start[f];
    neighbours.reserve(pairs.size());
    for (const auto& [f, g] : pairs) neighbours.emplace_back(g, sharedEdgeLength(f, g));
  }

  double sharedEdgeLength(std::uint32_t f, std::uint32_t g) const {
    double total = 0;
    const auto& a = faces[f];
    const auto& b = faces[g];
    for (std::size_t k = 0; k < a.size(); ++k) {
      const std::uint32_t u = a[k], v = a[(k + 1) % a.size()];
      for (std::size_t m = 0; m < b.size(); ++m)
        if ((b[m] == v && b[(m + 1) % b.size()] == u) || (b[m] == u && b[(m + 1) % b.size()] == v))
          total += length(surface->vertices[v] - surface->vertices[u]);
    }
    return total;
  }
};

// ---------------------------------------------------------------------------------------------
// Charts.

struct Chart {
  std::uint32_t surface = 0;
  std::vector<std::uint32_t> faces;      // into surfaceFaces(surface)
  std::vector<std::uint32_t> cornerStart;  // face k's corners are corners[cornerStart[k] ..)
  std::vector<P2> corners;               // scene units; bounding box [0, width] × [0, height]
  double width = 0, height = 0;
  double area = 0;                       // the faces' area, scene units²
  bool conformal = false;
};

// The chart's corners in the plane ⟂ `normal`, counter-clockwise seen from the front.
void projectOntoPlane(const SurfaceGeometry& g, Chart& chart, const Vec3& normal) {
  Vec3 t, b;
  orthonormalBasis(normal, t, b);
  if (dot(cross(t, b), normal) < 0) b = b * -1.0;
  chart.corners.clear();
  chart.cornerStart.assign(1, 0);
  for (std::uint32_t f : chart.faces) {
    for (std::uint32_t v : g.faces[f]) chart.corners.push_back({dot(g.surface->vertices[v], t), dot(g.surface->vertices[v], b)});
    chart.cornerStart.push_back(static_cast<std::uint32_t>(chart.corners.size()));
  }
}

// The least-squares conformal map of the chart's faces (their fan triangles), two far vertices
// pinned. False where the system is singular.
bool conformalMap(const SurfaceGeometry& g, Chart& chart) {
  const Surface& s = *g.surface;
  std::vector<std::uint32_t> local;  // chart vertex → surface vertex
  std::vector<int> index(s.vertices.size(), -1);
  for (std::uint32_t f : chart.faces)
    for (std::uint32_t v : g.faces[f])
      if (index[v] < 0) index[v] = static_cast<int>(local.size()), local.push_back(v);
  const std::size_t n = local.size();
  if (n < 3) return false;
  // Pins: the vertex farthest from the first, and the one farthest from that.
  auto farthestFrom = [&](std::size_t from) {
    std::size_t best = 0;
    double bestD = -1;
    for (std::size_t k = 0; k < n; ++k)
      if (double d = length(s.vertices[local[k]] - s.vertices[local[from]]); d > bestD) bestD = d, best = k;
    return best;
  };
  const std::size_t pinA = farthestFrom(0), pinB = farthestFrom(pinA);
  if (pinA == pinB) return false;
  const double pinDistance = length(s.vertices[local[pinB]] - s.vertices[local[pinA]]);
  // Unknowns: u then v of each free vertex.
  std::vector<int> column(n, -1);
  int free = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (k != pinA && k != pinB) column[k] = free++;
  const P2 pinned[2] = {{0, 0}, {pinDistance, 0}};
  auto pinOf = [&](std::size_t k) { return k == pinA ? pinned[0] : pinned[1]; };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * free);
  double chartExtent = pinDistance;
  const double tiny = 1e-14 * chartExtent * chartExtent;
  // Each triangle adds (rowRe² + rowIm²) / (2 area) to the energy: accumulate AᵀA and Aᵀb.
  std::vector<std::pair<int, double>> rowRe, rowIm;
  for (std::uint32_t f : chart.faces) {
    const auto& face = g.faces[f];
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const std::uint32_t tv[3] = {face[0], face[k], face[k + 1]};
      const Vec3 p0 = s.vertices[tv[0]], e1 = s.vertices[tv[1]] - p0, e2 = s.vertices[tv[2]] - p0;
      const double l1 = length(e1);
      const double twiceArea = length(cross(e1, e2));
      if (!(twiceArea > tiny) || !(l1 > 0)) continue;
      // The triangle in its own frame: x along e1, y in its plane.
      const P2 q[3] = {{0, 0}, {l1, 0}, {dot(e2, e1) / l1, twiceArea / l1}};
      // W_j = q_{j+2} − q_{j+1} (as complex numbers); residual Σ_j W_j (u_j + i v_j).
      const double w = 1 / std::sqrt(twiceArea);
      rowRe.clear(), rowIm.clear();
      double bRe = 0, bIm = 0;
      for (int j = 0; j < 3; ++j) {
        const P2 W = q[(j + 2) % 3] - q[(j + 1) % 3];
        const std::size_t k2 = static_cast<std::size_t>(index[tv[j]]);
        // Re: Wx u − Wy v; Im: Wy u + Wx v.
        if (column[k2] >= 0) {
          rowRe.push_back({column[k2], w * W.x}), rowRe.push_back({free + column[k2], -w * W.y});
          rowIm.push_back({column[k2], w * W.y}), rowIm.push_back({free + column[k2], w * W.x});
        } else {
          const P2 p = pinOf(k2);
          bRe -= w * (W.x * p.x - W.y * p.y);
          bIm -= w * (W.y * p.x + W.x * p.y);
        }
      }
      for (const auto* row : {&rowRe, &rowIm}) {
        const double b = row == &rowRe ? bRe : bIm;
        for (const auto& [c1, a1] : *row) {
          rhs[c1] += a1 * b;
          for (const auto& [c2, a2] : *row) entries.emplace_back(c1, c2, a1 * a2);
        }
      }
    }
  }
  if (free == 0) return false;
  Eigen::SparseMatrix<double> normalMatrix(2 * free, 2 * free);
  normalMatrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normalMatrix);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::VectorXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  chart.corners.clear();
  chart.cornerStart.assign(1, 0);
  for (std::uint32_t f : chart.faces) {
    for (std::uint32_t v : g.faces[f]) {
      const std::size_t k = static_cast<std::size_t>(index[v]);
      chart.corners.push_back(column[k] >= 0 ? P2{x[column[k]], x[free + column[k]]} : pinOf(k));
    }
    chart.cornerStart.push_back(static_cast<std::uint32_t>(chart.corners.size()));
  }
  return true;
}

double signedFanArea(const P2* c, std::size_t count) {
  double a = 0;
  for (std::size_t k = 1; k + 1 < count; ++k) a += 0.5 * cross2(c[k] - c[0], c[k + 1] - c[0]);
  return a;
}

// Scales a conformal chart to its faces' area, mirrors it if it came out clockwise, and says
// whether it is usable: no fan triangle flipped, area stretch within kMaxAreaStretch.
bool acceptConformal(const SurfaceGeometry& g, Chart& chart) {
  double uvArea = 0;
  for (std::size_t k = 0; k < chart.faces.size(); ++k)
    uvArea += signedFanArea(&chart.corners[chart.cornerStart[k]], chart.cornerStart[k + 1] - chart.cornerStart[k]);
  if (!(std::fabs(uvArea) > 0)) return false;
  if (uvArea < 0)
    for (P2& c : chart.corners) c.x = -c.x;
  const double scale = std::sqrt(chart.area / std::fabs(uvArea));
  for (P2& c : chart.corners) c.x *= scale, c.y *= scale;
  double lo = INFINITY, hi = 0;
  for (std::size_t k = 0; k < chart.faces.size(); ++k) {
    const auto& face = g.faces[chart.faces[k]];
    const P2* c = &chart.corners[chart.cornerStart[k]];
    for (std::size_t j = 1; j + 1 < face.size(); ++j) {
      const double a3 = 0.5 * length(cross(g.surface->vertices[face[j]] - g.surface->vertices[face[0]],
                                            g.surface->vertices[face[j + 1]] - g.surface->vertices[face[0]]));
      if (!(a3 > 1e-12 * chart.area)) continue;
      const double a2 = 0.5 * cross2(c[j] - c[0], c[j + 1] - c[0]);
      if (!(a2 > 0)) return false;  // flipped (or collapsed)
      lo = std::min(lo, a2 / a3), hi = std::max(hi, a2 / a3);
    }
  }
  return hi <= kMaxAreaStretch * lo;
}

bool chartOverlapsItself(const Chart& chart) {
  if (chart.faces.size() < 2) return false;
  std::size_t triangles = 0;
  for (std::size_t k = 0; k < chart.faces.size(); ++k) triangles += chart.cornerStart[k + 1] - chart.cornerStart[k] - 2;
  P2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (const P2& c : chart.corners) lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)}, hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  OverlapGrid grid(lo, hi, triangles, 1e-9 * extent);
  for (std::size_t k = 0; k < chart.faces.size(); ++k) {
    const P2* c = &chart.corners[chart.cornerStart[k]];
    for (std::uint32_t j = 1; j + 1 < chart.cornerStart[k + 1] - chart.cornerStart[k]; ++j) {
      const P2 t[3] = {c[0], c[j], c[j + 1]};
      if (grid.overlapping(t) >= 0) return true;
      grid.insert(t, static_cast<long>(k));
    }
  }
  return false;
}

// Turns the chart to its minimum-area bounding rectangle, wider than tall, at the origin.
void fitRectangle(Chart& chart) {
  std::vector<P2> pts = chart.corners;
  std::sort(pts.begin(), pts.end(), [](P2 a, P2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<P2> hull(2 * pts.size());
  std::size_t h = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {  // Andrew's monotone chain
    while (h >= 2 && cross2(hull[h - 1] - hull[h - 2], pts[i] - hull[h - 2]) <= 0) --h;
    hull[h++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = h + 1; i-- > 0;) {
    while (h >= lower && cross2(hull[h - 1] - hull[h - 2], pts[i] - hull[h - 2]) <= 0) --h;
    hull[h++] = pts[i];
  }
  hull.resize(h > 1 ? h - 1 : h);
  double bestArea = INFINITY, bestC = 1, bestS = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const P2 d = hull[(i + 1) % hull.size()] - hull[i];
    const double len = std::hypot(d.x, d.y);
    if (!(len > 0)) continue;
    const double c = d.x / len, s = d.y / len;
    double xl = INFINITY, xh = -INFINITY, yl = INFINITY, yh = -INFINITY;
    for (const P2& p : hull) {
      const double x = c * p.x + s * p.y, y = -s * p.x + c * p.y;
      xl = std::min(xl, x), xh = std::max(xh, x), yl = std::min(yl, y), yh = std::max(yh, y);
    }
    if ((xh - xl) * (yh - yl) < bestArea * (1 - 1e-12)) bestArea = (xh - xl) * (yh - yl), bestC = c, bestS = s;
  }
  for (P2& p : chart.corners) p = {bestC * p.x + bestS * p.y, -bestS * p.x + bestC * p.y};
  P2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (const P2& c : chart.corners) lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)}, hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  for (P2& p : chart.corners) p = p - lo;
  chart.width = hi.x - lo.x, chart.height = hi.y - lo.y;
  if (chart.height > chart.width) {  // a quarter turn (a rotation: orientation kept)
    for (P2& p : chart.corners) p = {p.y, chart.width - p.x};
    std::swap(chart.width, chart.height);
  }
}

// Splits a chart's faces in two connected halves: a breadth-first race over shared edges from
// the face farthest from the first and the face farthest from that.
std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>> splitFaces(const SurfaceGeometry& g, const std::vector<std::uint32_t>& faces,
                                                                            std::vector<int>& mark) {
  auto farthest = [&](std::uint32_t from) {
    std::uint32_t best = faces[0];
    double bestD = -1;
    for (std::uint32_t f : faces)
      if (double d = length(g.centroid[f] - g.centroid[from]); d > bestD) bestD = d, best = f;
    return best;
  };
  const std::uint32_t a = farthest(faces[0]), b = farthest(a);
  for (std::uint32_t f : faces) mark[f] = -2;  // in this chart, not yet reached
  std::queue<std::uint32_t> queue;
  mark[a] = 0, queue.push(a);
  if (b != a) mark[b] = 1, queue.push(b);
  while (!queue.empty()) {
    const std::uint32_t f = queue.front();
    queue.pop();
    for (std::uint32_t k = g.start[f]; k < g.start[f + 1]; ++k)
      if (const std::uint32_t n = g.neighbours[k].first; mark[n] == -2) mark[n] = mark[f], queue.push(n);
  }
  std::pair<std::vector<std::uint32_t>, std::vector<std::uint32_t>> halves;
  for (std::uint32_t f : faces) {
    // Unreached faces (a chart joined only through a vertex) go with the smaller half.
    if (mark[f] == -2) mark[f] = halves.first.size() <= halves.second.size() ? 0 : 1;
    (mark[f] == 0 ? halves.first : halves.second).push_back(f);
  }
  for (std::uint32_t f : faces) mark[f] = -1;
  if (halves.second.empty()) {  // one face reached everything: cut the list instead
    halves.second.assign(halves.first.begin() + static_cast<std::ptrdiff_t>(halves.first.size() / 2), halves.first.end());
    halves.first.resize(halves.first.size() / 2);
  }
  return halves;
}

struct ChartStats {
  std::size_t planar = 0, conformal = 0, splits = 0;
};

// Flattens one group of faces into one or more charts (split where a map fails), appended to `out`.
void flatten(const SurfaceGeometry& g, std::uint32_t surface, std::vector<std::uint32_t> faces, bool planar, const Vec3& planeNormal,
             std::vector<Chart>& out, std::vector<int>& mark, ChartStats& stats) {
  std::vector<std::pair<std::vector<std::uint32_t>, bool>> work{{std::move(faces), planar}};
  while (!work.empty()) {
    auto [group, isPlanar] = std::move(work.back());
    work.pop_back();
    Chart chart;
    chart.surface = surface;
    chart.faces = std::move(group);
    for (std::uint32_t f : chart.faces) chart.area += g.area[f];
    bool ok;
    if (chart.faces.size() == 1) {
      projectOntoPlane(g, chart, g.normal[chart.faces[0]]);
      ok = true;
    } else if (isPlanar) {
      projectOntoPlane(g, chart, planeNormal);
      ok = !chartOverlapsItself(chart);
    } else {
      chart.conformal = true;
      ok = conformalMap(g, chart) && acceptConformal(g, chart) && !chartOverlapsItself(chart);
    }
    if (!ok) {
      ++stats.splits;
      auto [a, b] = splitFaces(g, chart.faces, mark);
      work.emplace_back(std::move(b), isPlanar);
      work.emplace_back(std::move(a), isPlanar);
      continue;
    }
    if (chart.conformal && chart.faces.size() > 1) ++stats.conformal; else ++stats.planar;
    fitRectangle(chart);
    out.push_back(std::move(chart));
  }
}

void surfaceCharts(const Scene& scene, std::uint32_t surface, std::vector<Chart>& out, ChartStats& stats) {
  const SurfaceGeometry g(scene.surfaces[surface]);
  const std::size_t n = g.faces.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return g.area[a] > g.area[b]; });
  // 1. Planar groups.
  const double cosPlanar = std::cos(kPlanarDegrees * kPi / 180);
  std::vector<int> group(n, -1);
  std::vector<std::vector<std::uint32_t>> groups;
  std::vector<Vec3> groupNormal;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed : order) {
    if (group[seed] >= 0) continue;
    const int id = static_cast<int>(groups.size());
    groups.emplace_back();
    const Vec3 normal = g.normal[seed];
    Vec3 weighted;
    group[seed] = id, stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      groups.back().push_back(f);
      weighted += g.normal[f] * g.area[f];
      for (std::uint32_t k = g.start[f]; k < g.start[f + 1]; ++k)
        if (const std::uint32_t m = g.neighbours[k].first; group[m] < 0 && dot(g.normal[m], normal) >= cosPlanar) group[m] = id, stack.push_back(m);
    }
    std::sort(groups.back().begin(), groups.back().end());
    groupNormal.push_back(length(weighted) > 0 ? normalize(weighted) : normal);
  }
  // 2. Flat groups: at most half of the outline along other faces of the surface.
  std::vector<bool> curved(n, false);
  for (std::size_t id = 0; id < groups.size(); ++id) {
    double outline = 0, shared = 0;
    for (std::uint32_t f : groups[id]) {
      double inner = 0;
      for (std::uint32_t k = g.start[f]; k < g.start[f + 1]; ++k) {
        if (group[g.neighbours[k].first] == static_cast<int>(id)) inner += g.neighbours[k].second;
        else shared += g.neighbours[k].second;
      }
      outline += g.perimeter[f] - inner;
    }
    if (shared > 0.5 * outline)
      for (std::uint32_t f : groups[id]) curved[f] = true;
  }
  std::vector<int> mark(n, -1);
  for (std::size_t id = 0; id < groups.size(); ++id)
    if (!curved[groups[id][0]]) flatten(g, surface, groups[id], true, groupNormal[id], out, mark, stats);
  // 3. Curved faces: grown nearest-first from the largest, normals within the cone of the seed's.
  const double cosCone = std::cos(kConeDegrees * kPi / 180);
  std::vector<bool> taken(n, false);
  using Entry = std::pair<double, std::uint32_t>;
  for (std::uint32_t seed : order) {
    if (!curved[seed] || taken[seed]) continue;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> frontier;
    std::vector<std::uint32_t> faces;
    taken[seed] = true, frontier.push({0, seed});
    while (!frontier.empty()) {
      const std::uint32_t f = frontier.top().second;
      frontier.pop();
      faces.push_back(f);
      for (std::uint32_t k = g.start[f]; k < g.start[f + 1]; ++k) {
        const std::uint32_t m = g.neighbours[k].first;
        if (!curved[m] || taken[m] || dot(g.normal[m], g.normal[seed]) < cosCone) continue;
        taken[m] = true;
        frontier.push({length(g.centroid[m] - g.centroid[seed]), m});
      }
    }
    std::sort(faces.begin(), faces.end());
    flatten(g, surface, std::move(faces), false, g.normal[seed], out, mark, stats);
  }
}

std::vector<Chart> buildCharts(const Scene& scene, ChartStats& stats) {
  std::vector<Chart> charts;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) surfaceCharts(scene, s, charts, stats);
  return charts;
}

// ---------------------------------------------------------------------------------------------
// Packing.

// The skyline of one atlas: segments (x, y, width) left to right, y the top of what is placed
// below them (y grows down the atlas).
class Skyline {
 public:
  explicit Skyline(int size) : size_(size) { segments_.push_back({0, 0, size}); }

  // The lowest, then leftmost, place for a w × h rectangle in either orientation.
  bool place(int w, int h, int& x, int& y, bool& rotated) {
    int bestTop = INT32_MAX, bestX = 0, bestY = 0;
    std::size_t bestIndex = 0;
    bool bestRotated = false;
    for (int turn = 0; turn < (w == h ? 1 : 2); ++turn) {
      const int rw = turn ? h : w, rh = turn ? w : h;
      for (std::size_t i = 0; i < segments_.size(); ++i) {
        int top;
        if (!fits(i, rw, rh, top)) continue;
        if (top + rh < bestTop || (top + rh == bestTop && segments_[i].x < bestX)) {
          bestTop = top + rh, bestX = segments_[i].x, bestY = top, bestIndex = i, bestRotated = turn;
        }
      }
    }
    if (bestTop == INT32_MAX) return false;
    x = bestX, y = bestY, rotated = bestRotated;
    add(bestIndex, bestRotated ? h : w, bestY + (bestRotated ? w : h));
    return true;
  }

 private:
  struct Segment {
    int x, y, width;
  };
  bool fits(std::size_t i, int w, int h, int& top) const {
    if (segments_[i].x + w > size_) return false;
    int left = w;
    top = 0;
    for (std::size_t j = i; left > 0; ++j) {
      top = std::max(top, segments_[j].y);
      if (top + h > size_) return false;
      left -= segments_[j].width;
    }
    return true;
  }
  void add(std::size_t i, int w, int top) {
    const int x = segments_[i].x;
    segments_.insert(segments_.begin() + static_cast<std::ptrdiff_t>(i), {x, top, w});
    for (std::size_t j = i + 1; j < segments_.size();) {
      Segment& s = segments_[j];
      if (s.x >= x + w) break;
      const int cut = x + w - s.x;
      if (cut >= s.width) {
        segments_.erase(segments_.begin() + static_cast<std::ptrdiff_t>(j));
        continue;
      }
      s.x += cut, s.width -= cut;
      break;
    }
    for (std::size_t j = 0; j + 1 < segments_.size();) {
      if (segments_[j].y == segments_[j + 1].y) {
        segments_[j].width += segments_[j + 1].width;
        segments_.erase(segments_.begin() + static_cast<std::ptrdiff_t>(j + 1));
      } else {
        ++j;
      }
    }
  }
  int size_;
  std::vector<Segment> segments_;
};

struct Placement {
  std::uint32_t atlas = 0;
  int x = 0, y = 0;  // the rectangle's corner (its padding starts here)
  bool rotated = false;
  double scale = 1;  // below 1 for a chart scaled down to fit an atlas
};

// A chart's footprint in whole texels at a texel size: at least one.
int footprint(double extent, double texelSize) {
  const double texels = extent / texelSize;
  return std::max(1, static_cast<int>(std::ceil(texels - 1e-9)));
}

// Packs every chart at `texelSize` into atlases of `size` texels (at most maxAtlases); the
// placements, or false where they do not fit.
// The orders rectangles are placed in (largest first, by one measure each): the packing that
// fits at the smallest texel size is kept.
enum class PackOrder { ShortSide, Area, LongSide };
constexpr PackOrder kPackOrders[] = {PackOrder::ShortSide, PackOrder::Area, PackOrder::LongSide};

bool pack(const std::vector<Chart>& charts, double texelSize, int size, int padding, std::size_t maxAtlases,
          std::vector<Placement>& placements, std::size_t& numAtlases, PackOrder order = PackOrder::ShortSide, bool scaleDown = true) {
  const int usable = size - padding % 2;  // the high sides keep ⌈padding / 2⌉ as the low ones
  if (usable - padding < 1) return false;
  struct Rect {
    int w, h;
    std::uint32_t chart;
  };
  std::vector<Rect> rects(charts.size());
  placements.assign(charts.size(), {});
  for (std::uint32_t c = 0; c < charts.size(); ++c) {
    double scale = 1;
    // A chart wider than an atlas is scaled down to fit (warned about by the caller).
    if (charts[c].width / texelSize > usable - padding) {
      if (!scaleDown) return false;
      scale = (usable - padding) / (charts[c].width / texelSize) * (1 - 1e-9);
    }
    placements[c].scale = scale;
    rects[c] = {footprint(charts[c].width * scale, texelSize) + padding, footprint(charts[c].height * scale, texelSize) + padding, c};
  }
  auto key = [order](const Rect& r) {
    const std::int64_t lo = std::min(r.w, r.h), hi = std::max(r.w, r.h);
    return order == PackOrder::ShortSide ? std::pair{lo, hi} : order == PackOrder::Area ? std::pair{lo * hi, hi} : std::pair{hi, lo};
  };
  std::stable_sort(rects.begin(), rects.end(), [&](const Rect& a, const Rect& b) { return key(a) > key(b); });
  std::vector<Skyline> atlases;
  for (const Rect& r : rects) {
    Placement& p = placements[r.chart];
    bool placed = false;
    // First fit over the last few atlases opened (the earlier ones are full but for slivers).
    for (std::size_t a = atlases.size() > 4 ? atlases.size() - 4 : 0; a < atlases.size() && !placed; ++a)
      if (atlases[a].place(r.w, r.h, p.x, p.y, p.rotated)) p.atlas = static_cast<std::uint32_t>(a), placed = true;
    if (placed) continue;
    if (atlases.size() >= maxAtlases) return false;
    atlases.emplace_back(usable);
    if (!atlases.back().place(r.w, r.h, p.x, p.y, p.rotated)) return false;
    p.atlas = static_cast<std::uint32_t>(atlases.size() - 1);
  }
  numAtlases = std::max<std::size_t>(atlases.size(), 1);
  return true;
}

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
        const P2 t[3] = {{c[0].u * uvs.size, c[0].v * uvs.size}, {c[k].u * uvs.size, c[k].v * uvs.size}, {c[k + 1].u * uvs.size, c[k + 1].v * uvs.size}};
        const double area = cross2(t[1] - t[0], t[2] - t[0]);
        if (area == 0) continue;
        const double sign = area > 0 ? 1 : -1;
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].x, t[1].x, t[2].x}) - 0.5)));
        const int x1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0].x, t[1].x, t[2].x}) - 0.5)));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({t[0].y, t[1].y, t[2].y}) - 0.5)));
        const int y1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0].y, t[1].y, t[2].y}) - 0.5)));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const P2 q{x + 0.5, y + 0.5};
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

// The smallest texel size at which the charts fit one atlas of `size` in one of the packing
// orders (bisection on its logarithm, to 0.2%), and that order; 0 when they fit none (too many
// charts for one atlas at any size).
double fittingTexelSize(const std::vector<Chart>& charts, double area, int size, int padding, PackOrder* fittingOrder = nullptr) {
  std::vector<Placement> placements;
  std::size_t numAtlases = 0;
  PackOrder found = PackOrder::ShortSide;
  auto fits = [&](double t) {
    for (PackOrder order : kPackOrders)
      if (pack(charts, t, size, padding, 1, placements, numAtlases, order, false)) {
        found = order;
        return true;
      }
    return false;
  };
  double lo = std::sqrt(area / (static_cast<double>(size) * size));  // all texels covered: no smaller
  double hi = lo * 1.25;
  for (int k = 0; !fits(hi); ++k) {
    if (k == 40) return 0;
    lo = hi, hi *= 2;
  }
  PackOrder atHi = found;
  while (hi > lo * 1.002) {
    const double mid = std::sqrt(lo * hi);
    if (fits(mid)) hi = mid, atHi = found;
    else lo = mid;
  }
  if (fittingOrder) *fittingOrder = atHi;
  return hi;
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
  std::vector<P2> tris;
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
        tris.insert(tris.end(), {P2{c[0].u, c[0].v}, P2{c[k].u, c[k].v}, P2{c[k + 1].u, c[k + 1].v}});
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
        atlases.emplace_back(P2{0, 0}, P2{1, 1}, triangles, tolerance);
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
  // atlasSize), or atlasSize where none is asked for.
  const double texelsPerUnit = std::sqrt(area2 / area3);  // atlas widths per scene unit
  out.size = options.atlasSize;
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
        const P2 q = chart.corners[j];
        const P2 t = p.rotated ? P2{q.y * k, w - q.x * k} : P2{q.x * k, q.y * k};
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
