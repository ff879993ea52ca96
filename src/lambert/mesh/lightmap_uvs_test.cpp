// Lightmap UVs checked independently of how they were made: faces rasterised over the atlas's
// texel centres (no centre covered twice), charts found again as the faces joined by shared
// corners (padding between their footprints), and each face's UV area against its 3D area.
#include "lambert/mesh/lightmap_uvs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>

#include "lambert/core/warning.h"
#include "lambert/scene/builtin.h"
#include "lambert/scene/building.h"
#include "lambert/load/scene_file.h"
#include "tests/support/files.h"

namespace lambert {
namespace {

double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// Every corner inside [0, 1]², one UV and one atlas per corner and face.
void expectShape(const Scene& scene, const LightmapUvs& uvs) {
  ASSERT_EQ(uvs.uv.size(), scene.surfaces.size());
  ASSERT_EQ(uvs.atlas.size(), scene.surfaces.size());
  ASSERT_GE(uvs.numAtlases, 1);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const auto faces = surfaceFaces(scene.surfaces[s]);
    ASSERT_EQ(uvs.uv[s].size(), faces.size());
    ASSERT_EQ(uvs.atlas[s].size(), faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      ASSERT_EQ(uvs.uv[s][f].size(), faces[f].size()) << scene.surfaces[s].name << " face " << f;
      ASSERT_LT(uvs.atlas[s][f], uvs.numAtlases);
      for (const Uv& uv : uvs.uv[s][f]) {
        EXPECT_TRUE(uv.u >= 0 && uv.u <= 1 && uv.v >= 0 && uv.v <= 1) << scene.surfaces[s].name << " (" << uv.u << ", " << uv.v << ")";
      }
    }
  }
}

// Rasterises every face's fan triangles over the texel centres with a top-left rule (an edge's
// points belong to exactly one of the two triangles that share it, whatever the rounding: the
// edge function is computed from its endpoints in one fixed order), and counts the centres
// covered twice. Also returns the covered fraction of all atlases' texels.
std::size_t texelsCoveredTwice(const LightmapUvs& uvs, double* covered = nullptr) {
  const std::size_t side = static_cast<std::size_t>(uvs.size);
  std::vector<std::uint8_t> count(side * side * static_cast<std::size_t>(uvs.numAtlases), 0);
  std::size_t twice = 0, once = 0;
  for (std::size_t s = 0; s < uvs.uv.size(); ++s)
    for (std::size_t f = 0; f < uvs.uv[s].size(); ++f) {
      const auto& c = uvs.uv[s][f];
      std::uint8_t* grid = count.data() + side * side * uvs.atlas[s][f];
      for (std::size_t k = 1; k + 1 < c.size(); ++k) {
        std::array<std::array<double, 2>, 3> t = {{{c[0].u * uvs.size, c[0].v * uvs.size},
                                                   {c[k].u * uvs.size, c[k].v * uvs.size},
                                                   {c[k + 1].u * uvs.size, c[k + 1].v * uvs.size}}};
        const double area = cross2(t[1][0] - t[0][0], t[1][1] - t[0][1], t[2][0] - t[0][0], t[2][1] - t[0][1]);
        if (area == 0) continue;
        if (area < 0) std::swap(t[1], t[2]);
        // Inside: left of every edge a → b, or on it where the edge runs up, or runs left.
        auto inside = [&](double x, double y) {
          for (int e = 0; e < 3; ++e) {
            auto a = t[e], b = t[(e + 1) % 3];
            const bool swapped = b < a;
            if (swapped) std::swap(a, b);
            double side2 = cross2(b[0] - a[0], b[1] - a[1], x - a[0], y - a[1]);
            if (swapped) side2 = -side2, std::swap(a, b);
            if (side2 < 0) return false;
            if (side2 == 0) {
              const double dx = b[0] - a[0], dy = b[1] - a[1];
              if (!(dy > 0 || (dy == 0 && dx < 0))) return false;
            }
          }
          return true;
        };
        const int x0 = std::max(0, static_cast<int>(std::floor(std::min({t[0][0], t[1][0], t[2][0]}))) - 1);
        const int x1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0][0], t[1][0], t[2][0]}))));
        const int y0 = std::max(0, static_cast<int>(std::floor(std::min({t[0][1], t[1][1], t[2][1]}))) - 1);
        const int y1 = std::min(uvs.size - 1, static_cast<int>(std::ceil(std::max({t[0][1], t[1][1], t[2][1]}))));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x)
            if (inside(x + 0.5, y + 0.5)) {
              std::uint8_t& n = grid[static_cast<std::size_t>(y) * side + static_cast<std::size_t>(x)];
              if (n == 0) ++once;
              if (n == 1) ++twice;
              n = static_cast<std::uint8_t>(std::min(n + 1, 2));
            }
      }
    }
  if (covered) *covered = static_cast<double>(once) / static_cast<double>(count.size());
  return twice;
}

