#include "lambert/hierarchical/element_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "lambert/core/error.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {
namespace {

// Area, unit normal and area centroid of a planar polygon of three or four corners.
void setElementGeometry(HierarchyNode& node) {
  const Vec3& origin = node.corners[0];
  Vec3 normalSum, weighted;
  double area = 0;
  for (std::size_t k = 1; k + 1 < node.numCorners; ++k) {
    Vec3 n = cross(node.corners[k] - origin, node.corners[k + 1] - origin);
    double a = 0.5 * length(n);
    normalSum += n;
    area += a;
    weighted += (origin + node.corners[k] + node.corners[k + 1]) * (a / 3.0);
  }
  node.area = area;
  node.normal = length(normalSum) > 0 ? normalize(normalSum) : Vec3{0, 0, 1};
  node.centre = area > 0 ? weighted / area : origin;
  node.radius = 0;
  for (std::size_t k = 0; k < node.numCorners; ++k) node.radius = std::fmax(node.radius, length(node.corners[k] - node.centre));
}

// A quad is kept whole only if it is planar and convex (every corner turns the same way about
// its normal). A twisted quad is fanned into triangles: its children, made at edge midpoints,
// would leave the two triangles the ray caster holds, and points sampled on them would lie
// behind the surface they stand for.
bool planarConvexQuad(const std::array<Vec3, 4>& q) {
  Vec3 n = cross(q[2] - q[0], q[3] - q[1]);
  const double size = std::fmax(length(q[2] - q[0]), length(q[3] - q[1]));
  if (!(length(n) > 0) || std::fabs(dot(q[3] - q[0], normalize(n))) > 1e-7 * size ||
      std::fabs(dot(q[1] - q[0], normalize(n))) > 1e-7 * size)
    return false;
  for (int k = 0; k < 4; ++k)
    if (dot(cross(q[(k + 1) % 4] - q[k], q[(k + 2) % 4] - q[(k + 1) % 4]), n) <= 0) return false;
  return true;
}

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

// A halved sliver's two children (elementSplit) from its corners v, in the order and orientation
// split() makes them; `midpoint(a, b)` makes the point (or vertex) half way along an edge. One
// place for both the hierarchy's corners and the leaf mesh's vertices, which must agree.
template <class Corner, class Midpoint>
std::array<std::array<Corner, 4>, 2> halvedSliver(const std::array<Corner, 4>& v, std::size_t numCorners, int edge,
                                                  Midpoint midpoint) {
  const auto at = [&](int k) { return v[static_cast<std::size_t>(k) % numCorners]; };
  const Corner a = at(edge), b = at(edge + 1), c = at(edge + 2);
  const Corner m = midpoint(a, b);
  if (numCorners == 3) return {{{a, m, c, Corner{}}, {m, b, c, Corner{}}}};
  const Corner d = at(edge + 3), o = midpoint(c, d);
  return {{{a, m, o, d}, {m, b, c, o}}};
}

}  // namespace

struct ElementHierarchy::FaceRoot {
  HierarchyNode element;
  std::array<std::uint32_t, 4> vertices;
};

// What the clusters are built from, apart from the faces themselves (208 bytes each, read at
// random once nth_element has moved these): the median split's order (the same comparisons give
// the same order), and what a cluster's bounds sum and bound, face by face in the same order.
struct ElementHierarchy::FaceKey {
  Vec3 centre;
  Vec3 lo, hi;  // the box about the face's corners
  Vec3 normal;
  double area;
  std::uint32_t firstVertex;
  std::uint32_t face;   // into the constructor's faces
  std::uint32_t group;  // the constructor's faceGroups (0 without)
};

