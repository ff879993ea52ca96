#include "lambert/render/lightmap_image.h"

#include <gtest/gtest.h>

#include <cmath>

#include "lambert/render/camera.h"

namespace lambert {
namespace {

constexpr int kAtlas = 8;

// E at texel (x, y), linear in the texel's position, so that bilinear filtering reproduces the
// same linear function between texel centres: E at filter position (px, py) (texel units, centres
// at integers) is this of (px, py).
Rgb linearIrradiance(double px, double py) { return Rgb{1 + px + 2 * py, 2 + 0.5 * px, 3 + py}; }

Image linearAtlas() {
  Image atlas{kAtlas, kAtlas, std::vector<Rgb>(kAtlas * kAtlas)};
  for (int y = 0; y < kAtlas; ++y)
    for (int x = 0; x < kAtlas; ++x) atlas.at(x, y) = linearIrradiance(x, y);
  return atlas;
}

TEST(LightmapImageTest, SampleIsBilinearBetweenTexelCentresAndClampsToTheEdge) {
  const Image atlas = linearAtlas();
  // Inside: (u, v) · size − ½ is the position between centres.
  for (const Uv uv : {Uv{0.5, 0.5}, Uv{0.1, 0.8}, Uv{0.33, 0.07}, Uv{0.9, 0.9}}) {
    const Rgb expected = linearIrradiance(uv.u * kAtlas - 0.5, uv.v * kAtlas - 0.5);
    const Rgb got = sampleLightmap(atlas, uv);
    EXPECT_NEAR(got.r, expected.r, 1e-12);
    EXPECT_NEAR(got.g, expected.g, 1e-12);
    EXPECT_NEAR(got.b, expected.b, 1e-12);
  }
  // Within half a texel of the edge, and beyond it, the edge texels (CLAMP_TO_EDGE).
  EXPECT_EQ(sampleLightmap(atlas, {0.0, 0.0}).r, atlas.at(0, 0).r);
  EXPECT_EQ(sampleLightmap(atlas, {1.0, 1.0}).r, atlas.at(kAtlas - 1, kAtlas - 1).r);
  EXPECT_EQ(sampleLightmap(atlas, {-3.0, 0.5 / kAtlas}).r, atlas.at(0, 0).r);
  EXPECT_EQ(sampleLightmap(atlas, {NAN, INFINITY}).r, atlas.at(0, 0).r);
}

// One square face of half-side 1 in the plane through the origin with normal n (front +n), its
// lightmap coordinates glTF-style over the whole atlas: corner (s, t) ∈ {±1}² at
// u = (s + 1)/2, v = (1 − t)/2 (t up, v down).
struct SquareScene {
  Scene scene;
  BakedLightmaps baked;
  Vec3 sAxis, tAxis;

  SquareScene(double tiltRadians, const Rgb& albedo, const Rgb& emitted) {
    sAxis = {std::cos(tiltRadians), 0, -std::sin(tiltRadians)};
    tAxis = {0, 1, 0};
    scene.materials.push_back(Material{"grey", albedo});
    Surface surface;
    surface.name = "square";
    surface.emittedRadiance = emitted;
    std::vector<Uv> uvs;
    for (const auto& [s, t] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}) {
      surface.vertices.push_back(sAxis * s + tAxis * t);
      uvs.push_back({(s + 1) / 2, (1 - t) / 2});
    }
    scene.surfaces.push_back(surface);
    baked.uvs.size = kAtlas;
    baked.uvs.numAtlases = 1;
    baked.uvs.uv = {{uvs}};
    baked.uvs.atlas = {{0}};
    baked.irradiance = {linearAtlas()};
  }
  // The radiance a client draws at the face point (s, t): ρ/π · E(u, v) + L_e.
  Rgb radianceAt(double s, double t) const {
    const double u = (s + 1) / 2, v = (1 - t) / 2;
    return scene.surfaces[0].emittedRadiance + scene.materials[0].albedo * linearIrradiance(u * kAtlas - 0.5, v * kAtlas - 0.5) / kPi;
  }
};

// Every pixel whose centre ray meets the face well inside (where the filter is linear) shows the
// radiance at the point it meets, found here by intersecting the ray with the plane: so the
// coordinates are interpolated perspective-correctly across a face seen at a slant.
TEST(LightmapImageTest, EachPixelShowsAlbedoOverPiTimesTheIrradianceAtThePointItSees) {
  const SquareScene square(0.9, Rgb{0.5, 0.6, 0.7}, Rgb{});
  const Camera camera{{0.3, 0.2, 3}, {0, 0, 0}, {0, 1, 0}, 50};
  LightmapImageOptions options;
  options.width = 64;
  options.height = 48;
  options.supersample = 1;
  const Image image = renderLightmapped(square.scene, square.baked, camera, options);
  const PinholeCamera pinhole(camera, options.width, options.height);
  const Vec3 normal = cross(square.sAxis, square.tAxis);
  int checked = 0;
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      const Vec3 ray = pinhole.forward + pinhole.right * ((x + 0.5 - 0.5 * options.width) / pinhole.focalPixels) -
                       pinhole.up * ((y + 0.5 - 0.5 * options.height) / pinhole.focalPixels);
      const Vec3 hit = pinhole.eye + ray * (-dot(pinhole.eye, normal) / dot(ray, normal));
      const double s = dot(hit, square.sAxis), t = dot(hit, square.tAxis);
      if (std::fabs(s) > 0.8 || std::fabs(t) > 0.8) continue;  // near the rim, or off the face
      const Rgb expected = square.radianceAt(s, t), got = image.at(x, y);
      EXPECT_NEAR(got.r, expected.r, 1e-9 * expected.r) << x << ", " << y;
      EXPECT_NEAR(got.g, expected.g, 1e-9 * expected.g) << x << ", " << y;
      EXPECT_NEAR(got.b, expected.b, 1e-9 * expected.b) << x << ", " << y;
      ++checked;
    }
  EXPECT_GT(checked, 300);
  EXPECT_EQ(image.at(0, 0).r, 0.0);  // the background
}

TEST(LightmapImageTest, EmissionAddsAndTheBackIsNotDrawn) {
  const SquareScene square(0, Rgb{0.5, 0.5, 0.5}, Rgb{2, 3, 4});
  LightmapImageOptions options;
  options.width = options.height = 33;  // pixel 16's centre is on the view axis
  options.supersample = 1;
  const Image front = renderLightmapped(square.scene, square.baked, Camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40}, options);
  const Rgb expected = square.radianceAt(0, 0);
  EXPECT_NEAR(front.at(16, 16).g, expected.g, 1e-12);
  EXPECT_NEAR(front.at(16, 16).b, 4 + 0.5 / kPi * linearIrradiance(3.5, 3.5).b, 1e-12);
  const Image back = renderLightmapped(square.scene, square.baked, Camera{{0, 0, -4}, {0, 0, 0}, {0, 1, 0}, 40}, options);
  for (const Rgb& p : back.pixels) EXPECT_EQ(p.r + p.g + p.b, 0.0);
}

}  // namespace
}  // namespace lambert
