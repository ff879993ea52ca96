#pragma once
// The element hierarchy of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, "A rapid
// hierarchical radiosity algorithm") under a hierarchy of clusters (Smits, Arvo & Greenberg
// 1994, "A clustering algorithm for radiosity in complex environments"; Sillion 1995).
//
// Every input face (a triangle or a planar convex quad; other polygons are fanned into
// triangles) roots a tree of elements, each split four ways at its edge midpoints when the
// links need finer receivers or sources. Above the faces, a bounding-volume hierarchy of
// clusters (median splits along the longest axis, at most four faces per bottom cluster) groups
// them, so that distant groups of faces exchange light through one link instead of through
// every pair of faces.
//
// Nodes are numbered in creation order, so a node's parent always has a smaller index: a pass in
// increasing index visits parents before children (push), one in decreasing index children before
// parents (pull). The leaves, in increasing node order, are the elements B is solved on; leaves()
// turns them into a Mesh whose vertices are shared between the leaves of one surface (edge
// midpoints are made once per edge), so per-vertex values can be continuous.
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

inline constexpr std::uint32_t kNoNode = 0xffffffffu;

// A cluster's bounds: Σ over the faces inside of A·max(0, ±n_axis), for +x, −x, +y, −y, +z, −z,
// so that projectedArea(ω) bounds the area the faces show toward ω (exact for faces along the
// axes, as in most buildings); half the extent of the axis-aligned box about its centre that
// holds its faces, rounded up; and a box oriented along the faces' mean normal (slabAxis, zero
// where they have none) that holds them too. A patch of a curved surface lies thin along its
// normal, while its axis-aligned box, tilted to the axes, is as thick as it is wide: judged by
// that box, every face of a sphere found the patches beside it in front of its plane, and
// refinement opened them down to every pair of faces (a 64-segment sphere: 2.2 × 10⁷ pairs).
struct ClusterBounds {
  std::array<float, 6> axisArea;  // trivial, to share a union: value-initialise ({}) to zero
  std::array<float, 3> halfExtent;
  std::array<float, 3> slabAxis, slabCentre, slabHalfExtent;  // half extents along slabFrame()'s axes
};

// The oriented box's axes: the unit slab axis and two unit tangents (all zero where it has none).
struct SlabFrame {
  Vec3 axis, tangent, bitangent;
};
inline SlabFrame slabFrame(const ClusterBounds& b) {
  const Vec3 a{b.slabAxis[0], b.slabAxis[1], b.slabAxis[2]};
  const double l = length(a);
  if (!(l > 0)) return {};
  SlabFrame f;
  f.axis = a / l;
  orthonormalBasis(f.axis, f.tangent, f.bitangent);
  return f;
}

// The least and most of n·x over the points x a node holds.
struct Extent {
  double lo, hi;
};

// Where a per-side quantity of axis `axis` (0: x, 1: y, 2: z) goes for a vector whose component
// along it is `component`, in axisArea's order (+x, −x, +y, −y, +z, −z); every per-side array of
// the hierarchy (the links' facing shares, the push's bins, the gather's power per side) uses it.
inline int axisSide(int axis, double component) { return 2 * axis + (component > 0 ? 0 : 1); }

// How an element splits. Four ways in general: a triangle at its edge midpoints into four
// triangles, a quad at its midpoints and centre into four quads, each child its parent's shape.
// A sliver (a triangle whose longest edge is over four times its height, a quad over twice as
// long as wide) halves across its length instead: a triangle at its longest edge's midpoint (Rivara's
// longest-edge bisection), a quad at the midpoints of its two long edges. Split four ways, a
// sliver's leaves stay slivers however small, and values interpolated along them run from one
// end of the sliver to the other: a floor given as a fan of long triangles showed light and dark
// wedges radiating from the fan's apex. Halved, leaves grow toward their width's size and shape.
// Only new vertices at edges' midpoints are made, so the leaves' hanging vertices (T-junctions)
// are found as for four-way splits.
struct ElementSplit {
  int children;  // 4, or 2 for a halved sliver
  int edge;      // halved: the split edge (a triangle's longest, a quad's first long one: k and k + 2)
};

