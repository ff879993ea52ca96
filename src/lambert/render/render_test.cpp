#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <mutex>
#include <sstream>
#include <utility>
#include <vector>

#include "lambert/mesh/mesh.h"
#include "lambert/mesh/vertex_radiosity.h"
#include "lambert/render/camera.h"
#include "lambert/render/rasterizer.h"
#include "lambert/render/tonemap.h"
#include "lambert/scene/builtin.h"

namespace lambert {
namespace {

// A mesh from explicit triangles, with the derived patch fields filled in as mesh.cpp does.
struct MeshBuilder {
  Mesh mesh;

  std::uint32_t vertex(const Vec3& p, std::uint32_t surface = 0) {
    mesh.positions.push_back(p);
    mesh.vertexSurface.push_back(surface);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t surface = 0) {
    const std::uint32_t corners[3] = {a, b, c};
    mesh.patches.push_back(makePatch(mesh.positions, corners, surface));
  }
  // A quad a, b, c, d (counter-clockwise from the front) as triangles (a, b, c) and (a, c, d).
  void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, std::uint32_t surface = 0) {
    std::uint32_t ia = vertex(a, surface), ib = vertex(b, surface), ic = vertex(c, surface),
                  id = vertex(d, surface);
    triangle(ia, ib, ic, surface);
    triangle(ia, ic, id, surface);
  }
  // The same quad as one four-cornered patch.
  void quadPatch(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, std::uint32_t surface = 0) {
    const std::uint32_t corners[4] = {vertex(a, surface), vertex(b, surface), vertex(c, surface),
                                      vertex(d, surface)};
    mesh.patches.push_back(makePatch(mesh.positions, corners, surface));
  }
};

Camera lookingDownZ(double distance, double fov = 40) {
  return Camera{{0, 0, distance}, {0, 0, 0}, {0, 1, 0}, fov};
}

bool isBlack(const Rgb& c) { return c.r == 0 && c.g == 0 && c.b == 0; }

// ---------------------------------------------------------------------------------------------
// Camera

TEST(CameraTest, CornellTargetProjectsToImageCentre) {
  PinholeCamera camera(cornellBox().camera, 512, 512);
  auto centre = camera.project({278, 273, 0});
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->x, 256, 0.5);
  EXPECT_NEAR(centre->y, 256, 0.5);
  EXPECT_NEAR(centre->depth, 800, 1e-9);
}

TEST(CameraTest, CornellRedWallOnTheLeftGreenOnTheRight) {
  PinholeCamera camera(cornellBox().camera, 512, 512);
  auto red = camera.project({554, 274, 280});
  auto green = camera.project({0, 274, 280});
  ASSERT_TRUE(red);
  ASSERT_TRUE(green);
  EXPECT_LT(red->x, 200);
  EXPECT_GT(green->x, 312);
  // Up in the world is up in the image (smaller row).
  auto ceiling = camera.project({278, 548, 280});
  ASSERT_TRUE(ceiling);
  EXPECT_LT(ceiling->y, 100);
}

TEST(CameraTest, FieldOfViewSpansTheImage) {
  // A point on the upper edge of the vertical field of view lands on the top edge of the image,
  // and with a 2:1 image the horizontal edge is twice as far out.
  const double fov = 40, d = 10;
  PinholeCamera camera(lookingDownZ(d, fov), 200, 100);
  double h = d * std::tan(fov * kPi / 360);
  auto top = camera.project({0, h, 0});
  ASSERT_TRUE(top);
  EXPECT_NEAR(top->x, 100, 1e-9);
  EXPECT_NEAR(top->y, 0, 1e-9);
  auto right = camera.project({2 * h, 0, 0});
  ASSERT_TRUE(right);
  EXPECT_NEAR(right->x, 200, 1e-9);
  EXPECT_NEAR(right->y, 50, 1e-9);
}

TEST(CameraTest, PointsBehindTheEyeAreRejected) {
  PinholeCamera camera(cornellBox().camera, 512, 512);
  EXPECT_FALSE(camera.project({278, 273, -900}));
  EXPECT_FALSE(camera.project({278, 273, -800}));  // the eye itself
  EXPECT_FALSE(camera.project({0, 0, -1000}));
  EXPECT_TRUE(camera.project({278, 273, -790}));
}