// The oriented box of a cluster's faces (ClusterBounds): along their area-weighted mean normal,
// each face's normal counted on the first one's side (a two-sided surface's twins would cancel),
// and the two tangents slabFrame() makes from it; the centre and the half extents rounded so
// that the box, as stored, holds every corner.
void ElementHierarchy::setSlab(const std::vector<FaceRoot>& all, std::span<const FaceKey> faces, ClusterBounds& bounds) {
  Vec3 sum{};
  for (const FaceKey& f : faces) sum += f.normal * (f.area * (dot(f.normal, faces[0].normal) < 0 ? -1.0 : 1.0));
  const double l = length(sum);
  if (!(l > 0)) return;  // slabAxis stays zero: the axis-aligned box alone
  const Vec3 unit = sum / l;
  bounds.slabAxis = {static_cast<float>(unit.x), static_cast<float>(unit.y), static_cast<float>(unit.z)};
  const SlabFrame frame = slabFrame(bounds);
  const std::array<Vec3, 3> axes = {frame.axis, frame.tangent, frame.bitangent};
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const FaceKey& f : faces) {
    const HierarchyNode& e = all[f.face].element;
    for (std::size_t k = 0; k < e.numCorners; ++k)
      for (int a = 0; a < 3; ++a) {
        const double h = dot(axes[a], e.corners[k]);
        lo[a] = std::fmin(lo[a], h);
        hi[a] = std::fmax(hi[a], h);
      }
  }
  const Vec3 centre = axes[0] * (0.5 * (lo[0] + hi[0])) + axes[1] * (0.5 * (lo[1] + hi[1])) + axes[2] * (0.5 * (lo[2] + hi[2]));
  bounds.slabCentre = {static_cast<float>(centre.x), static_cast<float>(centre.y), static_cast<float>(centre.z)};
  const Vec3 stored{bounds.slabCentre[0], bounds.slabCentre[1], bounds.slabCentre[2]};
  for (int a = 0; a < 3; ++a) {
    const double c = dot(axes[a], stored), half = std::fmax(hi[a] - c, c - lo[a]);
    float h = static_cast<float>(half);
    if (static_cast<double>(h) < half) h = std::nextafter(h, INFINITY);  // the box must hold the faces
    bounds.slabHalfExtent[a] = h;
  }
}

std::uint32_t ElementHierarchy::addNode(const HierarchyNode& node) {
  LAMBERT_CHECK(nodes_.size() < kNoNode);
  nodes_.push_back(node);
  return static_cast<std::uint32_t>(nodes_.size() - 1);
}

ElementHierarchy::ElementHierarchy(const Scene& scene, const std::vector<std::vector<std::uint32_t>>& faceGroups) {
  std::vector<FaceRoot> faces;
  std::size_t numPolygons = 0;
  for (const Surface& surface : scene.surfaces) numPolygons += std::max<std::size_t>(1, surface.faces.size());
  faces.reserve(numPolygons);  // quads and triangles, mostly: one root each
  std::uint32_t vertexBase = 0;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    // The surface's faces, read in place (surfaceFaces would copy them), or its one polygon.
    const std::vector<std::vector<std::uint32_t>> whole =
        surface.faces.empty() ? surfaceFaces(surface) : std::vector<std::vector<std::uint32_t>>{};
    const std::vector<std::vector<std::uint32_t>>& polygons = surface.faces.empty() ? whole : surface.faces;
    for (std::uint32_t f = 0; f < polygons.size(); ++f) {
      const std::vector<std::uint32_t>& face = polygons[f];
      LAMBERT_CHECK(face.size() >= 3);
      FaceRoot root;
      root.element.surface = s;
      root.element.face = f;
      root.element.twinned = surface.twin >= 0;
      auto emit = [&](std::initializer_list<std::uint32_t> corners) {
        root.element.numCorners = static_cast<std::uint8_t>(corners.size());
        std::size_t k = 0;
        for (std::uint32_t c : corners) {
          root.element.corners[k] = surface.vertices[c];
          root.vertices[k++] = vertexBase + c;
        }
        setElementGeometry(root.element);
        if (root.element.area > 0) faces.push_back(root);
      };
      if (face.size() == 4 &&
          planarConvexQuad({surface.vertices[face[0]], surface.vertices[face[1]], surface.vertices[face[2]], surface.vertices[face[3]]}))
        emit({face[0], face[1], face[2], face[3]});
      else
        for (std::size_t i = 1; i + 1 < face.size(); ++i) emit({face[0], face[i], face[i + 1]});
    }
    vertexBase += static_cast<std::uint32_t>(surface.vertices.size());
  }
  LAMBERT_CHECK(!faces.empty());
  numFaces_ = faces.size();
  nodes_.reserve(faces.size() * 2);
  HierarchyNode root;  // a cluster: no corners
  addNode(root);
  childList_.push_back(0);  // slot 0 holds nothing: the root is nobody's child
  std::vector<FaceKey> keys(faces.size());
  for (std::uint32_t i = 0; i < faces.size(); ++i) {
    const HierarchyNode& e = faces[i].element;
    Vec3 lo = e.corners[0], hi = e.corners[0];
    for (std::size_t k = 1; k < e.numCorners; ++k) {
      lo = componentMin(lo, e.corners[k]);
      hi = componentMax(hi, e.corners[k]);
    }
    const std::uint32_t group = faceGroups.empty() ? 0 : faceGroups.at(e.surface).at(e.face);
    keys[i] = {e.centre, lo, hi, e.normal, e.area, faces[i].vertices[0], i, group};
  }
  buildClusters(faces, keys, kNoNode, 0, 0);
  numberLeaves();
}

