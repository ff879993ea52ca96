// Lightmap baking (bake/lightmaps.h) over UVs laid out here, so that the bake is tested apart from
// the chart generator: texels against the path tracer, seams, dilation, the flat method refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lambert/bake/lightmaps.h"
#include "lambert/core/parallel.h"
#include "lambert/engine/radiosity.h"
#include "lambert/geometry/coverage.h"
#include "lambert/reference/reference.h"
#include "lambert/scene/builtin.h"
#include "tests/support/engines.h"
#include "tests/support/scenes.h"

namespace lambert {
namespace {

using testing::solved;

// Each face of each surface in a cell of its own in one atlas: a grid of `cells` × `cells` cells
// of the atlas, the face's corners (3 or 4) at the cell's corners inset by `inset` texels.
LightmapUvs gridUvs(const Scene& scene, int size, int cells, double inset) {
  LightmapUvs uvs;
  uvs.size = size;
  uvs.numAtlases = 1;
  int cell = 0;
  const double step = static_cast<double>(size) / cells;
  for (const Surface& surface : scene.surfaces) {
    std::vector<std::vector<Uv>> perFace;
    for (const std::vector<std::uint32_t>& face : surfaceFaces(surface)) {
      const double x0 = (cell % cells) * step + inset, y0 = (cell / cells) * step + inset, x1 = x0 + step - 2 * inset,
                   y1 = y0 + step - 2 * inset;
      ++cell;
      const std::vector<Uv> square = {{x0 / size, y0 / size}, {x1 / size, y0 / size}, {x1 / size, y1 / size}, {x0 / size, y1 / size}};
      std::vector<Uv> corners;
      for (std::size_t k = 0; k < face.size(); ++k) corners.push_back(square[std::min<std::size_t>(k, 3)]);
      if (face.size() == 3) corners[2] = {(x0 + x1) / 2 / size, y1 / size};
      perFace.push_back(corners);
    }
    uvs.atlas.push_back(std::vector<std::uint16_t>(perFace.size(), 0));
    uvs.uv.push_back(std::move(perFace));
  }
  EXPECT_LE(cell, cells * cells);
  return uvs;
}

Result<BakedLightmaps> quietBake(const Radiosity& engine, const LightmapUvs& uvs) {
  LightmapBakeOptions options;
  options.showProgress = false;
  return bakeLightmaps(engine.solution(), uvs, options);
}

// Bilinear lookup with texel centres at (x + ½, y + ½) / size, clamped at the border.
Rgb bilinear(const Image& image, double u, double v) {
  const double x = u * image.width - 0.5, y = v * image.height - 0.5;
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, image.width - 2), y0 = std::clamp(static_cast<int>(std::floor(y)), 0, image.height - 2);
  const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
  return image.at(x0, y0) * ((1 - fx) * (1 - fy)) + image.at(x0 + 1, y0) * (fx * (1 - fy)) + image.at(x0, y0 + 1) * ((1 - fx) * fy) +
         image.at(x0 + 1, y0 + 1) * (fx * fy);
}

// The Cornell box's texels against the path tracer at the same points: E = π (L − L_e) / ρ from
// its outgoing radiance, green channel, at every 100th texel not under a block (1,000 samples
// each, the tracer's own noise about 2% a texel). Measured: bias −1.3%, relative RMSE 2.4%. The
// mean difference must stay within 3% and the RMSE within 4% (the lightmaps' accuracy target: 3%).
TEST(LightmapTest, CornellTexelsAgreeWithThePathTracer) {
  const Scene scene = cornellBox();
  auto engine = solved(scene);
  ASSERT_TRUE(engine);
  const LightmapUvs uvs = gridUvs(scene, 256, 4, 3);
  Result<BakedLightmaps> baked = quietBake(*engine, uvs);
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  const LightmapTexels texels = lightmapTexels(scene, uvs);
  ASSERT_EQ(texels.points.size(), baked->texelsBaked);
  ReferenceOptions traceOptions;
  traceOptions.vertexSamples = 1000;
  traceOptions.showProgress = false;
  const ReferenceRenderer tracer(scene, subdivideScene(scene, 2 * sceneDiagonal(scene)), traceOptions);
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < texels.points.size(); i += 100) {
    const SurfacePoint& p = texels.points[i];
    const Material& m = scene.materials[scene.surfaces[p.surface].material];
    if (scene.surfaces[p.surface].emittedRadiance.g > 0 || m.albedo.g < 0.2) continue;  // the lamp; the red wall's green
    // Under a block the floor shows nothing (its texels are never seen) while the bake keeps the
    // light of the leaf's open part there, for bilinear lookups at the block's foot.
    if (isCovered(engine->solution().caster(), p.point, p.normal, 1e-4 * sceneDiagonal(scene))) continue;
    chosen.push_back(i);
  }
  ASSERT_GT(chosen.size(), 300u);
  std::vector<double> traced(chosen.size()), baked_(chosen.size());
  parallelFor(0, chosen.size(), [&](std::size_t k) {
    const std::size_t i = chosen[k];
    const SurfacePoint& p = texels.points[i];
    const Surface& surface = scene.surfaces[p.surface];
    const double albedo = scene.materials[surface.material].albedo.g;
    const Rgb radiance = tracer.outgoingRadiance(p.point, p.normal, p.surface, i);
    traced[k] = kPi * (radiance.g - surface.emittedRadiance.g) / albedo;
    baked_[k] = baked->irradiance[texels.atlas[i]].pixels[texels.texel[i]].g;
  });
  double bias = 0, squares = 0, mean = 0;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    bias += (baked_[k] - traced[k]) / chosen.size();
    squares += (baked_[k] - traced[k]) * (baked_[k] - traced[k]) / chosen.size();
    mean += traced[k] / chosen.size();
  }
  std::printf("%zu texels: bias %+.2f%%, relative RMSE %.2f%% of the mean irradiance\n", chosen.size(), 100 * bias / mean,
              100 * std::sqrt(squares) / mean);
  EXPECT_LT(std::fabs(bias / mean), 0.03);
  EXPECT_LT(std::sqrt(squares) / mean, 0.04);
}