TEST(CameraTest, DegenerateUpStillGivesAnOrthonormalBasis) {
  PinholeCamera camera(Camera{{0, 0, 0}, {0, 5, 0}, {0, 1, 0}, 40}, 64, 64);
  for (const Vec3& v : {camera.right, camera.up, camera.forward}) {
    EXPECT_NEAR(length(v), 1, 1e-12);
  }
  EXPECT_NEAR(dot(camera.right, camera.up), 0, 1e-12);
  EXPECT_NEAR(dot(camera.right, camera.forward), 0, 1e-12);
  EXPECT_NEAR(dot(camera.up, camera.forward), 0, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Vertex radiosity

TEST(RenderVertexRadiosityTest, AreaWeightedAverageOnOneSurface) {
  MeshBuilder b;
  std::uint32_t v0 = b.vertex({0, 0, 0}), v1 = b.vertex({1, 0, 0}), v2 = b.vertex({0, 1, 0}),
                v3 = b.vertex({3, 1, 0});
  b.triangle(v0, v1, v2);  // area 0.5
  b.triangle(v1, v3, v2);  // area 1.5
  ASSERT_NEAR(b.mesh.patches[0].area, 0.5, 1e-12);
  ASSERT_NEAR(b.mesh.patches[1].area, 1.5, 1e-12);
  Rgb first{1, 2, 3}, second{5, 6, 7};
  std::vector<Rgb> vertex = vertexRadiosity(b.mesh, {first, second});
  ASSERT_EQ(vertex.size(), 4u);
  Rgb shared = first * 0.25 + second * 0.75;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(vertex[v0][c], first[c], 1e-12);
    EXPECT_NEAR(vertex[v3][c], second[c], 1e-12);
    EXPECT_NEAR(vertex[v1][c], shared[c], 1e-12);
    EXPECT_NEAR(vertex[v2][c], shared[c], 1e-12);
  }
}

TEST(RenderVertexRadiosityTest, SurfacesMeetingAtACreaseDoNotMix) {
  // A floor and a wall meeting along the x axis, each with its own copies of the crease vertices.
  MeshBuilder b;
  b.quad({0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, 0);
  b.quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 1);
  Rgb floor{1, 1, 1}, wall{4, 0, 2};
  std::vector<Rgb> vertex = vertexRadiosity(b.mesh, {floor, floor, wall, wall});
  ASSERT_EQ(vertex.size(), 8u);
  for (std::size_t v = 0; v < 8; ++v) {
    EXPECT_EQ(vertex[v], b.mesh.vertexSurface[v] == 0 ? floor : wall) << "vertex " << v;
  }
}

TEST(RenderVertexRadiosityTest, UnusedVertexIsZero) {
  MeshBuilder b;
  b.quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  std::uint32_t loose = b.vertex({5, 5, 5});
  std::vector<Rgb> vertex = vertexRadiosity(b.mesh, {Rgb{1, 1, 1}, Rgb{1, 1, 1}});
  EXPECT_EQ(vertex[loose], Rgb{});
}

// ---------------------------------------------------------------------------------------------
// Rasterizer

TEST(RenderTest, UniformQuadFillingTheViewIsBOverPiEverywhere) {
  // The quad reaches far outside the view, so it is cut by the clip planes; its diagonal crosses
  // the whole image, so any crack along it would show as black.
  MeshBuilder b;
  b.quad({-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
  const Rgb radiosity{1, 2, 3};
  for (Shading shading : {Shading::Gouraud, Shading::Flat}) {
    for (int ss : {1, 2, 3}) {
      for (auto [w, h] : {std::pair{64, 64}, std::pair{37, 23}, std::pair{20, 50}}) {
        RenderOptions options{w, h, shading, ss};
        Image image = renderRadiance(lookingDownZ(5), b.mesh, {radiosity, radiosity}, options);
        ASSERT_EQ(image.width, w);
        ASSERT_EQ(image.height, h);
        ASSERT_EQ(image.pixels.size(), static_cast<std::size_t>(w) * h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
              ASSERT_NEAR(image.at(x, y)[c], radiosity[c] / kPi, 1e-9)
                  << "pixel " << x << "," << y << " ss " << ss << " size " << w << "x" << h;
      }
    }
  }
}

// RenderPark's own scripts stand cameras a few centimetres outside a room's wall, looking in (its
// hospital's eye is 4.5 cm in front of the corridor wall's outer face, which faces it). The near
// plane is a hundredth of the eye–target distance, as RenderPark clips: the wall there is not
// drawn, and the room beyond shows; with it drawn the picture was black.
TEST(RenderTest, AWallInsideTheNearPlaneDoesNotHideTheRoom) {
  MeshBuilder b;
  b.quad({-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, 0);  // the wall's outer face, toward the eye
  b.quad({-100, -100, -5}, {100, -100, -5}, {100, 100, -5}, {-100, 100, -5}, 1);  // the room's far wall
  const Camera camera{{0, 0, 0.045}, {0, 0, -10}, {0, 1, 0}, 40};
  EXPECT_GT(PinholeCamera(camera, 32, 32).nearDistance, 0.045);
  const Rgb lit{1, 1, 1};
  const Image image = renderRadiance(camera, b.mesh, {Rgb{}, Rgb{}, lit, lit}, RenderOptions{32, 32, Shading::Flat, 1});
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_NEAR(image.at(x, y).r, 1 / kPi, 1e-9) << "pixel " << x << "," << y;
}

// Maps pixel coordinates of a size×size image to the z = 0 plane seen by a lookingDownZ(10, …)
// camera, so tests can put vertices exactly on sample centres.
auto pixelToPlane(const Camera& camera, int size) {
  const double unitsPerPixel = 10 / PinholeCamera(camera, size, size).focalPixels;
  return [=](double px, double py) {
    return Vec3{(px - size / 2.0) * unitsPerPixel, (size / 2.0 - py) * unitsPerPixel, 0};
  };
}

TEST(RenderTest, EverySampleIsCoveredByExactlyOneTriangleOfAMesh) {
  // A grid whose vertices project exactly onto sample centres, so cell edges and diagonals run
  // through samples: the top-left rule must give each such sample to exactly one triangle.
  const int size = 16;
  const Camera camera = lookingDownZ(10, 30);
  auto world = pixelToPlane(camera, size);
  MeshBuilder grid;
  const int cells = 10;  // 2-pixel cells from -1.5 to 18.5 cover every sample
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      double x0 = -1.5 + 2 * i, y0 = -1.5 + 2 * j;
      // Counter-clockwise seen from the camera: pixel y runs down, world y up.
      std::uint32_t a = grid.vertex(world(x0, y0 + 2)), bb = grid.vertex(world(x0 + 2, y0 + 2)),
                    c = grid.vertex(world(x0 + 2, y0)), d = grid.vertex(world(x0, y0));
      if ((i + j) % 2 == 0) {
        grid.triangle(a, bb, c);
        grid.triangle(a, c, d);
      } else {
        grid.triangle(a, bb, d);
        grid.triangle(bb, c, d);
      }
    }
  }
  std::vector<int> coverage(size * size, 0);
  for (std::size_t t = 0; t < grid.mesh.numPatches(); ++t) {
    MeshBuilder single;
    auto corners = grid.mesh.corners(t);
    ASSERT_EQ(corners.size(), 3u);
    single.triangle(single.vertex(corners[0]), single.vertex(corners[1]), single.vertex(corners[2]));
    RenderOptions options{size, size, Shading::Flat, 1};
    Image image = renderRadiance(camera, single.mesh, {Rgb::gray(kPi)}, options);
    for (int i = 0; i < size * size; ++i) {
      if (!isBlack(image.pixels[i])) {
        EXPECT_NEAR(image.pixels[i].r, 1, 1e-12);
        ++coverage[i];
      }
    }
  }
  for (int i = 0; i < size * size; ++i) EXPECT_EQ(coverage[i], 1) << "pixel " << i % size << "," << i / size;
}

TEST(RenderTest, SamplesOnTopAndLeftEdgesAreInsideBottomAndRightOutside) {
  // A square whose edges run exactly through sample centres 0.5 and 4.5: the top-left rule keeps
  // the first row and column of samples on its edges and leaves the last ones to a neighbour.
  const int size = 8;
  const Camera camera = lookingDownZ(10, 30);
  auto world = pixelToPlane(camera, size);
  MeshBuilder b;
  b.quad(world(0.5, 4.5), world(4.5, 4.5), world(4.5, 0.5), world(0.5, 0.5));
  Image image = renderRadiance(camera, b.mesh, {Rgb::gray(kPi), Rgb::gray(kPi)}, {size, size, Shading::Flat, 1});
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) EXPECT_EQ(!isBlack(image.at(x, y)), x < 4 && y < 4) << x << "," << y;
}

// A unit quad in local (u, v) ∈ [-1, 1]², tilted back about the x axis, in front of the camera.
struct TiltedQuad {
  Vec3 origin{0, 0, -1}, uAxis{1, 0, 0}, vAxis{0, std::cos(1.2), -std::sin(1.2)};
  Vec3 at(double u, double v) const { return origin + uAxis * u + vAxis * v; }
  // The (u, v) where the ray through pixel (px, py) centre meets the quad's plane.
  std::pair<double, double> hit(const PinholeCamera& cam, double px, double py) const {
    Vec3 dir = cam.forward + cam.right * ((px - cam.width / 2.0) / cam.focalPixels) -
               cam.up * ((py - cam.height / 2.0) / cam.focalPixels);
    Vec3 n = cross(uAxis, vAxis);
    double t = dot(origin - cam.eye, n) / dot(dir, n);
    Vec3 p = cam.eye + dir * t - origin;
    return {dot(p, uAxis), dot(p, vAxis)};
  }
};

TEST(RenderTest, FlatAndGouraudOnTwoPatches) {
  // Triangles (0,1,2) with B = 1 and (0,2,3) with B = 3 of equal area: the shared corners 0 and 2
  // get 2, so Gouraud shading is the plane B = 2 + (v - u)/2 over the quad, which a perspective
  // view must reproduce (an affine screen-space interpolation would not).
  TiltedQuad quad;
  MeshBuilder b;
  b.quad(quad.at(-1, -1), quad.at(1, -1), quad.at(1, 1), quad.at(-1, 1));
  const std::vector<Rgb> radiosity{Rgb::gray(1), Rgb::gray(3)};
  const Camera camera{{0, 0, 1.5}, {0, 0, -1}, {0, 1, 0}, 60};
  const int size = 96;
  PinholeCamera pinhole(camera, size, size);
  Image flat = renderRadiance(camera, b.mesh, radiosity, {size, size, Shading::Flat, 1});
  Image gouraud = renderRadiance(camera, b.mesh, radiosity, {size, size, Shading::Gouraud, 1});

  int inFirst = 0, inSecond = 0, outside = 0;
  double maxAffineError = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      auto [u, v] = quad.hit(pinhole, x + 0.5, y + 0.5);
      bool inside = std::fabs(u) < 0.98 && std::fabs(v) < 0.98;
      bool clearlyOutside = std::fabs(u) > 1.02 || std::fabs(v) > 1.02;
      if (clearlyOutside) {
        EXPECT_TRUE(isBlack(flat.at(x, y)));
        EXPECT_TRUE(isBlack(gouraud.at(x, y)));
        ++outside;
      }
      if (!inside) continue;
      if (u - v > 0.02) {
        EXPECT_DOUBLE_EQ(flat.at(x, y).g, 1 / kPi);
        ++inFirst;
      } else if (v - u > 0.02) {
        EXPECT_DOUBLE_EQ(flat.at(x, y).g, 3 / kPi);
        ++inSecond;
      }
      double expected = (2 + 0.5 * (v - u)) / kPi;
      // Vertices are snapped to 1/256 pixel, which moves the interpolation by a little.
      EXPECT_NEAR(gouraud.at(x, y).g, expected, 2e-4) << x << "," << y;
      // v as an affine interpolation down the screen would have it, to make sure the view is
      // perspective enough for this test to tell the two apart.
      double nearRow = pinhole.project(quad.at(0, -1))->y, farRow = pinhole.project(quad.at(0, 1))->y;
      double affineV = -1 + 2 * ((y + 0.5) - nearRow) / (farRow - nearRow);
      maxAffineError = std::max(maxAffineError, std::fabs(affineV - v) * 0.5 / kPi);
    }
  }
  EXPECT_GT(inFirst, 300);
  EXPECT_GT(inSecond, 300);
  EXPECT_GT(outside, 300);
  EXPECT_GT(maxAffineError, 20 * 2e-4);  // in radiance, against the tolerance above
}