// 192 bytes: an element's corners and a cluster's bounds share their space, and the fields are
// ordered without padding (the hierarchy of a 10⁶-face scene holds about 1.8 × 10⁶ nodes).
struct HierarchyNode {
  union {
    // Elements: the corners, counter-clockwise (numCorners 3 or 4).
    std::array<Vec3, 4> corners{};
    // Clusters (numCorners 0): assigned whole when the cluster is built.
    ClusterBounds bounds;
  };
  Vec3 normal;                // elements: unit, front side; clusters: zero
  Vec3 centre;                // elements: area centroid; clusters: bounding-box centre
  double area = 0;            // scene units²; clusters: the area of all faces inside
  double radius = 0;          // of a sphere about centre that holds the node
  std::uint32_t surface = 0;  // elements: the scene surface and face they lie on
  std::uint32_t face = 0;
  std::uint32_t parent = kNoNode;
  std::uint32_t firstChild = 0;  // into ElementHierarchy::childList
  std::uint32_t numChildren = 0;
  std::uint32_t leaf = kNoNode;  // index among the leaves, set by numberLeaves()
  std::uint8_t numCorners = 0;
  std::uint8_t depth = 0;     // splits below the face (elements) or below the root (clusters)
  bool twinned = false;       // element of a two-sided surface (Patch::twinned)
  bool enclosed = false;      // element inside a closed two-sided object, where no light reaches (geometry/enclosures.h)

  bool isCluster() const { return numCorners == 0; }
  // The area the node shows toward the unit direction ω: A·max(0, n·ω) for an element; for a
  // cluster Σ_axis |ω_axis| · axisArea on ω's side, never less than what its faces show.
  double projectedArea(const Vec3& w) const {
    if (!isCluster()) return area * std::fmax(0.0, dot(normal, w));
    const std::array<float, 6>& axisArea = bounds.axisArea;
    return std::fabs(w.x) * axisArea[w.x > 0 ? 0 : 1] + std::fabs(w.y) * axisArea[w.y > 0 ? 2 : 3] +
           std::fabs(w.z) * axisArea[w.z > 0 ? 4 : 5];
  }
  bool isLeaf() const { return numChildren == 0; }
  // The least and most of n·x over the node's points: an element's corners; within both of a
  // cluster's boxes.
  Extent extentAlong(const Vec3& n) const {
    if (!isCluster()) {
      Extent e{dot(n, corners[0]), dot(n, corners[0])};
      for (std::size_t k = 1; k < numCorners; ++k) {
        const double h = dot(n, corners[k]);
        e.lo = std::fmin(e.lo, h);
        e.hi = std::fmax(e.hi, h);
      }
      return e;
    }
    const double c = dot(n, centre);
    const double reach = std::fabs(n.x) * bounds.halfExtent[0] + std::fabs(n.y) * bounds.halfExtent[1] + std::fabs(n.z) * bounds.halfExtent[2];
    Extent e{c - reach, c + reach};
    if (const SlabFrame f = slabFrame(bounds); f.axis.x != 0 || f.axis.y != 0 || f.axis.z != 0) {
      const double s = dot(n, Vec3{bounds.slabCentre[0], bounds.slabCentre[1], bounds.slabCentre[2]});
      const double slabReach = std::fabs(dot(n, f.axis)) * bounds.slabHalfExtent[0] + std::fabs(dot(n, f.tangent)) * bounds.slabHalfExtent[1] +
                               std::fabs(dot(n, f.bitangent)) * bounds.slabHalfExtent[2];
      e.lo = std::fmax(e.lo, s - slabReach);
      e.hi = std::fmin(e.hi, s + slabReach);
    }
    return e;
  }
  // The axis-aligned box that holds the node: a cluster's, or its corners'.
  void box(Vec3& lo, Vec3& hi) const {
    if (isCluster()) {
      const Vec3 half{bounds.halfExtent[0], bounds.halfExtent[1], bounds.halfExtent[2]};
      lo = centre - half;
      hi = centre + half;
      return;
    }
    lo = hi = corners[0];
    for (std::size_t k = 1; k < numCorners; ++k) {
      lo = componentMin(lo, corners[k]);
      hi = componentMax(hi, corners[k]);
    }
  }
  std::span<const Vec3> polygon() const { return {corners.data(), numCorners}; }
};
static_assert(sizeof(HierarchyNode) <= 192, "the node layout above is meant to be compact");

ElementSplit elementSplit(const HierarchyNode& element);
// The area an element's error shows over: the larger of its own and a quarter of its longest
// edge squared, the area of a well-shaped element as long as it (a right isosceles triangle on
// that edge); a cluster's own. A value wrong by ΔB over a sliver is wrong along its whole length,
// which its small area hides from a bound on power: a floor fanned into 40 long triangles was
// left with leaves 13 times as long as high where a lamp's light varied along them, and values
// interpolated over them 7% off (RMS; 42% at worst) where the same floor as two triangles was
// within 0.9%.
double extentArea(const HierarchyNode& element);
// The share of an element's area each child of its split has.
inline double childAreaShare(const HierarchyNode& element) { return 1.0 / elementSplit(element).children; }