// The charts found again from the output: faces of one surface joined where they share a corner
// (the same vertex at the same UV). Each chart's footprint is the texels its UV bounding box
// reaches; any two footprints in one atlas must be more than `padding` texels apart (so at least
// `padding` empty texels lie between them), and each at least ⌈padding / 2⌉ from the atlas's edges.
// Returns the number of charts.
std::size_t expectPadding(const Scene& scene, const LightmapUvs& uvs, int padding) {
  struct Box {
    int atlas;
    int x0 = INT32_MAX, y0 = INT32_MAX, x1 = -1, y1 = -1;  // texel range, inclusive
  };
  std::vector<Box> boxes;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const auto faces = surfaceFaces(scene.surfaces[s]);
    std::vector<std::size_t> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::size_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::map<std::tuple<std::uint32_t, double, double>, std::size_t> firstFace;
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (std::size_t k = 0; k < faces[f].size(); ++k) {
        auto [it, added] = firstFace.emplace(std::make_tuple(faces[f][k], uvs.uv[s][f][k].u, uvs.uv[s][f][k].v), f);
        if (!added) parent[find(f)] = find(it->second);
      }
    std::map<std::size_t, std::size_t> boxOfRoot;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      auto [it, added] = boxOfRoot.emplace(find(f), boxes.size());
      if (added) boxes.push_back({uvs.atlas[s][f]});
      Box& b = boxes[it->second];
      EXPECT_EQ(b.atlas, uvs.atlas[s][f]) << "one chart in two atlases";
      for (const Uv& uv : uvs.uv[s][f]) {
        const double x = uv.u * uvs.size, y = uv.v * uvs.size;
        b.x0 = std::min(b.x0, static_cast<int>(std::floor(x))), b.x1 = std::max(b.x1, static_cast<int>(std::ceil(x)) - 1);
        b.y0 = std::min(b.y0, static_cast<int>(std::floor(y))), b.y1 = std::max(b.y1, static_cast<int>(std::ceil(y)) - 1);
      }
    }
  }
  // Stamp each footprint, then look for another chart within `padding` texels of each.
  const std::size_t side = static_cast<std::size_t>(uvs.size);
  std::vector<std::vector<int>> owner(static_cast<std::size_t>(uvs.numAtlases), std::vector<int>(side * side, -1));
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const Box& box = boxes[b];
    EXPECT_GE(std::min(box.x0, box.y0), (padding + 1) / 2) << "chart " << b << " too near the atlas's edge";
    EXPECT_LE(std::max(box.x1, box.y1), uvs.size - 1 - (padding + 1) / 2) << "chart " << b << " too near the atlas's edge";
    for (int y = std::max(0, box.y0); y <= std::min(box.y1, uvs.size - 1); ++y)
      for (int x = std::max(0, box.x0); x <= std::min(box.x1, uvs.size - 1); ++x) {
        int& o = owner[static_cast<std::size_t>(box.atlas)][static_cast<std::size_t>(y) * side + static_cast<std::size_t>(x)];
        EXPECT_EQ(o, -1) << "the footprints of charts " << o << " and " << b << " overlap at texel " << x << ", " << y;
        o = static_cast<int>(b);
      }
  }
  std::size_t near = 0;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const Box& box = boxes[b];
    for (int y = std::max(0, box.y0 - padding); y <= std::min(box.y1 + padding, uvs.size - 1); ++y)
      for (int x = std::max(0, box.x0 - padding); x <= std::min(box.x1 + padding, uvs.size - 1); ++x) {
        const int o = owner[static_cast<std::size_t>(box.atlas)][static_cast<std::size_t>(y) * side + static_cast<std::size_t>(x)];
        if (o != -1 && o != static_cast<int>(b)) ++near;
      }
  }
  EXPECT_EQ(near, 0u) << "texels of another chart within " << padding << " texels of a chart";
  return boxes.size();
}