TEST(RenderTest, NearerTriangleOccludesFartherInEitherDrawOrder) {
  MeshBuilder nearFirst, farFirst;
  auto addNear = [](MeshBuilder& b) { b.quad({-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}); };
  auto addFar = [](MeshBuilder& b) { b.quad({-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0}); };
  addNear(nearFirst);
  addFar(nearFirst);
  addFar(farFirst);
  addNear(farFirst);
  const Rgb red{kPi, 0, 0}, green{0, kPi, 0};
  const RenderOptions options{64, 64, Shading::Flat, 2};
  Image a = renderRadiance(lookingDownZ(6), nearFirst.mesh, {red, red, green, green}, options);
  Image b = renderRadiance(lookingDownZ(6), farFirst.mesh, {green, green, red, red}, options);
  for (const Image* image : {&a, &b}) {
    EXPECT_NEAR(image->at(32, 32).r, 1, 1e-12);
    EXPECT_EQ(image->at(32, 32).g, 0);
    // The near quad spans ±1 at distance 4 (±14° of the 20° half-field), the far one ±3 at
    // distance 6 (±26.6°): a pixel at 17° sees the far quad only.
    int x = static_cast<int>(32 + 32 * std::tan(17 * kPi / 180) / std::tan(20 * kPi / 180));
    EXPECT_EQ(image->at(x, 32).r, 0);
    EXPECT_NEAR(image->at(x, 32).g, 1, 1e-12);
  }
  EXPECT_EQ(a.pixels, b.pixels);
}

