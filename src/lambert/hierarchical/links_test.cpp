// Link refinement on a luminaire: long reflectors and a casing whose ends meet end caps fanned
// into sliver triangles, around a lamp as long as they are (the geometry of RenderPark's
// examp1.mgf, Ledalite's fixture, built here from its description).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "lambert/core/rng.h"
#include "lambert/engine/radiosity.h"
#include "lambert/hierarchical/links.h"
#include "lambert/hierarchical/refiner.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/hierarchical/element_hierarchy.h"
#include "lambert/load/scene_file.h"
#include "tests/support/engines.h"
#include "tests/support/files.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

// A 48-inch casing of 12 strips over a half-round profile, closed by two prisms (end caps: the
// 15-gon of the profile, fanned into slivers), an upper reflector 1.7 inches wide whose ends lie
// in the caps' planes, and a lamp cylinder of radius 0.5 inch along the whole length.
std::string luminaireMgf() {
  std::string mgf = "m white =\n\tsides 1\n\tc\n\trd .8\nm lamp =\n\tsides 1\n\tc\n\ted 44700\n\trd .6\nxf -s .0254\n";
  for (const auto& [side, x] : {std::pair<const char*, int>{"-", -24}, {"+", 24}}) {
    for (int k = 0; k <= 12; ++k) {
      const double t = -kPi / 2 + kPi * k / 12;
      mgf += "v c" + std::to_string(k) + side + " =\n\tp " + std::to_string(x) + " " + std::to_string(3.06 + 2 * std::cos(t)) + " " +
             std::to_string(1.75 * std::sin(t)) + "\n";
    }
    mgf += std::string("v top") + side + " =\n\tp " + std::to_string(x) + " 0 1.75\n";
    mgf += std::string("v bot") + side + " =\n\tp " + std::to_string(x) + " 0 -1.75\n";
  }
  mgf += "v u1 =\n\tp -24 2.5625 .5833\nv u2 =\n\tp 24 2.5625 .5833\nv u3 =\n\tp 24 4.25 .5833\nv u4 =\n\tp -24 4.25 .5833\n";
  mgf += "m white\n";
  for (int k = 0; k < 12; ++k) {
    const std::string a = std::to_string(k), b = std::to_string(k + 1);
    mgf += "f c" + a + "- c" + b + "- c" + b + "+ c" + a + "+\n";
  }
  mgf += "prism";
  for (int k = 0; k <= 12; ++k) mgf += " c" + std::to_string(k) + "-";
  mgf += " top- bot- .125\nprism";
  for (int k = 12; k >= 0; --k) mgf += " c" + std::to_string(k) + "+";
  mgf += " bot+ top+ .125\nf u1 u2 u3 u4\n";
  mgf += "m lamp\nv l1 =\n\tp -24 1 1.25\nv l2 =\n\tp 24 1 1.25\ncyl l1 .5 l2\nxf\n";
  return mgf;
}

double statValue(const Stats& stats, const char* key) {
  const auto* entry = stats.find(key);
  EXPECT_NE(entry, nullptr) << key;
  if (!entry) return 0;
  if (const auto* i = std::get_if<std::int64_t>(&entry->value)) return static_cast<double>(*i);
  return std::get<double>(entry->value);
}

// An end cap's sliver triangle with a corner just above a reflector's plane: its quadrature
// points see nothing of the reflector, and split by area the pair cut the reflector (and the
// casing, whose planes cut through the lamp's and caps' clusters) down to the smallest elements
// along their whole length. Measured before: 22,125 leaves and 417,055 links estimated; with the
// receiver split where its points see nothing and the cluster opened where an element's plane
// cuts through it: 3,651 and 52,551. Energy still balances.
TEST(LinksTest, ALuminairesLongReflectorsAreNotCutToTheSmallestElements) {
  const std::filesystem::path dir = testing::scratchDirectory("links", "luminaire");
  std::ofstream(dir / "luminaire.mgf") << luminaireMgf();
  Result<Scene> scene = loadScene((dir / "luminaire.mgf").string());
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  RadiosityOptions options;
  options.meshing = MeshStrategy::Hierarchical;
  options.formFactors.showProgress = false;
  auto engine = Radiosity::create(*scene, options);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  auto report = (*engine)->solve();
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_TRUE(report->converged);
  const Stats stats = (*engine)->stats();
  const double faces = statValue(stats, "faces"), leaves = statValue(stats, "patches"), estimated = statValue(stats, "links_estimated");
  std::printf("%g faces: %g leaves, %g links estimated\n", faces, leaves, estimated);
  EXPECT_LT(leaves, 8000);
  EXPECT_LT(estimated, 150e3);
  // Open at the front and back: the surfaces absorb part of what is emitted and the rest leaves
  // (links that made light would absorb more than was emitted, with negative escaped power).
  const double emitted = statValue(stats, "emitted_watts"), absorbed = statValue(stats, "absorbed_watts"), escaped = statValue(stats, "escaped_watts");
  EXPECT_GT(absorbed, 0.01 * emitted);
  EXPECT_LT(absorbed, emitted);
  EXPECT_GT(escaped, 0.01 * emitted);
}