// Each face's UV area in texels against its area in texels of texelSize: the ratios' range.
std::pair<double, double> texelAreaRatios(const Scene& scene, const LightmapUvs& uvs) {
  double lo = INFINITY, hi = 0;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const auto faces = surfaceFaces(scene.surfaces[s]);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const std::vector<Vec3> p = facePositions(scene.surfaces[s], faces[f]);
      const auto& c = uvs.uv[s][f];
      double a3 = 0, a2 = 0;
      for (std::size_t k = 1; k + 1 < p.size(); ++k) {
        a3 += 0.5 * length(cross(p[k] - p[0], p[k + 1] - p[0]));
        a2 += 0.5 * std::fabs(cross2(c[k].u - c[0].u, c[k].v - c[0].v, c[k + 1].u - c[0].u, c[k + 1].v - c[0].v));
      }
      const double ratio = a2 * uvs.size * uvs.size / (a3 / (uvs.texelSize * uvs.texelSize));
      lo = std::min(lo, ratio), hi = std::max(hi, ratio);
    }
  }
  return {lo, hi};
}

// The checks every generated layout passes.
void expectValidLayout(const Scene& scene, const LightmapUvs& uvs, int padding = LightmapUvOptions{}.paddingTexels) {
  expectShape(scene, uvs);
  if (::testing::Test::HasFatalFailure()) return;
  double covered = 0;
  EXPECT_EQ(texelsCoveredTwice(uvs, &covered), 0u);
  // (To 1e-4: a centre exactly on a chart's outline is counted by one rule and not the other.)
  EXPECT_NEAR(covered, uvs.efficiency, 1e-4) << "the efficiency it reports is the covered fraction";
  if (uvs.origin == LightmapUvs::Origin::Generated) {
    EXPECT_EQ(expectPadding(scene, uvs, padding), uvs.charts);
  }
}

TEST(LightmapUvsTest, CornellBoxIsPackedWithoutOverlapAtOneTexelSize) {
  const Scene scene = cornellBox();
  Result<LightmapUvs> uvs = lightmapUvs(scene);
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  EXPECT_EQ(uvs->origin, LightmapUvs::Origin::Generated);
  EXPECT_EQ(uvs->size, 1024);
  EXPECT_EQ(uvs->numAtlases, 1);
  expectValidLayout(scene, *uvs);
  // Planar charts: every face's UV area is its area in texels (the published box's walls are a
  // few millimetres off plane: a projection's cosine away from exact).
  const auto [lo, hi] = texelAreaRatios(scene, *uvs);
  EXPECT_NEAR(lo, 1, 1e-4);
  EXPECT_NEAR(hi, 1, 1e-4);
  EXPECT_GE(uvs->efficiency, 0.7) << uvs->note;
  EXPECT_DOUBLE_EQ(uvs->texelSize, defaultTexelSize(scene));
}

TEST(LightmapUvsTest, ShippedScenesPackAtLeastSeventyPercent) {
  std::vector<std::pair<std::string, Scene>> scenes;
  for (const std::string& name : builtinSceneNames()) scenes.emplace_back(name, *builtinScene(name));
  for (const char* file : {"cornell/cornell.json", "cornell/cornell-obj.json", "cornell/cornell-spots.json", "floor/floor.json", "room/room.gltf"}) {
    WarningCapture quiet;
    Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/" + file);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    scenes.emplace_back(file, std::move(*scene));
  }
  for (const auto& [name, scene] : scenes) {
    SCOPED_TRACE(name);
    const auto start = std::chrono::steady_clock::now();
    Result<LightmapUvs> uvs = lightmapUvs(scene);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(uvs.ok()) << uvs.error().message;
    std::printf("  %-26s %6zu faces: %s (%.3f s)\n", name.c_str(), [&] {
      std::size_t n = 0;
      for (const Surface& s : scene.surfaces) n += surfaceFaces(s).size();
      return n;
    }(), uvs->note.c_str(), seconds);
    expectValidLayout(scene, *uvs);
    EXPECT_GE(uvs->efficiency, 0.7) << uvs->note;
  }
}

// Blender's own export (tests/data/blender_room.glb: boxes, planes and a 24 × 12 UV sphere, no
// TEXCOORD_1, TEXCOORD_0 only on the textured floor): generated, the sphere by conformal charts.
TEST(LightmapUvsTest, BlenderExportGetsGeneratedChartsWithConformalOnesOnItsSphere) {
  WarningCapture quiet;
  Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/tests/data/blender_room.glb");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Result<LightmapUvs> uvs = lightmapUvs(*scene);
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  std::printf("  blender_room.glb: %s\n", uvs->note.c_str());
  EXPECT_EQ(uvs->origin, LightmapUvs::Origin::Generated);
  EXPECT_NE(uvs->note.find("the file's texture coordinates"), std::string::npos) << "why the first set was not used";
  EXPECT_GE(uvs->conformalCharts, 2u);
  expectValidLayout(*scene, *uvs);
  EXPECT_GE(uvs->efficiency, 0.7);
}