// Makes the cluster over `faces` (or, for one face, its root element) and records it in
// childList_[slot] as a child of `parent`; node 0 is the root cluster, made by the constructor.
void ElementHierarchy::buildClusters(const std::vector<FaceRoot>& all, std::span<FaceKey> faces, std::uint32_t parent,
                                     std::uint32_t slot, std::uint8_t depth) {
  if (faces.size() == 1 && parent != kNoNode) {
    const FaceRoot& face = all[faces[0].face];
    HierarchyNode element = face.element;
    element.parent = parent;
    element.depth = 0;
    std::uint32_t index = addNode(element);
    childList_[slot] = index;
    roots_.push_back({index, face.vertices});
    return;
  }
  std::uint32_t cluster = parent == kNoNode ? 0 : addNode(HierarchyNode{});
  if (parent != kNoNode) childList_[slot] = cluster;
  ++numClusters_;
  {
    HierarchyNode& c = nodes_[cluster];
    c.parent = parent;
    c.depth = depth;
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    double area = 0;
    std::array<double, 6> axisArea{};
    // min and max are exact in any order (the corners are finite: comparisons, not fmin's calls);
    // the sums run over the faces in this span's order.
    for (const FaceKey& f : faces) {
      area += f.area;
      const double components[3] = {f.normal.x, f.normal.y, f.normal.z};
      for (int a = 0; a < 3; ++a) axisArea[axisSide(a, components[a])] += f.area * std::fabs(components[a]);
      lo = {f.lo.x < lo.x ? f.lo.x : lo.x, f.lo.y < lo.y ? f.lo.y : lo.y, f.lo.z < lo.z ? f.lo.z : lo.z};
      hi = {f.hi.x > hi.x ? f.hi.x : hi.x, f.hi.y > hi.y ? f.hi.y : hi.y, f.hi.z > hi.z ? f.hi.z : hi.z};
    }
    c.area = area;
    ClusterBounds bounds{};
    for (int k = 0; k < 6; ++k) bounds.axisArea[k] = static_cast<float>(axisArea[k]);
    c.centre = (lo + hi) * 0.5;
    c.radius = 0.5 * length(hi - lo);
    const Vec3 half = (hi - lo) * 0.5;
    const double halves[3] = {half.x, half.y, half.z};
    for (int a = 0; a < 3; ++a) {
      float h = static_cast<float>(halves[a]);
      if (static_cast<double>(h) < halves[a]) h = std::nextafter(h, INFINITY);  // the box must hold the faces
      bounds.halfExtent[a] = h;
    }
    setSlab(all, faces, bounds);
    c.bounds = bounds;
  }
  // Faces of two groups: two parts by group (the groups in order, cut at the group boundary
  // nearest the middle). Else at most four faces: they are the cluster's children. Otherwise two
  // halves by the median centroid along the longest axis of the centroids' bounds.
  std::vector<std::span<FaceKey>> parts;
  const bool mixed = std::any_of(faces.begin(), faces.end(), [&](const FaceKey& f) { return f.group != faces[0].group; });
  if (mixed) {
    std::sort(faces.begin(), faces.end(), [](const FaceKey& a, const FaceKey& b) { return a.group != b.group ? a.group < b.group : a.face < b.face; });
    std::size_t cut = 0, best = faces.size();
    for (std::size_t i = 1; i < faces.size(); ++i) {
      if (faces[i].group == faces[i - 1].group) continue;
      const std::size_t off = i > faces.size() / 2 ? i - faces.size() / 2 : faces.size() / 2 - i;
      if (off < best) best = off, cut = i;
    }
    parts = {faces.first(cut), faces.subspan(cut)};
  } else if (faces.size() <= 4) {
    for (std::size_t i = 0; i < faces.size(); ++i) parts.push_back(faces.subspan(i, 1));
  } else {
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (const FaceKey& f : faces) {
      lo = {f.centre.x < lo.x ? f.centre.x : lo.x, f.centre.y < lo.y ? f.centre.y : lo.y, f.centre.z < lo.z ? f.centre.z : lo.z};
      hi = {f.centre.x > hi.x ? f.centre.x : hi.x, f.centre.y > hi.y ? f.centre.y : hi.y, f.centre.z > hi.z ? f.centre.z : hi.z};
    }
    Vec3 extent = hi - lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    auto coordinate = [axis](const FaceKey& f) { return axis == 0 ? f.centre.x : axis == 1 ? f.centre.y : f.centre.z; };
    std::size_t half = faces.size() / 2;
    std::nth_element(faces.begin(), faces.begin() + static_cast<std::ptrdiff_t>(half), faces.end(),
                     [&](const FaceKey& a, const FaceKey& b) {
                       double ca = coordinate(a), cb = coordinate(b);
                       if (ca != cb) return ca < cb;
                       return a.firstVertex < b.firstVertex;  // a strict order whatever the ties
                     });
    parts = {faces.first(half), faces.subspan(half)};
  }
  const auto first = static_cast<std::uint32_t>(childList_.size());
  nodes_[cluster].firstChild = first;
  nodes_[cluster].numChildren = static_cast<std::uint32_t>(parts.size());
  childList_.resize(childList_.size() + parts.size(), kNoNode);
  for (std::size_t i = 0; i < parts.size(); ++i)
    buildClusters(all, parts[i], cluster, first + static_cast<std::uint32_t>(i), static_cast<std::uint8_t>(std::min(depth + 1, 255)));
}