// A unit square as an n×n grid of faces at height z, facing up or down.
Surface gridSquare(std::string name, double z, bool up, int n) {
  Surface s;
  s.name = std::move(name);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.vertices.push_back({double(i) / n, double(j) / n, z});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto at = [&](int a, int b) { return static_cast<std::uint32_t>(b * (n + 1) + a); };
      if (up) s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      else s.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  return s;
}

struct Refined {
  ElementHierarchy hierarchy;
  Links links;
  RefinementReport report;
};

// The links of a scene whose faces all have radiosity 1, refined from the root cluster.
Refined refineUniform(const Scene& scene, double linkError) {
  Refined out{ElementHierarchy(scene), {}, {}};
  const ElementHierarchy::LeafMesh leaves = out.hierarchy.leaves(scene);
  const std::unique_ptr<RayCaster> caster = makeEmbreeRayCaster(leaves.mesh);
  std::vector<std::uint64_t> casterFace;
  for (const Patch& p : leaves.mesh.patches) casterFace.push_back(static_cast<std::uint64_t>(p.surface) << 32 | p.face);
  const std::vector<double> ones(leaves.mesh.numPatches(), 1.0);
  LinkOptions options;
  options.linkError = linkError;
  out.links = refineLinks(out.hierarchy, *caster, rayEpsilon(leaves.mesh), casterFace, nullptr, ones, ones, options, out.report);
  return out;
}

// Faces in one plane exchange nothing, and a cluster of them is found so before anything is
// sampled: a floor of 256 faces alone costs the root's link to itself and keeps no link (taken
// apart pair by pair, the same floor cost 7,169 estimates, for the same none). Facing a parallel ceiling one above,
// each floor leaf still gathers the whole of it: with every face's radiosity 1, Σ K over the
// links of a leaf and its ancestors is the leaf's form factor to the ceiling, whose area-weighted
// mean over the floor is Howell's 0.19982 for unit squares one apart.
TEST(LinksTest, CoplanarFacesCostNoEstimatesAndFacingOnesKeepTheirExchange) {
  {
    const Refined floor = refineUniform(testing::sceneOf({gridSquare("floor", 0, true, 16)}), 2e-4);
    EXPECT_EQ(floor.links.size(), 0u);
    EXPECT_EQ(floor.report.estimated, 1u);
  }
  const Refined box = refineUniform(testing::sceneOf({gridSquare("floor", 0, true, 16), gridSquare("ceiling", 1, false, 16)}), 2e-4);
  const ElementHierarchy& h = box.hierarchy;
  double gathered = 0, area = 0, least = 1;
  for (std::uint32_t leaf : h.leafNodes()) {
    const HierarchyNode& node = h.node(leaf);
    if (node.normal.z < 0.5) continue;  // the floor's leaves
    double k = 0;
    for (std::uint32_t r = leaf; r != kNoNode; r = h.node(r).parent)
      for (std::uint32_t i = box.links.start[r]; i < box.links.start[r + 1]; ++i) k += box.links.formFactor[i];
    gathered += k * node.area;
    area += node.area;
    least = std::fmin(least, k);
  }
  std::printf("%zu links, %llu estimated: mean floor-to-ceiling factor %.5f (Howell 0.19982), least %.4f\n", box.links.size(),
              static_cast<unsigned long long>(box.report.estimated), gathered / area, least);
  EXPECT_NEAR(gathered / area, 0.19982, 0.02 * 0.19982);
  EXPECT_GT(least, 0.13);  // every leaf sees the ceiling: at the floor's corner point 0.139, at its centre 0.240
}

// Two grey spheres (two-sided, as MGF's materials are) on the floor of a room lit by a lamp
// panel: a curved surface, its patches' boxes tilted to the axes, and inner twins enclosed.
std::string spheresInARoomMgf() {
  return "m white =\n\tc\n\trd .7\nm grey =\n\tc\n\trd .5\nm lamp =\n\tc\n\ted 40\n"
         "v f1 =\n\tp 0 0 0\nv f2 =\n\tp 4 0 0\nv f3 =\n\tp 4 4 0\nv f4 =\n\tp 0 4 0\n"
         "v c1 =\n\tp 0 0 3\nv c2 =\n\tp 4 0 3\nv c3 =\n\tp 4 4 3\nv c4 =\n\tp 0 4 3\n"
         "m white\nf f1 f2 f3 f4\nf c4 c3 c2 c1\nf f1 c1 c2 f2\nf f2 c2 c3 f3\nf f3 c3 c4 f4\nf f4 c4 c1 f1\n"
         "m grey\nv s1 =\n\tp 1.5 2 0.5\nv s2 =\n\tp 2.8 2 0.5\nsph s1 0.5\nsph s2 0.5\n"
         "m lamp\nv l1 =\n\tp 1.6 1.6 2.5\nv l2 =\n\tp 2.4 1.6 2.5\nv l3 =\n\tp 2.4 2.4 2.5\nv l4 =\n\tp 1.6 2.4 2.5\nf l1 l2 l3 l4\n";
}