TEST(LightmapUvsTest, SameSceneGivesTheSameUvs) {
  Result<Scene> scene = loadScene(std::string(LAMBERT_SOURCE_DIR) + "/scenes/floor/floor.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Result<LightmapUvs> a = lightmapUvs(*scene), b = lightmapUvs(*scene);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->uv, b->uv);
  EXPECT_EQ(a->atlas, b->atlas);
  EXPECT_EQ(a->texelSize, b->texelSize);
}

// A sphere of quads (triangles at the poles) as one smooth surface, outward faces.
Scene sphereScene(int segments, int rings, double radius) {
  Scene scene;
  scene.materials.push_back({"grey", Rgb::gray(0.5)});
  Surface s;
  s.name = "sphere";
  auto at = [&](int ring, int seg) {
    const double theta = kPi * ring / rings, phi = 2 * kPi * seg / segments;
    return Vec3{radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta), radius * std::sin(theta) * std::sin(phi)};
  };
  s.vertices.push_back(at(0, 0));
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < segments; ++k) s.vertices.push_back(at(r, k));
  s.vertices.push_back(at(rings, 0));
  auto index = [&](int r, int k) -> std::uint32_t {
    if (r == 0) return 0;
    if (r == rings) return static_cast<std::uint32_t>(s.vertices.size() - 1);
    return static_cast<std::uint32_t>(1 + (r - 1) * segments + (k % segments));
  };
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      if (r == 0) s.faces.push_back({index(0, 0), index(1, k + 1), index(1, k)});
      else if (r == rings - 1) s.faces.push_back({index(r, k), index(r, k + 1), index(rings, 0)});
      else s.faces.push_back({index(r, k), index(r, k + 1), index(r + 1, k + 1), index(r + 1, k)});
    }
  // Outward: cross(v1 − v0, v2 − v0) along the position.
  const auto first = facePositions(s, s.faces[s.faces.size() / 2]);
  if (dot(polygonAreaVector(first), first[0]) < 0)
    for (auto& f : s.faces) std::reverse(f.begin() + 1, f.end());
  scene.surfaces.push_back(std::move(s));
  return scene;
}

// The largest ratio of a triangle's two singular values under the map from its 3D frame to UV:
// 1 for a conformal (angle-keeping) map.
double worstAngleStretch(const Scene& scene, const LightmapUvs& uvs) {
  double worst = 1;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const auto faces = surfaceFaces(scene.surfaces[s]);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto p = facePositions(scene.surfaces[s], faces[f]);
      const auto& c = uvs.uv[s][f];
      for (std::size_t k = 1; k + 1 < p.size(); ++k) {
        const Vec3 e1 = p[k] - p[0], e2 = p[k + 1] - p[0];
        const double l1 = length(e1), x2 = dot(e2, e1) / l1, y2 = length(cross(e1, e2)) / l1;
        // UV edges, as columns of J × [[l1, x2], [0, y2]].
        const double a = (c[k].u - c[0].u), b = (c[k + 1].u - c[0].u), d = (c[k].v - c[0].v), e = (c[k + 1].v - c[0].v);
        // J = [[a, b], [d, e]] × inverse([[l1, x2], [0, y2]]).
        const double j11 = a / l1, j12 = (b - a * x2 / l1) / y2, j21 = d / l1, j22 = (e - d * x2 / l1) / y2;
        const double frob = j11 * j11 + j12 * j12 + j21 * j21 + j22 * j22, det = std::fabs(j11 * j22 - j12 * j21);
        const double disc = std::sqrt(std::max(0.0, frob * frob / 4 - det * det));
        const double s1 = std::sqrt(frob / 2 + disc), s2 = std::sqrt(std::max(1e-300, frob / 2 - disc));
        worst = std::max(worst, s1 / s2);
      }
    }
  }
  return worst;
}

TEST(LightmapUvsTest, SphereGetsConformalChartsThatNeitherFoldNorStretchMuch) {
  const Scene scene = sphereScene(48, 24, 1.0);
  Result<LightmapUvs> uvs = lightmapUvs(scene);
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  std::printf("  sphere: %s\n", uvs->note.c_str());
  expectValidLayout(scene, *uvs);
  // Charts much larger than a face (conformal pieces, not per-face projections)...
  EXPECT_LE(uvs->charts, scene.surfaces[0].faces.size() / 20);
  // ...whose texel density stays within a factor of the asked (area) and keep angles.
  const auto [lo, hi] = texelAreaRatios(scene, *uvs);
  std::printf("  sphere: face area ratios %.3f to %.3f, worst angle stretch %.3f\n", lo, hi, worstAngleStretch(scene, *uvs));
  EXPECT_GT(lo, 0.5);
  EXPECT_LT(hi, 2.0);
  EXPECT_LT(worstAngleStretch(scene, *uvs), 1.5);
}