// A vertex of leaves() that lies on an edge of a larger leaf without being one of its corners
// (a T-junction): its value must be interpolated along that edge, half way between the ends of
// the edge it was made on, so that both sides of the edge show the same values.
struct HangingVertex {
  std::uint32_t vertex, edgeStart, edgeEnd;
};

class ElementHierarchy {
 public:
  // The faces of every surface, and the clusters over them. The root (node 0) is a cluster.
  // faceGroups (per surface, per face; empty: one group) keeps groups apart: a cluster's faces
  // are split by group before by place, so that no cluster below the root holds two groups
  // (geometry/enclosures.h: a room's inside and, across its two-sided walls, its outside).
  explicit ElementHierarchy(const Scene& scene, const std::vector<std::vector<std::uint32_t>>& faceGroups = {});

  const std::vector<HierarchyNode>& nodes() const { return nodes_; }
  const HierarchyNode& node(std::uint32_t i) const { return nodes_[i]; }
  std::span<const std::uint32_t> children(std::uint32_t i) const {
    return {childList_.data() + nodes_[i].firstChild, nodes_[i].numChildren};
  }
  std::size_t numFaces() const { return numFaces_; }
  std::size_t numClusters() const { return numClusters_; }
  std::size_t numElements() const { return nodes_.size() - numClusters_; }
  double totalArea() const { return nodes_[0].area; }

  // Marks the faces whose root leaf is flagged (per leaf, in leaf order, before any split) and
  // everything split from them later as enclosed.
  void markEnclosedFaces(std::span<const std::uint8_t> perLeaf);
  // Per node, the area of its faces outside closed two-sided objects: an element's own area, 0 if
  // it is enclosed; a cluster's, the sum of its children's. What a cluster's links sample and its
  // mean radiosity is taken over (the enclosed faces receive and send nothing).
  std::vector<double> unenclosedAreas() const;

  // Splits a leaf element (elementSplit below says how). Children are appended to nodes().
  void split(std::uint32_t element);

  // Numbers the leaves in node order; returns how many there are. Call after splitting.
  std::size_t numberLeaves();
  const std::vector<std::uint32_t>& leafNodes() const { return leafNodes_; }

  // The leaves as patches (face, surface and twinned set) over shared per-surface vertices, and
  // the T-junction vertices among them, in the order they must be interpolated.
  struct LeafMesh {
    Mesh mesh;
    std::vector<HangingVertex> hanging;
  };
  LeafMesh leaves(const Scene& scene) const;

  // The bytes the nodes and child lists take.
  std::size_t bytes() const;

 private:
  struct FaceRoot;
  struct FaceKey;
  std::uint32_t addNode(const HierarchyNode& node);
  static void setSlab(const std::vector<FaceRoot>& all, std::span<const FaceKey> faces, ClusterBounds& bounds);
  void buildClusters(const std::vector<FaceRoot>& all, std::span<FaceKey> faces, std::uint32_t parent, std::uint32_t slot,
                     std::uint8_t depth);

  // A face's root element and its corners' indices among all surfaces' vertices (surfaces in
  // order, each one's vertices in order), which leaves() shares between faces.
  struct Root {
    std::uint32_t node;
    std::array<std::uint32_t, 4> vertices;
  };

  std::vector<HierarchyNode> nodes_;
  std::vector<std::uint32_t> childList_;
  std::vector<Root> roots_;
  std::vector<std::uint32_t> leafNodes_;
  std::size_t numFaces_ = 0, numClusters_ = 0;
};

// Per-vertex values of a per-leaf quantity on a LeafMesh, continuous across leaves of one
// surface: mesh/vertex_radiosity.h's averaging (with its border extrapolation), then every
// T-junction vertex set to the mean of its edge's ends, coarsest first.
std::vector<Rgb> leafVertexValues(const ElementHierarchy::LeafMesh& leaves, const std::vector<Rgb>& perLeaf);

// Sets every T-junction vertex's value to the mean of its edge's ends, coarsest first, so that
// both sides of the edge interpolate the same values (no crack in Gouraud shading).
void constrainHangingVertices(const ElementHierarchy::LeafMesh& leaves, std::vector<Rgb>& perVertex);

}  // namespace lambert