ElementSplit elementSplit(const HierarchyNode& e) {
  const std::array<Vec3, 4>& p = e.corners;
  if (e.numCorners == 3) {
    int longest = 0;
    double longestSquared = 0;
    for (int k = 0; k < 3; ++k)
      if (const double l = lengthSquared(p[(k + 1) % 3] - p[k]); l > longestSquared) longestSquared = l, longest = k;
    // Height over the longest edge h = 2A / L: a sliver where L > 4h, that is L² > 8A (a right
    // isosceles triangle, half of a quad as exporters triangulate it, has L² = 4A).
    return longestSquared > 8 * e.area ? ElementSplit{2, longest} : ElementSplit{4, 0};
  }
  const double along01 = length(p[1] - p[0]) + length(p[3] - p[2]), along12 = length(p[2] - p[1]) + length(p[0] - p[3]);
  if (along01 > 2 * along12) return {2, 0};
  if (along12 > 2 * along01) return {2, 1};
  return {4, 0};
}

double extentArea(const HierarchyNode& e) {
  if (e.isCluster()) return e.area;
  double longestSquared = 0;
  for (std::size_t k = 0; k < e.numCorners; ++k)
    longestSquared = std::fmax(longestSquared, lengthSquared(e.corners[(k + 1) % e.numCorners] - e.corners[k]));
  return std::fmax(e.area, 0.25 * longestSquared);
}

void ElementHierarchy::split(std::uint32_t element) {
  LAMBERT_CHECK(!nodes_[element].isCluster() && nodes_[element].isLeaf());
  const HierarchyNode parent = nodes_[element];
  const std::array<Vec3, 4>& p = parent.corners;
  const ElementSplit how = elementSplit(parent);
  std::array<std::array<Vec3, 4>, 4> children;
  if (how.children == 2) {
    const auto halves = halvedSliver(p, parent.numCorners, how.edge, [](const Vec3& a, const Vec3& b) { return (a + b) * 0.5; });
    children[0] = halves[0];
    children[1] = halves[1];
  } else if (parent.numCorners == 3) {
    Vec3 ab = (p[0] + p[1]) * 0.5, bc = (p[1] + p[2]) * 0.5, ca = (p[2] + p[0]) * 0.5;
    children = {{{p[0], ab, ca, {}}, {ab, p[1], bc, {}}, {ca, bc, p[2], {}}, {ab, bc, ca, {}}}};
  } else {
    Vec3 m01 = (p[0] + p[1]) * 0.5, m12 = (p[1] + p[2]) * 0.5, m23 = (p[2] + p[3]) * 0.5, m30 = (p[3] + p[0]) * 0.5;
    Vec3 c = (m01 + m23) * 0.5;
    children = {{{p[0], m01, c, m30}, {m01, p[1], m12, c}, {c, m12, p[2], m23}, {m30, c, m23, p[3]}}};
  }
  const auto first = static_cast<std::uint32_t>(childList_.size());
  for (int k = 0; k < how.children; ++k) {
    const std::array<Vec3, 4>& corners = children[static_cast<std::size_t>(k)];
    HierarchyNode child;
    child.corners = corners;
    child.numCorners = parent.numCorners;
    child.depth = static_cast<std::uint8_t>(std::min(parent.depth + 1, 255));
    child.twinned = parent.twinned;
    child.enclosed = parent.enclosed;
    child.surface = parent.surface;
    child.face = parent.face;
    child.parent = element;
    setElementGeometry(child);
    child.normal = parent.normal;  // the same plane, without rounding
    childList_.push_back(addNode(child));
  }
  nodes_[element].firstChild = first;
  nodes_[element].numChildren = static_cast<std::uint32_t>(how.children);
}