// The adaptive lattice (bake/adaptive_texels.h) against the same bake with every texel gathered,
// on the Cornell box in charts of about 60 × 60 texels: the blocks' contact shadows, the room's
// corner lines and the lamp's penumbrae are what it must not interpolate away. A point's rays are
// drawn from its place, so a texel gathered in both bakes has one value and the difference is the
// interpolation's alone. Measured: 35% of the texels gathered, RMSE 0.53% of the mean
// irradiance, the worst texel 6.3% of the mean.
TEST(LightmapTest, AnAdaptiveBakeAgreesWithEveryTexelGathered) {
  const Scene scene = cornellBox();
  auto engine = solved(scene);
  ASSERT_TRUE(engine);
  const LightmapUvs uvs = gridUvs(scene, 256, 4, 3);
  LightmapBakeOptions every;
  every.showProgress = false;
  every.sampling.coarsestStep = 1;
  Result<BakedLightmaps> exact = bakeLightmaps(engine->solution(), uvs, every);
  Result<BakedLightmaps> adaptive = quietBake(*engine, uvs);
  ASSERT_TRUE(exact.ok() && adaptive.ok());
  EXPECT_EQ(exact->texelsGathered, exact->texelsBaked);
  double mean = 0, squares = 0, worst = 0;
  std::size_t n = 0;
  for (std::size_t t = 0; t < exact->irradiance[0].pixels.size(); ++t)
    if (exact->covered[0][t]) mean += exact->irradiance[0].pixels[t].g, ++n;
  mean /= static_cast<double>(n);
  for (std::size_t t = 0; t < exact->irradiance[0].pixels.size(); ++t) {
    if (!exact->covered[0][t]) continue;
    const double d = adaptive->irradiance[0].pixels[t].g - exact->irradiance[0].pixels[t].g;
    squares += d * d;
    worst = std::fmax(worst, std::fabs(d));
  }
  const double rmse = std::sqrt(squares / static_cast<double>(n)) / mean;
  std::printf("%zu of %zu texels gathered; RMSE %.3f%%, worst %.2f%% of the mean\n", adaptive->texelsGathered, adaptive->texelsBaked,
              100 * rmse, 100 * worst / mean);
  EXPECT_LT(adaptive->texelsGathered, adaptive->texelsBaked / 2);
  EXPECT_LT(rmse, 0.01);
  EXPECT_LT(worst / mean, 0.15);
}