TEST(LightmapUvsTest, GivenTexelSizeIsKeptAndTheAtlasIsTheSmallestPowerOfTwo) {
  const Scene scene = cornellBox();
  // The box's 556 mm sides at 5 mm per texel: about 111 texels each.
  LightmapUvOptions options;
  options.texelSize = 5;
  Result<LightmapUvs> uvs = lightmapUvs(scene, options);
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  EXPECT_EQ(uvs->texelSize, options.texelSize);
  expectValidLayout(scene, *uvs);
  const auto [lo, hi] = texelAreaRatios(scene, *uvs);
  EXPECT_NEAR(lo, 1, 1e-4);
  EXPECT_NEAR(hi, 1, 1e-4);
  EXPECT_EQ(uvs->numAtlases, 1);
  // Smallest: the charts do not fit the next smaller power of two (their area alone, or packed).
  options.atlasSize = uvs->size / 2;
  Result<LightmapUvs> smaller = lightmapUvs(scene, options);
  ASSERT_TRUE(smaller.ok());
  EXPECT_GT(smaller->numAtlases, 1) << "a " << uvs->size << "² atlas was chosen where " << options.atlasSize << "² holds them";
  expectValidLayout(scene, *smaller);
}

TEST(LightmapUvsTest, ChartLargerThanAnAtlasIsScaledDownWithAWarning) {
  const Scene scene = cornellBox();
  LightmapUvOptions options;
  options.atlasSize = 64;
  options.texelSize = 556.0 / 200;  // the floor is 200 texels wide: larger than 64
  WarningCapture warnings;
  Result<LightmapUvs> uvs = lightmapUvs(scene, options);
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  ASSERT_EQ(warnings.messages().size(), 1u) << "one warning for all the charts scaled down";
  EXPECT_EQ(warnings.count("larger than an atlas"), 1);
  EXPECT_EQ(warnings.count("'floor'"), 1) << warnings.messages()[0];
  expectValidLayout(scene, *uvs);
  std::size_t faces = 0;
  for (const Surface& s : scene.surfaces) faces += surfaceFaces(s).size();
  EXPECT_EQ(uvs->charts, faces) << "no chart dropped";
}

TEST(LightmapUvsTest, ImpossibleOptionsAreRefusedSayingWhy) {
  LightmapUvOptions options;
  options.atlasSize = 2;  // padding 2 between charts leaves no texel for one
  Result<LightmapUvs> uvs = lightmapUvs(cornellBox(), options);
  ASSERT_FALSE(uvs.ok());
  EXPECT_NE(uvs.error().message.find("atlas size"), std::string::npos) << uvs.error().message;
  options = {};
  options.texelSize = -1;
  EXPECT_FALSE(lightmapUvs(cornellBox(), options).ok());
}

// Two unit squares side by side (one surface each) with the given first-set UVs.
Scene twoSquares(const std::array<Uv, 4>& first, const std::array<Uv, 4>& second) {
  Scene scene;
  scene.materials.push_back({"grey", Rgb::gray(0.5)});
  for (int k = 0; k < 2; ++k) {
    Surface s;
    s.name = k == 0 ? "left" : "right";
    const double x = 2.0 * k;
    s.vertices = {{x, 0, 0}, {x + 1, 0, 0}, {x + 1, 1, 0}, {x, 1, 0}};
    const auto& uv = k == 0 ? first : second;
    s.faceUvs = {std::vector<Uv>(uv.begin(), uv.end())};
    scene.surfaces.push_back(std::move(s));
  }
  return scene;
}