// What a picture shows, known by construction: a quad in front of the camera, one wholly hidden
// behind it, one turned away, one outside the field of view, and the far quad's rim beyond the
// near one's.
TEST(VisiblePatchesTest, TheFrontsOfWhatTheCameraSeesAndNothingElse) {
  MeshBuilder b;
  b.quad({-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2});          // patches 0, 1: in front
  b.quad({-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0});  // 2, 3: hidden behind 0, 1
  b.quad({-3, -3, -1}, {3, -3, -1}, {3, 3, -1}, {-3, 3, -1});      // 4, 5: the far wall's rim shows
  b.quad({1.2, -0.2, 1}, {1.2, 0.2, 1}, {1.6, 0.2, 1}, {1.6, -0.2, 1});  // 6, 7: beside, but turned away
  b.quad({40, 40, 0}, {41, 40, 0}, {41, 41, 0}, {40, 41, 0});      // 8, 9: far outside the view
  const std::vector<std::uint8_t> seen = visiblePatches(lookingDownZ(6), b.mesh, {64, 64, Shading::Gouraud, 2});
  ASSERT_EQ(seen.size(), b.mesh.numPatches());
  EXPECT_EQ(seen, (std::vector<std::uint8_t>{1, 1, 0, 0, 1, 1, 0, 0, 0, 0}));
  // Turned toward the camera, the side quad is seen.
  MeshBuilder turned;
  turned.quad({1.2, -0.2, 1}, {1.6, -0.2, 1}, {1.6, 0.2, 1}, {1.2, 0.2, 1});
  EXPECT_EQ(visiblePatches(lookingDownZ(6), turned.mesh, {64, 64, Shading::Gouraud, 2}), (std::vector<std::uint8_t>{1, 1}));
}

// The patches the picture draws are those visiblePatches names: every patch it flags shows its
// own colour at some pixel of a flat image, and no other patch does (the mesh covers the view
// with 400 small quads at random depths, some hidden behind others).
TEST(VisiblePatchesTest, AgreesWithTheImageDrawnPatchByPatch) {
  MeshBuilder b;
  std::uint64_t state = 7;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 200; ++i) {
    const double x = uniform() * 4 - 2, y = uniform() * 4 - 2, z = uniform() * 2, s = 0.1 + 0.4 * uniform();
    b.quadPatch({x, y, z}, {x + s, y, z}, {x + s, y + s, z}, {x, y + s, z});
  }
  const RenderOptions options{48, 48, Shading::Flat, 1};
  std::vector<Rgb> id(b.mesh.numPatches());
  for (std::size_t i = 0; i < id.size(); ++i) id[i] = Rgb{kPi * static_cast<double>(i + 1), 0, 0};
  const Image image = renderRadiance(lookingDownZ(6), b.mesh, id, options);
  std::vector<std::uint8_t> drawn(b.mesh.numPatches(), 0);
  for (const Rgb& pixel : image.pixels)
    if (const long k = std::lround(pixel.r) - 1; k >= 0) drawn[static_cast<std::size_t>(k)] = 1;
  const std::vector<std::uint8_t> seen = visiblePatches(lookingDownZ(6), b.mesh, options);
  EXPECT_EQ(seen, drawn);
  const auto count = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 1));
  EXPECT_GT(count, 20u);
  EXPECT_LT(count, b.mesh.numPatches());  // some are hidden
}

TEST(RenderTest, BackFacesAreCulled) {
  MeshBuilder b;
  b.quad({-1, -1, 2}, {-1, 1, 2}, {1, 1, 2}, {1, -1, 2});  // wound clockwise from the camera
  b.quad({-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0});
  const Rgb white = Rgb::gray(kPi), grey = Rgb::gray(kPi / 2);
  Image image = renderRadiance(lookingDownZ(6), b.mesh, {white, white, grey, grey}, {64, 64, Shading::Gouraud, 1});
  EXPECT_NEAR(image.at(32, 32).r, 0.5, 1e-12);  // through the back face: the far quad
  EXPECT_NEAR(image.at(3, 32).r, 0.5, 1e-12);
}

