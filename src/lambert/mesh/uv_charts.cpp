#include "lambert/mesh/uv_charts.h"

// Per surface (a smooth region: faces of different surfaces never share a chart), faces are
// grown into planar charts from the largest face outwards, over edges shared by two faces,
// taking every face whose normal is within kPlanarDegrees of the seed's. A planar chart is kept
// when at most half of its outline runs along other faces of its surface (a wall, a floor, the
// flat side of a block); the others are strips of a curved region (a cylinder's facets, a
// sphere's). The faces of those are grown again into charts whose normals stay within
// kConeDegrees of their seed's (a disc-like piece, never a closed tube or sphere), nearest the
// seed first so that charts come out round, and each is flattened by the least-squares conformal
// map (mesh/lscm.h). A chart whose map flips a triangle, stretches area by more than
// kMaxAreaStretch between its triangles, or overlaps itself is split in two (a breadth-first
// race from its two farthest faces) and each half flattened again; a single face is projected
// onto its own plane. Every chart is turned to its minimum-area bounding rectangle (rotating
// calipers over its convex hull: Freeman & Shapira 1975) and scaled to scene units: planar
// charts exactly, conformal ones so that their area is their faces' area.
//
// Cost: linear in faces (plus the conformal maps' sparse solves, about linear in the curved
// faces).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "lambert/mesh/lscm.h"
#include "lambert/mesh/uv_overlap_grid.h"

namespace lambert {
namespace {

constexpr double kPlanarDegrees = 2;     // a planar chart's faces lie within this of its seed's plane
constexpr double kConeDegrees = 50;      // a conformal chart's normals stay within this of its seed's
constexpr double kMaxAreaStretch = 4;    // a conformal chart's largest / smallest triangle area ratio

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

double signedFanArea(const Vec2* c, std::size_t count) {
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
    for (Vec2& c : chart.corners) c.x = -c.x;
  const double scale = std::sqrt(chart.area / std::fabs(uvArea));
  for (Vec2& c : chart.corners) c.x *= scale, c.y *= scale;
  double lo = INFINITY, hi = 0;
  for (std::size_t k = 0; k < chart.faces.size(); ++k) {
    const auto& face = g.faces[chart.faces[k]];
    const Vec2* c = &chart.corners[chart.cornerStart[k]];
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
  Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (const Vec2& c : chart.corners) lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)}, hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  OverlapGrid grid(lo, hi, triangles, 1e-9 * extent);
  for (std::size_t k = 0; k < chart.faces.size(); ++k) {
    const Vec2* c = &chart.corners[chart.cornerStart[k]];
    for (std::uint32_t j = 1; j + 1 < chart.cornerStart[k + 1] - chart.cornerStart[k]; ++j) {
      const Vec2 t[3] = {c[0], c[j], c[j + 1]};
      if (grid.overlapping(t) >= 0) return true;
      grid.insert(t, static_cast<long>(k));
    }
  }
  return false;
}

// Turns the chart to its minimum-area bounding rectangle, wider than tall, at the origin.
void fitRectangle(Chart& chart) {
  std::vector<Vec2> pts = chart.corners;
  std::sort(pts.begin(), pts.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<Vec2> hull(2 * pts.size());
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
    const Vec2 d = hull[(i + 1) % hull.size()] - hull[i];
    const double len = std::hypot(d.x, d.y);
    if (!(len > 0)) continue;
    const double c = d.x / len, s = d.y / len;
    double xl = INFINITY, xh = -INFINITY, yl = INFINITY, yh = -INFINITY;
    for (const Vec2& p : hull) {
      const double x = c * p.x + s * p.y, y = -s * p.x + c * p.y;
      xl = std::min(xl, x), xh = std::max(xh, x), yl = std::min(yl, y), yh = std::max(yh, y);
    }
    if ((xh - xl) * (yh - yl) < bestArea * (1 - 1e-12)) bestArea = (xh - xl) * (yh - yl), bestC = c, bestS = s;
  }
  for (Vec2& p : chart.corners) p = {bestC * p.x + bestS * p.y, -bestS * p.x + bestC * p.y};
  Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (const Vec2& c : chart.corners) lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)}, hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  for (Vec2& p : chart.corners) p = p - lo;
  chart.width = hi.x - lo.x, chart.height = hi.y - lo.y;
  if (chart.height > chart.width) {  // a quarter turn (a rotation: orientation kept)
    for (Vec2& p : chart.corners) p = {p.y, chart.width - p.x};
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

}  // namespace

SurfaceGeometry::SurfaceGeometry(const Surface& s) : surface(&s), faces(surfaceFaces(s)) {
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

double SurfaceGeometry::sharedEdgeLength(std::uint32_t f, std::uint32_t g) const {
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

std::vector<Chart> buildCharts(const Scene& scene, ChartStats& stats) {
  std::vector<Chart> charts;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) surfaceCharts(scene, s, charts, stats);
  return charts;
}

}  // namespace lambert
