// Lightmap texels with their places, for the accuracy benchmark (bench/accuracy_bench.py): the
// default method's solve of a scene, its lightmaps baked as `lambert solve --lightmaps` bakes
// them, and up to --texels covered texels, picked evenly through the atlases, written as a vertex
// file: the texel's point and normal on its face (where it was baked) and its irradiance E in W/m²
// in the radiance columns. bench/vertex_reference --irradiance traces the same points.
//
//   lightmap_texels --scene room.gltf [--sides one] [--texels 600] [--lightmap-size 256] -o texels.csv
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_common.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/engine/radiosity.h"
#include "lambert/io/vertices.h"
#include "lambert/load/scene_file.h"

using namespace lambert;

int main(int argc, char** argv) {
  std::string sceneName, output, sides = "file";
  std::size_t wanted = 600;
  int atlasSize = 256;
  double linkError = RadiosityOptions{}.hierarchical.links.linkError;
  CLI::App app{"lightmap_texels: lightmap texels of the default method's solve, with their points, as a vertex file of irradiance"};
  app.add_option("--scene", sceneName, "Scene file or built-in scene")->required();
  bench::addSidesOption(app, sides);
  app.add_option("--texels", wanted, "Covered texels to write, evenly through the atlases")->check(CLI::Range(1, 1 << 24))->capture_default_str();
  app.add_option("--lightmap-size", atlasSize, "Texels per side of the atlas (lambert's --lightmap-size; 1024 there): the texel "
                 "size follows, and a texel's value does not depend on it")
      ->check(CLI::Range(16, 16384))
      ->capture_default_str();
  app.add_option("--link-error", linkError, "The hierarchy's link error (lambert's --link-error)")->check(CLI::Range(1e-12, 1.0))->capture_default_str();
  app.add_option("-o,--output", output, "Vertex file to write (.csv or .ply)")->required();
  bench::parseOrExit(app, argc, argv);

  Result<Scene> scene = bench::loadSceneWithSides(sceneName, sides);
  if (!scene) {
    std::fprintf(stderr, "lightmap_texels: %s\n", scene.error().message.c_str());
    return 2;
  }
  RadiosityOptions options;
  options.formFactors.showProgress = false;
  options.hierarchical.links.linkError = linkError;
  Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(*scene, options);
  if (!engine) {
    std::fprintf(stderr, "lightmap_texels: %s\n", engine.error().message.c_str());
    return 2;
  }
  if (Result<SolveReport> solved = (*engine)->solve(); !solved) {
    std::fprintf(stderr, "lightmap_texels: %s\n", solved.error().message.c_str());
    return 1;
  }
  LightmapBakeOptions bake;
  bake.showProgress = false;
  bake.uvs.atlasSize = atlasSize;
  Result<BakedLightmaps> baked = bakeLightmaps((*engine)->solution(), bake);
  if (!baked) {
    std::fprintf(stderr, "lightmap_texels: %s\n", baked.error().message.c_str());
    return 1;
  }
  const LightmapTexels texels = lightmapTexels((*engine)->solution().scene(), baked->uvs);
  const std::size_t step = std::max<std::size_t>(1, texels.points.size() / wanted);
  std::vector<VertexSample> out;
  for (std::size_t i = 0; i < texels.points.size() && out.size() < wanted; i += step) {
    const Image& atlas = baked->irradiance[texels.atlas[i]];
    const std::size_t t = texels.texel[i];
    out.push_back({texels.points[i].point, texels.points[i].normal, atlas.pixels[t]});
  }
  if (Status written = writeVertices(output, out); !written) {
    std::fprintf(stderr, "lightmap_texels: %s\n", written.error().message.c_str());
    return 1;
  }
  std::printf("{\"texels\": %zu, \"written\": %zu, \"atlases\": %zu}\n", texels.points.size(), out.size(), baked->irradiance.size());
  return 0;
}