void ElementHierarchy::markEnclosedFaces(std::span<const std::uint8_t> perLeaf) {
  LAMBERT_CHECK(perLeaf.size() == leafNodes_.size());
  for (std::size_t l = 0; l < perLeaf.size(); ++l) {
    LAMBERT_CHECK(nodes_[leafNodes_[l]].depth == 0 && !nodes_[leafNodes_[l]].isCluster());  // a face, not yet split
    nodes_[leafNodes_[l]].enclosed = perLeaf[l] != 0;
  }
}

std::vector<double> ElementHierarchy::unenclosedAreas() const {
  std::vector<double> area(nodes_.size(), 0.0);
  for (std::size_t i = nodes_.size(); i-- > 0;) {  // children first
    const HierarchyNode& n = nodes_[i];
    if (!n.isCluster()) area[i] = n.enclosed ? 0.0 : n.area;
    if (n.parent != kNoNode && nodes_[n.parent].isCluster()) area[n.parent] += area[i];
  }
  return area;
}

std::size_t ElementHierarchy::numberLeaves() {
  leafNodes_.clear();
  for (std::uint32_t i = 0; i < nodes_.size(); ++i) {
    HierarchyNode& n = nodes_[i];
    n.leaf = kNoNode;
    if (n.isLeaf() && !n.isCluster()) {
      n.leaf = static_cast<std::uint32_t>(leafNodes_.size());
      leafNodes_.push_back(i);
    }
  }
  return leafNodes_.size();
}