TEST(LightmapUvsTest, FirstSetIsUsedWhenItDoesNotOverlapAndRejectedWhenItDoes) {
  const std::array<Uv, 4> left{{{0, 0}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}}}, right{{{0.5, 0.5}, {1, 0.5}, {1, 1}, {0.5, 1}}};
  const Scene clean = twoSquares(left, right);
  Result<LightmapUvs> used = lightmapUvs(clean);
  ASSERT_TRUE(used.ok());
  EXPECT_EQ(used->origin, LightmapUvs::Origin::FileFirstSet) << used->note;
  EXPECT_EQ(used->uv[0], clean.surfaces[0].faceUvs);
  EXPECT_EQ(used->uv[1], clean.surfaces[1].faceUvs);
  EXPECT_EQ(used->numAtlases, 1);
  expectValidLayout(clean, *used);
  // A unit square over half the atlas's width: 1 / (0.5 × 1024) units per texel.
  EXPECT_NEAR(used->texelSize, 1 / 512.0, 1e-12);
  // Squares touching along an edge in UV are still apart.
  const Scene touching = twoSquares(left, {{{0.5, 0}, {1, 0}, {1, 0.5}, {0.5, 0.5}}});
  EXPECT_EQ(lightmapUvs(touching)->origin, LightmapUvs::Origin::FileFirstSet);

  // Overlapping by a quarter texel's width: said, and generated instead.
  const double d = 0.25 / 1024;
  const Scene overlapping = twoSquares(left, {{{0.5 - d, 0}, {1, 0}, {1, 0.5}, {0.5 - d, 0.5}}});
  Result<LightmapUvs> rejected = lightmapUvs(overlapping);
  ASSERT_TRUE(rejected.ok());
  EXPECT_EQ(rejected->origin, LightmapUvs::Origin::Generated);
  EXPECT_NE(rejected->note.find("surface 'right' overlaps surface 'left'"), std::string::npos) << rejected->note;
  expectValidLayout(overlapping, *rejected);
  // Outside [0, 1] (a tiling texture): said too.
  const Scene tiled = twoSquares(left, {{{0, 0}, {2, 0}, {2, 2}, {0, 2}}});
  Result<LightmapUvs> outside = lightmapUvs(tiled);
  EXPECT_EQ(outside->origin, LightmapUvs::Origin::Generated);
  EXPECT_NE(outside->note.find("outside [0, 1]"), std::string::npos) << outside->note;
  // Not asked for: generated.
  LightmapUvOptions options;
  options.useFileUvs = false;
  EXPECT_EQ(lightmapUvs(clean, options)->origin, LightmapUvs::Origin::Generated);
}

TEST(LightmapUvsTest, OverlapDetectionScalesToManyFaces) {
  // 200 × 200 squares (80 000 triangles) whose first set tiles [0, 1]² exactly: used as it is,
  // every face keeping its own coordinates, no texel centre covered twice and every one covered
  // once. Then one corner nudged over the next square: that one overlap among the 40 000 faces is
  // found (the check is a grid of the triangles' bounds, not all pairs), and the layout generated
  // instead passes every check a generated layout must (every face in a chart, no texel twice,
  // padding between the charts).
  Scene scene;
  scene.materials.push_back({"grey", Rgb::gray(0.5)});
  Surface s;
  s.name = "grid";
  const int n = 200;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) s.vertices.push_back({static_cast<double>(x), 0, static_cast<double>(-y)});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
      s.faces.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)});
      std::vector<Uv> uv;
      for (auto [i, j] : {std::pair{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}}) uv.push_back({i / double(n), j / double(n)});
      s.faceUvs.push_back(uv);
    }
  scene.surfaces.push_back(s);
  Result<LightmapUvs> clean = lightmapUvs(scene);
  ASSERT_TRUE(clean.ok());
  EXPECT_EQ(clean->origin, LightmapUvs::Origin::FileFirstSet) << clean->note;
  expectValidLayout(scene, *clean);
  EXPECT_NEAR(clean->efficiency, 1, 1e-9) << "the squares tile the atlas";
  std::size_t moved = 0;
  for (std::size_t f = 0; f < s.faceUvs.size(); ++f)
    for (std::size_t k = 0; k < 4; ++k)
      moved += std::fabs(clean->uv[0][f][k].u - s.faceUvs[f][k].u) > 1e-12 || std::fabs(clean->uv[0][f][k].v - s.faceUvs[f][k].v) > 1e-12;
  EXPECT_EQ(moved, 0u) << "corners moved off the file's coordinates";

  scene.surfaces[0].faceUvs[n * 100 + 100][1].u += 0.3 / n;  // one corner over the next square
  Result<LightmapUvs> folded = lightmapUvs(scene);
  ASSERT_TRUE(folded.ok());
  EXPECT_EQ(folded->origin, LightmapUvs::Origin::Generated);
  EXPECT_NE(folded->note.find("faces of surface 'grid' overlap one another"), std::string::npos) << folded->note;
  expectValidLayout(scene, *folded);
}