Result<Scene> spheresInARoom(int divisions) {
  const std::filesystem::path dir = testing::scratchDirectory("links", "spheres-" + std::to_string(divisions));
  std::ofstream(dir / "spheres.mgf") << spheresInARoomMgf();
  LoadOptions load;
  load.mgfDivisions = divisions;
  return loadScene((dir / "spheres.mgf").string(), load);
}

// A cluster's bounds hold every corner of every face under it, along any direction; and over a
// sphere's small patches the box along their mean normal is far thinner than the axis-aligned
// one (the test the refinement's culling relies on, links.cpp mayFace and cutsThrough).
TEST(LinksTest, ClusterBoundsHoldTheirFacesAndLieThinAlongACurvedPatch) {
  const Result<Scene> scene = spheresInARoom(32);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const ElementHierarchy h(*scene);
  Pcg32 rng(5, 9);
  std::vector<Vec3> directions;
  for (int k = 0; k < 24; ++k) {
    const double z = 2 * rng.nextDouble() - 1, phi = 2 * kPi * rng.nextDouble(), r = std::sqrt(1 - z * z);
    directions.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  std::vector<double> thinness;  // small clusters: extent along the slab axis, slab / axis-aligned
  for (std::uint32_t c = 0; c < h.nodes().size(); ++c) {
    if (!h.node(c).isCluster()) continue;
    std::vector<Vec3> corners;
    std::vector<std::uint32_t> stack{c};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (!h.node(n).isCluster()) {
        for (const Vec3& p : h.node(n).polygon()) corners.push_back(p);
        continue;
      }
      for (std::uint32_t k : h.children(n)) stack.push_back(k);
    }
    for (const Vec3& n : directions) {
      const Extent e = h.node(c).extentAlong(n);
      for (const Vec3& p : corners) {
        ASSERT_GE(dot(n, p), e.lo - 1e-12) << c;
        ASSERT_LE(dot(n, p), e.hi + 1e-12) << c;
      }
    }
    const SlabFrame frame = slabFrame(h.node(c).bounds);
    if (corners.size() <= 64 && length(frame.axis) > 0) {
      const Vec3 half{h.node(c).bounds.halfExtent[0], h.node(c).bounds.halfExtent[1], h.node(c).bounds.halfExtent[2]};
      const double boxReach = std::fabs(frame.axis.x) * half.x + std::fabs(frame.axis.y) * half.y + std::fabs(frame.axis.z) * half.z;
      const Extent e = h.node(c).extentAlong(frame.axis);
      thinness.push_back(0.5 * (e.hi - e.lo) / boxReach);
    }
  }
  ASSERT_GT(thinness.size(), 100u);
  std::nth_element(thinness.begin(), thinness.begin() + static_cast<std::ptrdiff_t>(thinness.size() / 2), thinness.end());
  const double median = thinness[thinness.size() / 2];
  std::printf("%zu small clusters: median thickness along the mean normal %.3f of the axis-aligned box's\n", thinness.size(), median);
  EXPECT_LT(median, 0.3);
}

// Every face of a sphere found the patches beside it in front of its plane (their axis-aligned
// boxes, tilted, rise above it), the patches behind a sphere found no sampled pair facing a wall
// and asked to look closer, and the inner twins overlapped the outer ones: refinement opened
// those pairs down to the single faces. Measured before, at 64 segments (8,206 faces): 7.1 × 10⁷
// candidates estimated, 1.9 × 10⁸ rays, 72 s; with the enclosed nodes dropped, the bounds along
// the patches' normals and the normal cones: 2.5 × 10⁶ and 1.7 s; with small clusters' faces
// asked one by one where no sampled pair faced (links.cpp, facesSeeNothingOf): 5.4 × 10⁵, 85, 69 and
// 66 a face at 16, 32 and 64 segments: linear in the faces. The same links are kept (18,617 against 19,452),
// and the leaves the spurious splits made (32,824) are down to 12,745.
TEST(LinksTest, SpheresInARoomAreNotOpenedDownToEveryPairOfFaces) {
  const Result<Scene> scene = spheresInARoom(64);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const auto engine = testing::solved(*scene);  // the default method: hierarchical, clustered
  ASSERT_TRUE(engine);
  const Stats stats = engine->stats();
  const double faces = statValue(stats, "faces"), estimated = statValue(stats, "links_estimated");
  std::printf("%g faces: %g links estimated, %g kept, %g leaves\n", faces, estimated, statValue(stats, "links"), statValue(stats, "patches"));
  EXPECT_LT(estimated, 120 * faces);  // was 8,690 a face, 308 without the faces asked one by one
  // A closed room: what is emitted is absorbed, but for what the links' factors leave out at this
  // link error (3.4% here, as before the culling: nothing the culled pairs carried).
  EXPECT_GT(statValue(stats, "absorbed_watts") / statValue(stats, "emitted_watts"), 0.96);
}

}  // namespace
}  // namespace lambert