ElementHierarchy::LeafMesh ElementHierarchy::leaves(const Scene& scene) const {
  LeafMesh out;
  Mesh& mesh = out.mesh;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s)
    for (const Vec3& v : scene.surfaces[s].vertices) {
      mesh.positions.push_back(v);
      mesh.vertexSurface.push_back(s);
    }
  mesh.patches.resize(leafNodes_.size());

  std::unordered_map<std::uint64_t, std::uint32_t> midpoints;           // edge → its midpoint
  std::unordered_map<std::uint64_t, std::uint64_t> parentEdge;          // half edge → the edge it halves
  std::vector<std::pair<std::uint32_t, std::uint64_t>> madeOn;         // midpoint vertex, its edge
  auto newVertex = [&](const Vec3& p, std::uint32_t surface) {
    mesh.positions.push_back(p);
    mesh.vertexSurface.push_back(surface);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  };
  auto midpoint = [&](std::uint32_t a, std::uint32_t b, std::uint32_t surface) {
    const std::uint64_t key = edgeKey(a, b);
    auto [it, inserted] = midpoints.try_emplace(key, 0);
    if (inserted) {
      it->second = newVertex((mesh.positions[a] + mesh.positions[b]) * 0.5, surface);
      parentEdge[edgeKey(a, it->second)] = key;
      parentEdge[edgeKey(it->second, b)] = key;
      madeOn.push_back({it->second, key});
    }
    return it->second;
  };

  struct Visit {
    std::uint32_t node;
    std::array<std::uint32_t, 4> vertices;
  };
  std::vector<Visit> stack;
  for (const Root& root : roots_) {
    stack.push_back({root.node, root.vertices});
    while (!stack.empty()) {
      Visit visit = stack.back();
      stack.pop_back();
      const HierarchyNode& n = nodes_[visit.node];
      const auto& v = visit.vertices;
      if (n.isLeaf()) {
        std::span<const std::uint32_t> corners(v.data(), n.numCorners);
        Patch patch = makePatch(mesh.positions, corners, n.surface);
        patch.face = n.face;
        patch.twinned = n.twinned;
        mesh.patches[n.leaf] = patch;
        continue;
      }
      std::span<const std::uint32_t> kids = children(visit.node);
      if (kids.size() == 2) {  // a halved sliver (elementSplit): as split() made it
        const auto halves = halvedSliver(v, n.numCorners, elementSplit(n).edge,
                                         [&](std::uint32_t a, std::uint32_t b) { return midpoint(a, b, n.surface); });
        stack.push_back({kids[0], halves[0]});
        stack.push_back({kids[1], halves[1]});
      } else if (n.numCorners == 3) {
        std::uint32_t ab = midpoint(v[0], v[1], n.surface), bc = midpoint(v[1], v[2], n.surface), ca = midpoint(v[2], v[0], n.surface);
        stack.push_back({kids[0], {v[0], ab, ca, 0}});
        stack.push_back({kids[1], {ab, v[1], bc, 0}});
        stack.push_back({kids[2], {ca, bc, v[2], 0}});
        stack.push_back({kids[3], {ab, bc, ca, 0}});
      } else {
        std::uint32_t m01 = midpoint(v[0], v[1], n.surface), m12 = midpoint(v[1], v[2], n.surface);
        std::uint32_t m23 = midpoint(v[2], v[3], n.surface), m30 = midpoint(v[3], v[0], n.surface);
        std::uint32_t c = newVertex(nodes_[kids[0]].corners[2], n.surface);
        stack.push_back({kids[0], {v[0], m01, c, m30}});
        stack.push_back({kids[1], {m01, v[1], m12, c}});
        stack.push_back({kids[2], {c, m12, v[2], m23}});
        stack.push_back({kids[3], {m30, c, m23, v[3]}});
      }
    }
  }

  // A midpoint hangs when the edge it was made on, or an edge that one lies on, is a leaf's edge.
  // Only edges that were split are asked, so only those of the leaves' edges are kept (none where
  // nothing was split: a 10⁶-face scene's 4 × 10⁶ edges cost a second in a hash set).
  std::unordered_set<std::uint64_t> leafEdges;
  if (!midpoints.empty())
    for (const Patch& patch : mesh.patches)
      for (std::size_t k = 0; k < patch.numCorners; ++k) {
        const std::uint64_t edge = edgeKey(patch.vertices[k], patch.vertices[(k + 1) % patch.numCorners]);
        if (midpoints.count(edge)) leafEdges.insert(edge);
      }
  for (const auto& [vertex, edge] : madeOn) {
    bool hangs = false;
    for (std::uint64_t e = edge;;) {
      if (leafEdges.count(e)) {
        hangs = true;
        break;
      }
      auto up = parentEdge.find(e);
      if (up == parentEdge.end()) break;
      e = up->second;
    }
    if (hangs)
      out.hanging.push_back({vertex, static_cast<std::uint32_t>(edge >> 32), static_cast<std::uint32_t>(edge & 0xffffffffu)});
  }
  std::sort(out.hanging.begin(), out.hanging.end(),
            [](const HangingVertex& a, const HangingVertex& b) { return a.vertex < b.vertex; });
  return out;
}

std::size_t ElementHierarchy::bytes() const {
  return nodes_.capacity() * sizeof(HierarchyNode) + childList_.capacity() * sizeof(std::uint32_t) +
         leafNodes_.capacity() * sizeof(std::uint32_t) + roots_.capacity() * sizeof(Root);
}

std::vector<Rgb> leafVertexValues(const ElementHierarchy::LeafMesh& leaves, const std::vector<Rgb>& perLeaf) {
  std::vector<Rgb> values = vertexRadiosity(leaves.mesh, perLeaf);
  constrainHangingVertices(leaves, values);
  return values;
}

void constrainHangingVertices(const ElementHierarchy::LeafMesh& leaves, std::vector<Rgb>& values) {
  LAMBERT_CHECK(values.size() == leaves.mesh.numVertices());
  // Made on a coarser edge first (a smaller vertex index), so an end that hangs itself is final.
  for (const HangingVertex& h : leaves.hanging) values[h.vertex] = (values[h.edgeStart] + values[h.edgeEnd]) * 0.5;
}

}  // namespace lambert