TEST(RenderTest, TriangleReachingBehindTheEyeIsClipped) {
  // A floor triangle under a camera 1 unit up, with two corners behind the eye: it must cover the
  // bottom of the image, leave the top black, and produce no NaN or smear.
  MeshBuilder b;
  b.triangle(b.vertex({-10, 0, 10}), b.vertex({10, 0, 10}), b.vertex({0, 0, -100}));
  const Camera camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 40};
  for (int ss : {1, 2, 3}) {
    Image image = renderRadiance(camera, b.mesh, {Rgb{kPi, 2 * kPi, 0}}, {64, 48, Shading::Gouraud, ss});
    ASSERT_EQ(image.width, 64);
    ASSERT_EQ(image.height, 48);
    for (const Rgb& c : image.pixels)
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(c[k]));
    for (int x = 0; x < 64; ++x) {
      for (int y = 0; y < 24; ++y) ASSERT_TRUE(isBlack(image.at(x, y))) << x << "," << y;
      // The whole bottom row: the floor at distance 2.7 is 17 units wide there.
      EXPECT_NEAR(image.at(x, 47).r, 1, 1e-9) << x;
      EXPECT_NEAR(image.at(x, 47).g, 2, 1e-9) << x;
    }
    // The apex, 100 away and 1 below the eye, is 0.01 rad below the horizon, 0.66 of a row here:
    // the first row under the horizon is partly covered at most, the rows after it fully.
    EXPECT_LT(image.at(32, 24).r, 1 - 1e-3);
    EXPECT_NEAR(image.at(32, 26).r, 1, 1e-9);
  }
}

TEST(RenderTest, QuadWhoseDiagonalCrossesTheNearPlaneHasNoCrack) {
  // The floor quad's shared diagonal runs from behind the eye to far ahead; both triangles clip
  // it at the same point, so the rows the floor fills are lit without a gap.
  MeshBuilder b;
  b.quad({-10, 0, 10}, {10, 0, 10}, {10, 0, -100}, {-10, 0, -100});
  const Camera camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 40};
  for (Shading shading : {Shading::Gouraud, Shading::Flat}) {
    for (int ss : {1, 2, 3}) {
      Image image = renderRadiance(camera, b.mesh, {Rgb::gray(kPi), Rgb::gray(kPi)}, {64, 48, shading, ss});
      // Row r below the horizon sees the floor at f/(r - 24) ahead, where its ±10 sides are
      // ±10·(r - 24) pixels out: from row 28 on, wider than the image.
      for (int y = 28; y < 48; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_NEAR(image.at(x, y).r, 1, 1e-9) << x << "," << y << " ss " << ss;
      for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_TRUE(isBlack(image.at(x, y)));
    }
  }
}

TEST(RenderTest, GeometryEntirelyBehindTheEyeRendersBlack) {
  MeshBuilder b;
  b.quad({-1, -1, 10}, {1, -1, 10}, {1, 1, 10}, {-1, 1, 10});
  Image image = renderRadiance(lookingDownZ(5), b.mesh, {Rgb{1, 1, 1}, Rgb{1, 1, 1}}, {32, 32, Shading::Flat, 2});
  for (const Rgb& c : image.pixels) ASSERT_TRUE(isBlack(c));
}

TEST(RenderTest, CornellBoxRedWallLeftGreenWallRight) {
  Scene scene = cornellBox();
  Mesh mesh = subdivideScene(scene, 100.0);
  std::vector<Rgb> radiosity;
  for (const Patch& patch : mesh.patches) radiosity.push_back(scene.materials[scene.surfaces[patch.surface].material].albedo * kPi);
  Image image = renderRadiance(scene.camera, mesh, radiosity, {128, 128, Shading::Gouraud, 2});
  const Rgb left = image.at(8, 64), right = image.at(119, 64);
  EXPECT_NEAR(left.r, 0.63, 1e-9);
  EXPECT_NEAR(left.g, 0.065, 1e-9);
  EXPECT_NEAR(right.r, 0.14, 1e-9);
  EXPECT_NEAR(right.g, 0.45, 1e-9);
  // The open front: no patch covers the corners of the image outside the box.
  EXPECT_TRUE(isBlack(image.at(0, 0)));
  // Everything is lit somewhere in the middle (the back wall behind the blocks).
  EXPECT_FALSE(isBlack(image.at(64, 40)));
}

// ---------------------------------------------------------------------------------------------
// Direct light hook and per-vertex rendering

RenderOptions withDirect(RenderOptions options, DirectRadianceFn direct) {
  options.directRadiance = std::move(direct);
  return options;
}

// A hit the hook saw: where, and on which patch.
struct Hit {
  Vec3 position;
  std::uint32_t patch;
};

// Renders with a hook that records every call and adds nothing.
std::vector<Hit> recordHits(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& radiosity,
                            RenderOptions options, Image* image = nullptr) {
  std::mutex mutex;
  std::vector<Hit> hits;
  options.directRadiance = [&](const Vec3& position, std::uint32_t patch) {
    std::lock_guard lock(mutex);
    hits.push_back({position, patch});
    return Rgb{};
  };
  Image rendered = renderRadiance(camera, mesh, radiosity, options);
  if (image) *image = std::move(rendered);
  return hits;
}

// How far p lies off the patch's plane, and how far outside its footprint (0 inside).
std::pair<double, double> planeAndFootprintError(const Mesh& mesh, const Hit& hit) {
  const Patch& patch = mesh.patches[hit.patch];
  PatchCorners corners = mesh.corners(hit.patch);
  double offPlane = std::fabs(dot(hit.position - corners[0], patch.normal));
  double outside = 0;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    Vec3 edge = corners[(k + 1) % corners.size()] - corners[k];
    // Positive inside a counter-clockwise patch.
    double inside = dot(cross(edge, hit.position - corners[k]), patch.normal) / length(edge);
    outside = std::max(outside, -inside);
  }
  return {offPlane, outside};
}