// A glTF of unit squares (one primitive, so one surface each) with the given TEXCOORD_1.
std::string writeSquaresGltf(const std::filesystem::path& dir, const std::vector<std::array<Uv, 4>>& lightmap) {
  std::vector<char> bin;
  auto put = [&](const void* data, std::size_t size) { bin.insert(bin.end(), static_cast<const char*>(data), static_cast<const char*>(data) + size); };
  const std::size_t n = lightmap.size();
  for (std::size_t q = 0; q < n; ++q)
    for (auto [x, y] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
      const float p[3] = {static_cast<float>(x + 2.0 * q), static_cast<float>(y), 0};
      put(p, sizeof p);
    }
  for (const auto& square : lightmap)
    for (const Uv& uv : square) {
      const float t[2] = {static_cast<float>(uv.u), static_cast<float>(uv.v)};
      put(t, sizeof t);
    }
  for (std::size_t q = 0; q < n; ++q)
    for (int k : {0, 1, 2, 0, 2, 3}) {
      const std::uint16_t i = static_cast<std::uint16_t>(4 * q + k);
      put(&i, 2);
    }
  testing::writeBytes(dir / "squares.bin", bin);
  const std::string path = (dir / "squares.gltf").string();
  const std::size_t positions = 48 * n, uvs = 32 * n, indices = 12 * n;
  std::ofstream(path) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"name": "squares", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_1": 1}, "indices": 2}]}],
    "buffers": [{"uri": "squares.bin", "byteLength": )" << positions + uvs + indices << R"(}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" << positions << R"(}, {"buffer": 0, "byteOffset": )" << positions
                     << R"(, "byteLength": )" << uvs << R"(}, {"buffer": 0, "byteOffset": )" << positions + uvs << R"(, "byteLength": )"
                     << indices << R"(}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" << 4 * n << R"(, "type": "VEC3", "min": [0, 0, 0], "max": [)" << 2 * n - 1
                     << R"(, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": )" << 4 * n << R"(, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": )" << 6 * n << R"(, "type": "SCALAR"}]})";
  return path;
}

// The corner's UV in the set at the position's corner of the square (squares are 2 units apart).
Uv fileUvAt(const Vec3& p, const std::vector<std::array<Uv, 4>>& lightmap) {
  const int q = static_cast<int>(std::floor(p.x / 2 + 0.25));
  const double x = p.x - 2 * q;
  const int corner = x < 0.5 ? (p.y < 0.5 ? 0 : 3) : (p.y < 0.5 ? 1 : 2);
  return lightmap[static_cast<std::size_t>(q)][static_cast<std::size_t>(corner)];
}

TEST(LightmapUvsTest, GltfTexcoord1IsReadAndUsed) {
  const std::filesystem::path dir = testing::scratchDirectory("lightmap_uvs", "texcoord1");
  const std::vector<std::array<Uv, 4>> halves = {{{{0, 0}, {0.5, 0}, {0.5, 1}, {0, 1}}}, {{{0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}}}};
  Result<Scene> scene = loadScene(writeSquaresGltf(dir, halves));
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces.size(), 2u);
  for (const Surface& s : scene->surfaces) {
    ASSERT_EQ(s.faceLightmapUvs.size(), s.faces.size()) << "TEXCOORD_1 read per face corner";
    EXPECT_TRUE(s.faceUvs.empty()) << "the untextured material reads no TEXCOORD_0";
  }
  Result<LightmapUvs> uvs = lightmapUvs(*scene);
  ASSERT_TRUE(uvs.ok());
  EXPECT_EQ(uvs->origin, LightmapUvs::Origin::FileLightmapSet) << uvs->note;
  EXPECT_EQ(uvs->numAtlases, 1);
  for (std::size_t s = 0; s < 2; ++s)
    for (std::size_t f = 0; f < scene->surfaces[s].faces.size(); ++f)
      for (std::size_t k = 0; k < scene->surfaces[s].faces[f].size(); ++k) {
        const Uv expected = fileUvAt(scene->surfaces[s].vertices[scene->surfaces[s].faces[f][k]], halves);
        EXPECT_EQ(uvs->uv[s][f][k], expected);
      }
  expectValidLayout(*scene, *uvs);
  // Unit squares over half the atlas's width each, in a 1024² atlas.
  EXPECT_NEAR(uvs->texelSize, 1 / 512.0 / std::sqrt(2.0), 1e-6);

  // The same square twice (a lightmap per object, as engines export them): two atlases.
  const std::vector<std::array<Uv, 4>> both = {{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}, {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  Result<Scene> twice = loadScene(writeSquaresGltf(dir, both));
  ASSERT_TRUE(twice.ok());
  Result<LightmapUvs> two = lightmapUvs(*twice);
  EXPECT_EQ(two->origin, LightmapUvs::Origin::FileLightmapSet);
  EXPECT_EQ(two->numAtlases, 2);
  EXPECT_NE(two->atlas[0][0], two->atlas[1][0]);
  expectValidLayout(*twice, *two);
  // By default the atlases together hold about one 1024² atlas's texels: two of 512², five of
  // 256² (not five of 1024², as Blender's Lightmap Pack per object gave a small room 5 mm texels).
  EXPECT_EQ(two->size, 512);
  const std::vector<std::array<Uv, 4>> five(5, std::array<Uv, 4>{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  Result<Scene> fiveTimes = loadScene(writeSquaresGltf(dir, five));
  ASSERT_TRUE(fiveTimes.ok());
  Result<LightmapUvs> fiveAtlases = lightmapUvs(*fiveTimes);
  EXPECT_EQ(fiveAtlases->numAtlases, 5);
  EXPECT_EQ(fiveAtlases->size, 256);
  // A texel size asked for is kept: 1/1024 of a unit square's width needs 1024². So is an atlas
  // size asked for each (the CLI's --lightmap-size: a tool packed its margins for it).
  LightmapUvOptions fine;
  fine.texelSize = 1.0 / 1024;
  EXPECT_EQ(lightmapUvs(*fiveTimes, fine)->size, 1024);
  LightmapUvOptions each;
  each.atlasSize = 512;
  each.fileSetsShareAtlas = false;
  EXPECT_EQ(lightmapUvs(*fiveTimes, each)->size, 512);

  // A square folded over its diagonal in the set: rejected, saying so, and generated.
  const std::vector<std::array<Uv, 4>> folded = {{{{0, 0}, {0.5, 0}, {0.5, 0.5}, {0.6, 0.2}}}};
  Result<Scene> fold = loadScene(writeSquaresGltf(dir, folded));
  ASSERT_TRUE(fold.ok());
  Result<LightmapUvs> generated = lightmapUvs(*fold);
  EXPECT_EQ(generated->origin, LightmapUvs::Origin::Generated);
  EXPECT_NE(generated->note.find("TEXCOORD_1"), std::string::npos) << generated->note;
  EXPECT_NE(generated->note.find("overlap"), std::string::npos) << generated->note;
  expectValidLayout(*fold, *generated);
}

TEST(LightmapUvsTest, SceneFileLightmapUvsAreRead) {
  const std::filesystem::path dir = testing::scratchDirectory("lightmap_uvs", "scene-file");
  const std::string path = (dir / "quad.json").string();
  std::ofstream(path) << R"({"version": 1, "materials": [{"name": "m"}], "surfaces": [
    {"name": "quad", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
     "lightmapUvs": [[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]]}]})";
  Result<Scene> scene = loadScene(path);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  ASSERT_EQ(scene->surfaces[0].faceLightmapUvs.size(), 1u);
  Result<LightmapUvs> uvs = lightmapUvs(*scene);
  EXPECT_EQ(uvs->origin, LightmapUvs::Origin::FileLightmapSet) << uvs->note;
  EXPECT_EQ(uvs->uv[0][0], (std::vector<Uv>{{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}}));
  // One per vertex, in [0, 1]: otherwise refused, naming the field.
  std::ofstream(path) << R"({"version": 1, "materials": [{"name": "m"}], "surfaces": [
    {"name": "quad", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "lightmapUvs": [[0, 0], [1, 0], [1, 1]]}]})";
  Result<Scene> wrong = loadScene(path);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("/surfaces/0/lightmapUvs"), std::string::npos) << wrong.error().message;
}

TEST(LightmapUvsTest, HundredThousandFaceBuilding) {
  BuildingOptions options;
  options.rooms = 64;
  options.faceSize = 0.25;
  Result<Scene> scene = generateBuilding(options);
  ASSERT_TRUE(scene.ok());
  std::size_t faces = 0;
  for (const Surface& s : scene->surfaces) faces += surfaceFaces(s).size();
  const auto start = std::chrono::steady_clock::now();
  Result<LightmapUvs> uvs = lightmapUvs(*scene);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(uvs.ok()) << uvs.error().message;
  std::printf("  building: %zu faces, %zu surfaces: %s in %.2f s\n", faces, scene->surfaces.size(), uvs->note.c_str(), seconds);
  expectShape(*scene, *uvs);
  EXPECT_EQ(texelsCoveredTwice(*uvs), 0u);
  const auto [lo, hi] = texelAreaRatios(*scene, *uvs);
  EXPECT_NEAR(lo, 1, 1e-6);
  EXPECT_NEAR(hi, 1, 1e-6);
}

}  // namespace
}  // namespace lambert