// A floor of two faces placed apart in the atlas, lit by a point light over their shared edge:
// the light changes across every texel, so each side's own texels differ along the seam; stitched,
// bilinear lookups on the two sides of the edge agree within 1%, and with the irradiance there,
// I h / r³ (a lone plane: no other light), as closely as a read between texel centres can. Twice:
// charts whose edges lie on texel boundaries under a light 0.5 m up, and charts placed 0.37 of a
// texel off them (as Blender's Lightmap Pack places its islands) under a light 0.1 m up, whose
// pool of light is four texels wide. Unstitched, the two sides' reads differ by up to 0.36% and
// 3.9% (the texel centres lie at other distances from the edge on the two sides); stitched, by
// 0.002% and 0.01%, within 0.08% and 1.4% of I h / r³.
TEST(LightmapTest, SeamsAreStitched) {
  struct Case {
    double inset, height;
  };
  for (const Case& c : {Case{4, 0.5}, Case{2.37, 0.1}}) {
    SCOPED_TRACE("inset " + std::to_string(c.inset) + " texels, light " + std::to_string(c.height) + " m up");
    Surface floor{"floor", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 1}, {1, 0, 1}, {0, 0, 1}}, 0, {}};
    floor.faces = {{0, 5, 4, 1}, {1, 4, 3, 2}};
    Scene scene = testing::sceneOf({floor}, Rgb::gray(0.5));
    Light light;
    light.kind = LightKind::Point;
    light.position = {0.97, c.height, 0.5};
    light.intensity = Rgb::gray(1);
    scene.lights = {light};
    auto engine = solved(scene);
    ASSERT_TRUE(engine);
    const LightmapUvs uvs = gridUvs(scene, 128, 2, c.inset);
    Result<BakedLightmaps> baked = quietBake(*engine, uvs);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    // The shared edge is vertices 1 → 4, (1, 0, 0) → (1, 0, 1): corners 3 → 2 of face 0 and 0 → 1
    // of face 1.
    const std::vector<Uv>& a = uvs.uv[0][0];
    const std::vector<Uv>& b = uvs.uv[0][1];
    double worstStep = 0, worstExact = 0;
    for (int i = 1; i < 40; ++i) {
      const double t = i / 40.0;
      const Rgb sa = bilinear(baked->irradiance[0], a[3].u + (a[2].u - a[3].u) * t, a[3].v + (a[2].v - a[3].v) * t);
      const Rgb sb = bilinear(baked->irradiance[0], b[0].u + (b[1].u - b[0].u) * t, b[0].v + (b[1].v - b[0].v) * t);
      worstStep = std::fmax(worstStep, std::fabs(sa.g - sb.g) / std::fmax(sa.g, sb.g));
      const double r = std::sqrt(0.03 * 0.03 + c.height * c.height + (t - 0.5) * (t - 0.5));
      const double exact = c.height / (r * r * r);
      worstExact = std::fmax(worstExact, std::fabs(0.5 * (sa.g + sb.g) - exact) / exact);
    }
    std::printf("inset %.2f, light %.1f m up: largest step across the seam %.3f%%, largest difference from I h / r^3 %.2f%%\n",
                c.inset, c.height, 100 * worstStep, 100 * worstExact);
    EXPECT_LT(worstStep, 0.01);
    EXPECT_LT(worstExact, c.height > 0.2 ? 0.01 : 0.06);
  }
}

// Texels around a chart that no face covers take their neighbours' light (dilation), and those
// far from every chart stay empty.
TEST(LightmapTest, PaddingIsDilatedFromTheChart) {
  const Scene scene = testing::closedCube(1, Rgb::gray(1), Rgb::gray(0.5));
  auto engine = solved(scene);
  ASSERT_TRUE(engine);
  const LightmapUvs uvs = gridUvs(scene, 64, 4, 4);
  Result<BakedLightmaps> baked = quietBake(*engine, uvs);
  ASSERT_TRUE(baked.ok()) << baked.error().message;
  const Image& image = baked->irradiance[0];
  const auto& covered = baked->covered[0];
  // The first cell's chart spans texels 4 to 11; texels 2 and 3 are padding next to it.
  EXPECT_FALSE(covered[2 * 64 + 6]);
  EXPECT_GT(image.at(6, 2).g, 0.5 * image.at(6, 5).g);
  EXPECT_NEAR(image.at(6, 3).g, image.at(6, 4).g, 0.2 * image.at(6, 4).g);
  // A cell no face uses (the cube has 6 faces of 16 cells) stays dark in its middle.
  EXPECT_EQ(image.at(56, 56).g, 0.0);
}

TEST(LightmapTest, TheFlatMethodIsRefusedWithTheReason) {
  const Scene scene = testing::closedCube(1, Rgb::gray(1), Rgb::gray(0.5));
  auto engine = solved(scene, testing::uniformOptions(96));
  ASSERT_TRUE(engine);
  Result<BakedLightmaps> baked = bakeLightmaps(engine->solution(), gridUvs(scene, 64, 4, 4));
  ASSERT_FALSE(baked.ok());
  EXPECT_NE(baked.error().message.find("hierarchical"), std::string::npos) << baked.error().message;
}

}  // namespace
}  // namespace lambert