TEST(RenderDirectTest, HookIsCalledOnceForEachCoveredFrontFacingSample) {
  // A front-facing floor behind a back face (culled), with background around both: with B = π
  // on the front patches each covered front sample adds 1/ss² to its pixel.
  MeshBuilder b;
  b.quad({-1.3, -0.7, 2}, {-1.3, 1.1, 2}, {0.9, 1.1, 2}, {0.9, -0.7, 2});  // clockwise: back face
  b.quad({-2.2, -1.9, 0}, {2.7, -1.6, 0}, {2.1, 2.3, 0}, {-2.5, 2.0, 0});
  const Rgb white = Rgb::gray(kPi);
  const std::vector<Rgb> radiosity{white, white, white, white};
  for (int ss : {1, 2}) {
    for (Shading shading : {Shading::Flat, Shading::Gouraud}) {
      const RenderOptions options{48, 40, shading, ss};
      Image plain = renderRadiance(lookingDownZ(6), b.mesh, radiosity, options);
      double covered = 0;
      int background = 0, partial = 0;
      for (const Rgb& c : plain.pixels) {
        covered += c.r * ss * ss;
        background += isBlack(c);
        partial += c.r > 1e-9 && c.r < 1 - 1e-9;
      }
      ASSERT_GT(background, 100);  // the background leaves black pixels
      if (ss > 1) {
        EXPECT_GT(partial, 20);
      }

      std::atomic<long> calls{0};
      Image lit = renderRadiance(lookingDownZ(6), b.mesh, radiosity, withDirect(options, [&](const Vec3& p, std::uint32_t patch) {
                                   ++calls;
                                   EXPECT_NEAR(p.z, 0, 1e-9);  // never on the back face at z = 2
                                   EXPECT_TRUE(patch == 2 || patch == 3) << patch;
                                   return Rgb{};
                                 }));
      EXPECT_EQ(calls.load(), std::lround(covered)) << "ss " << ss;
      EXPECT_GT(calls.load(), 200);
      EXPECT_EQ(lit.pixels, plain.pixels);  // adding nothing changes nothing
    }
  }
}

TEST(RenderDirectTest, PositionsLieOnThePatchPlaneInsideItsFootprint) {
  Scene scene = cornellBox();
  Mesh mesh = subdivideScene(scene, 40.0);
  const double diagonal = sceneDiagonal(scene);
  std::vector<Rgb> radiosity(mesh.numPatches(), Rgb::gray(1));
  Image image;
  std::vector<Hit> hits = recordHits(scene.camera, mesh, radiosity, {256, 256, Shading::Gouraud, 2}, &image);
  ASSERT_GT(hits.size(), 200000u);  // most of the 512² samples see the inside of the box
  double maxOffPlane = 0, maxOutside = 0;
  for (const Hit& hit : hits) {
    ASSERT_LT(hit.patch, mesh.numPatches());
    auto [offPlane, outside] = planeAndFootprintError(mesh, hit);
    maxOffPlane = std::max(maxOffPlane, offPlane);
    maxOutside = std::max(maxOutside, outside);
  }
  EXPECT_LT(maxOffPlane, 1e-6 * diagonal);
  // A covered sample is within the 1/512-sample vertex snapping of the patch.
  EXPECT_LT(maxOutside, 1e-4 * diagonal);
  std::ostringstream report;
  report << std::scientific << std::setprecision(2) << "off plane " << maxOffPlane / diagonal
         << ", outside " << maxOutside / diagonal << " of the scene diagonal";
  RecordProperty("max_position_error", report.str());
}

TEST(RenderDirectTest, PositionsOnAGrazingQuadPatchLieOnItsPlane) {
  // The tilted quad seen at a steep angle, as one four-cornered patch, and a floor running from
  // behind the eye to the far distance (clipped at the near plane): depth varies fast across
  // samples, the hardest case for reconstructing the position from the depth.
  TiltedQuad quad;
  MeshBuilder tilted, floor;
  tilted.quadPatch(quad.at(-1, -1), quad.at(1, -1), quad.at(1, 1), quad.at(-1, 1));
  floor.quadPatch({-10, 0, 10}, {10, 0, 10}, {10, 0, -100}, {-10, 0, -100});
  struct Case {
    const Mesh* mesh;
    Camera camera;
    double size;
  };
  for (const Case& c : {Case{&tilted.mesh, Camera{{0, 0, 1.5}, {0, 0, -1}, {0, 1, 0}, 60}, 2.0},
                        Case{&floor.mesh, Camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 40}, 100.0}}) {
    for (auto [w, h] : {std::pair{96, 64}, std::pair{64, 48}}) {
      for (int ss : {1, 2, 3}) {
        std::vector<Hit> hits = recordHits(c.camera, *c.mesh, {Rgb::gray(1)}, {w, h, Shading::Gouraud, ss});
        ASSERT_GT(hits.size(), 500u);
        for (const Hit& hit : hits) {
          ASSERT_EQ(hit.patch, 0u);
          auto [offPlane, outside] = planeAndFootprintError(*c.mesh, hit);
          ASSERT_LT(offPlane, 1e-6 * c.size);
          ASSERT_LT(outside, 1e-4 * c.size);
        }
      }
    }
  }
}

