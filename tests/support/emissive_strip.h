#pragma once
// An emitter whose emission texture is half white, half black, for the loaders' emission texture
// tests (glTF emissiveTexture, MTL map_Ke, scene-file emissionTexture): the strip
// x ∈ [0, 2], y ∈ [0, 1] of the plane z = 0, facing +z, made of two unit squares (four
// triangles), with u = x / 2, under a 64 × 64 texture whose columns u < 1/2 are white (sRGB 255,
// linear 1) and the rest black. Closed form: the left square emits π L_e × its area (1 m²), the
// right one nothing, so the strip emits π L_e per channel, whatever the mesh.
//
// Bilinear filtering (texture.h) blends the two halves within half a texel (1/128 in u, 1/64 in x)
// of u = 0, 1/2 and 1; its integral over the strip is still exactly the texels' mean, 1/2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <vector>

#include "lambert/engine/radiosity.h"
#include "lambert/io/png.h"
#include "lambert/scene/scene.h"
#include "tests/support/scenes.h"

namespace lambert::testing {

// Strip positions, triangles (counter-clockwise from +z) and u per vertex.
inline const Vec3 kStripPositions[6] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
inline const std::uint16_t kStripTriangles[12] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
inline double stripU(const Vec3& p) { return p.x / 2; }

inline void writeHalfWhitePng(const std::filesystem::path& path) {
  constexpr int kSize = 64;
  std::vector<std::uint8_t> rgb(kSize * kSize * 3, 0);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize / 2; ++x)
      for (int c = 0; c < 3; ++c) rgb[static_cast<std::size_t>((y * kSize + x) * 3 + c)] = 255;
  ASSERT_TRUE(writePng(path.string(), kSize, kSize, rgb).ok()) << path;
}

// For each mesh strategy: the patches' emitted power sums to π L_e (the closed form above) within
// 1%, patches wholly on the white half (clear of the blend) emit π L_e, and those wholly on the
// black half nothing. (Adaptive meshing needs surfaces that are single quads.)
inline void expectEmissionFollowsHalfWhiteTexture(const Scene& scene, Rgb radiance,
                                                  std::initializer_list<MeshStrategy> strategies = {MeshStrategy::Uniform,
                                                                                                    MeshStrategy::Hierarchical}) {
  const double blendX = 1.0 / 64 + 1e-9;
  for (MeshStrategy strategy : strategies) {
    SCOPED_TRACE(static_cast<int>(strategy));
    RadiosityOptions options;
    options.meshing = strategy;
    options.uniform.targetPatches = 256;
    Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(scene, options);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    const Mesh& mesh = (*engine)->solution().mesh();
    const std::vector<Rgb>& emitted = (*engine)->solution().emitted();
    ASSERT_EQ(emitted.size(), mesh.numPatches());
    Rgb power;
    std::size_t white = 0, black = 0;
    for (std::size_t i = 0; i < mesh.numPatches(); ++i) {
      power += emitted[i] * mesh.patches[i].area;
      double lo = INFINITY, hi = -INFINITY;
      for (const Vec3& corner : mesh.corners(i)) lo = std::fmin(lo, corner.x), hi = std::fmax(hi, corner.x);
      if (lo >= blendX && hi <= 1 - blendX) {
        ++white;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(emitted[i][c], kPi * radiance[c], 1e-9 * kPi * radiance[c]) << "patch " << i;
      } else if (lo >= 1 + blendX && hi <= 2 - blendX) {
        ++black;
        EXPECT_EQ(emitted[i].maxComponent(), 0) << "patch " << i;
      } else if (hi <= 1) {  // on the white half, touching the blend: some of the 16 samples per triangle in it
        for (int c = 0; c < 3; ++c) EXPECT_GT(emitted[i][c], 0.5 * kPi * radiance[c]) << "patch " << i;
      } else if (lo >= 1) {
        for (int c = 0; c < 3; ++c) EXPECT_LT(emitted[i][c], 0.5 * kPi * radiance[c]) << "patch " << i;
      }
    }
    // The hierarchy's leaves are the triangles, each touching the blend; the others resolve it.
    if (strategy != MeshStrategy::Hierarchical) {
      EXPECT_GT(white, 0u);
      EXPECT_GT(black, 0u);
    }
    for (int c = 0; c < 3; ++c) EXPECT_LT(relativeError(power[c], kPi * radiance[c]), 0.01) << "channel " << c;
    // The solve's power total reads the same emission (in watts of its luminance).
    ASSERT_TRUE((*engine)->solve({}).ok());
    const Stats stats = (*engine)->stats();
    EXPECT_LT(relativeError(std::get<double>(stats.find("emitted_watts")->value), kPi * radiance.luminance()), 0.01);
  }
}

}  // namespace lambert::testing