TEST(RenderDirectTest, ConstantHookAddsExactlyThatConstant) {
  const Rgb direct{0.25, 0.5, 4};
  // Every sample covered: each pixel gains exactly the constant.
  MeshBuilder full;
  full.quad({-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
  const Rgb radiosity{1, 2, 3};
  auto constant = [&](const Vec3&, std::uint32_t) { return direct; };
  for (Shading shading : {Shading::Gouraud, Shading::Flat}) {
    for (int ss : {1, 2, 3}) {
      Image image = renderRadiance(lookingDownZ(5), full.mesh, {radiosity, radiosity},
                                   withDirect({37, 23, shading, ss}, constant));
      for (const Rgb& c : image.pixels)
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(c[k], radiosity[k] / kPi + direct[k], 1e-12);
    }
  }
  // Partly covered pixels gain it in proportion to their covered samples.
  TiltedQuad quad;
  MeshBuilder tilted;
  tilted.quadPatch(quad.at(-1, -1), quad.at(1, -1), quad.at(1, 1), quad.at(-1, 1));
  const Camera camera{{0, 0, 1.5}, {0, 0, -1}, {0, 1, 0}, 60};
  for (int ss : {1, 2, 3}) {
    const RenderOptions options{64, 64, Shading::Flat, ss};
    Image coverage = renderRadiance(camera, tilted.mesh, {Rgb::gray(kPi)}, options);
    Image lit = renderRadiance(camera, tilted.mesh, {Rgb::gray(kPi)}, withDirect(options, constant));
    int partial = 0;
    for (std::size_t i = 0; i < lit.pixels.size(); ++i) {
      double fraction = coverage.pixels[i].r;
      partial += fraction > 0 && fraction < 1;
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(lit.pixels[i][k], fraction * (1 + direct[k]), 1e-12);
    }
    if (ss > 1) {
      EXPECT_GT(partial, 20);
    }
  }
}

TEST(RenderDirectTest, HookOfThePositionGivesItsGradient) {
  // A fronto-parallel plane lit by a hook that returns the point's x and y: the samples of a pixel
  // sit symmetrically about its centre, so each pixel gets the x and y there.
  const int size = 32;
  const Camera camera = lookingDownZ(10, 30);
  auto world = pixelToPlane(camera, size);
  MeshBuilder b;
  b.quad({-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
  for (int ss : {1, 2, 3}) {
    Image image = renderRadiance(camera, b.mesh, {Rgb{}, Rgb{}},
                                 withDirect({size, size, Shading::Gouraud, ss},
                                            [](const Vec3& p, std::uint32_t) { return Rgb{p.x, p.y, p.z}; }));
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        Vec3 expected = world(x + 0.5, y + 0.5);
        ASSERT_NEAR(image.at(x, y).r, expected.x, 1e-12) << x << "," << y << " ss " << ss;
        ASSERT_NEAR(image.at(x, y).g, expected.y, 1e-12) << x << "," << y << " ss " << ss;
        ASSERT_NEAR(image.at(x, y).b, 0, 1e-12);
      }
    }
  }
}

TEST(RenderVertexRadiosityTest, GivesRenderRadianceGouraudImageExactly) {
  Scene scene = cornellBox();
  Mesh mesh = subdivideScene(scene, 60.0);
  std::vector<Rgb> radiosity;
  for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
    const Patch& patch = mesh.patches[i];
    // Varies from patch to patch so the vertex averages are all different.
    radiosity.push_back(scene.materials[scene.surfaces[patch.surface].material].albedo * (1 + (i % 7) * 0.3) +
                        Rgb::gray(patch.centroid.y * 1e-3));
  }
  auto direct = [](const Vec3& p, std::uint32_t patch) { return Rgb{p.x * 1e-3, patch * 1e-4, 0.5}; };
  for (int ss : {1, 2}) {
    RenderOptions options{96, 80, Shading::Gouraud, ss};
    EXPECT_EQ(renderVertexRadiosity(scene.camera, mesh, vertexRadiosity(mesh, radiosity), options).pixels,
              renderRadiance(scene.camera, mesh, radiosity, options).pixels);
    options.directRadiance = direct;
    EXPECT_EQ(renderVertexRadiosity(scene.camera, mesh, vertexRadiosity(mesh, radiosity), options).pixels,
              renderRadiance(scene.camera, mesh, radiosity, options).pixels);
  }
}

TEST(RenderVertexRadiosityTest, FlatShowsEachPatchInTheMeanOfItsCorners) {
  MeshBuilder b;
  b.quad({-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0});
  const std::vector<Rgb> vertex{Rgb{1, 0, 0}, Rgb{0, 2, 0}, Rgb{0, 0, 3}, Rgb{4, 4, 4}};
  const RenderOptions options{32, 32, Shading::Flat, 2};
  Image image = renderVertexRadiosity(lookingDownZ(6), b.mesh, vertex, options);
  // Triangles (0, 1, 2) and (0, 2, 3): their mean radiosities as patch values.
  Image expected = renderRadiance(lookingDownZ(6), b.mesh,
                                  {(vertex[0] + vertex[1] + vertex[2]) / 3, (vertex[0] + vertex[2] + vertex[3]) / 3}, options);
  ASSERT_EQ(image.pixels.size(), expected.pixels.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(image.pixels[i][k], expected.pixels[i][k], 1e-14);
}

TEST(RenderTest, QuadPatchCoversTheSamePixelsAsItsTwoTriangles) {
  // A four-cornered patch is drawn as the fan (a, b, c), (a, c, d): exactly what the same quad
  // as two triangle patches gives, also where it is clipped at the near plane and the sides.
  TiltedQuad tilted;
  struct Case {
    std::array<Vec3, 4> corners;
    Camera camera;
  };
  const Case cases[] = {
      {{tilted.at(-1, -1), tilted.at(1, -1), tilted.at(1, 1), tilted.at(-1, 1)}, Camera{{0, 0, 1.5}, {0, 0, -1}, {0, 1, 0}, 60}},
      {{Vec3{-10, 0, 10}, {10, 0, 10}, {10, 0, -100}, {-10, 0, -100}}, Camera{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 40}},
      {{Vec3{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}}, lookingDownZ(5)},
  };
  for (const Case& c : cases) {
    MeshBuilder quad, split;
    quad.quadPatch(c.corners[0], c.corners[1], c.corners[2], c.corners[3]);
    split.quad(c.corners[0], c.corners[1], c.corners[2], c.corners[3]);
    ASSERT_EQ(quad.mesh.patches[0].numCorners, 4u);
    ASSERT_NEAR(quad.mesh.patches[0].area, split.mesh.patches[0].area + split.mesh.patches[1].area,
                1e-9 * quad.mesh.patches[0].area);
    for (int ss : {1, 2}) {
      RenderOptions options{64, 48, Shading::Flat, ss};
      Image one = renderRadiance(c.camera, quad.mesh, {Rgb::gray(kPi)}, options);
      Image two = renderRadiance(c.camera, split.mesh, {Rgb::gray(kPi), Rgb::gray(kPi)}, options);
      EXPECT_EQ(one.pixels, two.pixels);
      int covered = 0;
      for (const Rgb& p : one.pixels) covered += !isBlack(p);
      EXPECT_GT(covered, 300);
      // Gouraud from distinct corner values interpolates the same over both.
      options.shading = Shading::Gouraud;
      const std::vector<Rgb> vertex{Rgb{1, 0, 0}, Rgb{0, 2, 0}, Rgb{0, 0, 3}, Rgb{4, 4, 4}};
      EXPECT_EQ(renderVertexRadiosity(c.camera, quad.mesh, vertex, options).pixels,
                renderVertexRadiosity(c.camera, split.mesh, vertex, options).pixels);
      // The hook sees the quad's own patch index at the same points the split mesh gives.
      std::vector<Hit> quadHits = recordHits(c.camera, quad.mesh, {Rgb{}}, options);
      std::vector<Hit> splitHits = recordHits(c.camera, split.mesh, {Rgb{}, Rgb{}}, options);
      ASSERT_EQ(quadHits.size(), splitHits.size());
      for (const Hit& hit : quadHits) ASSERT_EQ(hit.patch, 0u);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Tone mapping

Image row(std::vector<Rgb> pixels) { return Image{static_cast<int>(pixels.size()), 1, std::move(pixels)}; }

TEST(ToneMapTest, KnownSrgbValues) {
  std::vector<std::uint8_t> out =
      toSrgb8(row({Rgb::gray(0), Rgb::gray(1), Rgb::gray(0.0031308), Rgb::gray(0.5), Rgb{0.5, 0, 1}}), 0);
  ASSERT_EQ(out.size(), 15u);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(out[3], 255);
  EXPECT_EQ(out[6], 10);  // 12.92 · 0.0031308 · 255 = 10.31
  EXPECT_EQ(out[9], 188);  // (1.055 · 0.5^(1/2.4) - 0.055) · 255 = 187.52
  // Channels stay in R, G, B order.
  EXPECT_EQ(out[12], 188);
  EXPECT_EQ(out[13], 0);
  EXPECT_EQ(out[14], 255);
}

TEST(ToneMapTest, TransferFunctionPieces) {
  EXPECT_NEAR(srgbEncode(0.001), 0.01292, 1e-12);  // the linear toe
  // The two pieces meet (to the precision of the published constants) at the threshold.
  EXPECT_NEAR(srgbEncode(0.0031308), 1.055 * std::pow(0.0031308, 1 / 2.4) - 0.055, 1e-7);
  EXPECT_NEAR(srgbEncode(0.2), 1.055 * std::pow(0.2, 1 / 2.4) - 0.055, 1e-15);
  EXPECT_NEAR(srgbEncode(1), 1, 1e-12);
}

TEST(ToneMapTest, ClampsOutOfRangeAndNonFinite) {
  std::vector<std::uint8_t> out =
      toSrgb8(row({Rgb{-1, 7, std::nan("")}, Rgb{1e300, -0.0, std::numeric_limits<double>::infinity()}}), 0);
  EXPECT_EQ(out, (std::vector<std::uint8_t>{0, 255, 0, 255, 0, 255}));
}

TEST(ToneMapTest, ExposureScalesBeforeTheCurve) {
  Image image = row({Rgb::gray(0.25), Rgb::gray(1), Rgb::gray(0.5)});
  std::vector<std::uint8_t> up = toSrgb8(image, 1);
  EXPECT_EQ(up[0], 188);  // 0.25 · 2 = 0.5
  EXPECT_EQ(up[3], 255);
  std::vector<std::uint8_t> down = toSrgb8(image, -1);
  EXPECT_EQ(down[3], 188);  // 1 / 2
  EXPECT_EQ(down[6], toSrgb8(row({Rgb::gray(0.25)}), 0)[0]);
  EXPECT_EQ(toSrgb8(image, 2)[0], 255);  // 0.25 · 4 = 1
}

TEST(ToneMapTest, LayoutIsRowMajorTopRowFirst) {
  Image image{2, 2, std::vector<Rgb>(4)};
  image.at(1, 0) = Rgb{1, 0, 0};
  image.at(0, 1) = Rgb{0, 1, 0};
  std::vector<std::uint8_t> out = toSrgb8(image, 0);
  ASSERT_EQ(out.size(), 12u);
  EXPECT_EQ(out[3], 255);  // (1, 0) red
  EXPECT_EQ(out[7], 255);  // (0, 1) green
  EXPECT_EQ(std::count(out.begin(), out.end(), 255), 2);
}

}  // namespace
}  // namespace lambert
