// Lightmap atlases (mesh/lightmap_uvs.h) of the shipped scenes and of any other scenes named:
// per scene and atlas size, where the coordinates come from, the charts, the atlases, the
// packing efficiency (texels whose centre a face covers / atlas texels) and the time. The
// issue's target (≥ 70% on the shipped scenes, at the default 1024² atlas) is judged on the
// shipped ones only; third-party scenes of many small objects are reported beside them (each
// chart, however small, takes its padding ring). Prints one JSON document on stdout.
//
//   atlas_bench [--sizes 1024,256] [--padding 2] [--only-named] [SCENE ...]   (names or paths, as --scene takes)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/core/timer.h"
#include "lambert/mesh/lightmap_uvs.h"
#include "lambert/scene/builtin.h"
#include "lambert/load/scene_file.h"

using namespace lambert;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kTargetEfficiency = 0.70;

// The built-in scenes and every scene file under scenes/ (a folder's .json files, else its one
// scene file).
std::vector<std::string> shippedScenes() {
  std::vector<std::string> scenes = builtinSceneNames();
#ifdef LAMBERT_SOURCE_DIR
  const std::filesystem::path root = LAMBERT_SOURCE_DIR "/scenes";
#else
  const std::filesystem::path root = "scenes";
#endif
  std::vector<std::filesystem::path> folders;
  for (const auto& entry : std::filesystem::directory_iterator(root))
    if (entry.is_directory()) folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  for (const auto& folder : folders) {
    std::vector<std::string> json, other;
    for (const auto& file : std::filesystem::directory_iterator(folder)) {
      const std::string ext = file.path().extension().string();
      if (ext == ".json") json.push_back(file.path().string());
      if (ext == ".gltf" || ext == ".glb") other.push_back(file.path().string());
    }
    std::vector<std::string>& chosen = json.empty() ? other : json;
    std::sort(chosen.begin(), chosen.end());
    scenes.insert(scenes.end(), chosen.begin(), chosen.end());
  }
  return scenes;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  int padding = LightmapUvOptions{}.paddingTexels;
  std::vector<std::string> others;
  bool onlyNamed = false;
  CLI::App app{"atlas_bench: lightmap atlas packing of the shipped scenes (and others named), as JSON"};
  std::string sizeList = "1024,256";
  app.add_option("--sizes", sizeList, "Atlas sizes (texels per side, comma-separated) to pack at, the default texel size for each");
  app.add_option("--padding", padding, "Texels between charts")->check(CLI::Range(0, 64));
  app.add_option("scenes", others, "Further scenes (built-in names or paths), reported but not judged");
  app.add_flag("--only-named", onlyNamed, "Pack only the scenes named, not the shipped ones (no target is judged then)");
  bench::parseOrExit(app, argc, argv);
  sizes.clear();
  for (std::size_t start = 0; start <= sizeList.size();) {
    const std::size_t comma = std::min(sizeList.find(',', start), sizeList.size());
    try {
      sizes.push_back(std::stoi(sizeList.substr(start, comma - start)));
    } catch (const std::exception&) {
      std::fprintf(stderr, "atlas_bench: --sizes %s: give texel counts separated by commas, e.g. 1024,256\n", sizeList.c_str());
      return 2;
    }
    if (sizes.back() < 1 || sizes.back() > 16384) {
      std::fprintf(stderr, "atlas_bench: --sizes: %d is not an atlas size from 1 to 16384\n", sizes.back());
      return 2;
    }
    start = comma + 1;
  }

  Json rows = Json::array();
  bool met = true;
  double worstShipped = 1;
  const std::vector<std::string> shipped = onlyNamed ? std::vector<std::string>{} : shippedScenes();
  std::vector<std::pair<std::string, bool>> all;
  for (const std::string& s : shipped) all.push_back({s, true});
  for (const std::string& s : others) all.push_back({s, false});
  for (const auto& [name, isShipped] : all) {
    std::fprintf(stderr, "atlas_bench: %s\n", name.c_str());
    Result<Scene> scene = loadScene(name);
    if (!scene) {
      std::fprintf(stderr, "atlas_bench: %s: %s\n", name.c_str(), scene.error().message.c_str());
      rows.push_back({{"scene", name}, {"shipped", isShipped}, {"error", scene.error().message}});
      if (isShipped) met = false;
      continue;
    }
    std::size_t faces = 0;
    for (const Surface& surface : scene->surfaces) faces += surfaceFaces(surface).size();
    for (int size : sizes) {
      LightmapUvOptions options;
      options.atlasSize = size;
      options.paddingTexels = padding;
      Timer timer;
      Result<LightmapUvs> uvs = lightmapUvs(*scene, options);
      const double seconds = timer.seconds();
      Json row{{"scene", name}, {"shipped", isShipped}, {"faces", faces}, {"surfaces", scene->surfaces.size()}, {"atlas_size", size}};
      if (!uvs) {
        row["error"] = uvs.error().message;
        if (isShipped) met = false;
      } else {
        row["origin"] = uvs->origin == LightmapUvs::Origin::Generated ? "generated" : "file";
        row["charts"] = uvs->charts;
        row["atlases"] = uvs->numAtlases;
        row["texel_size"] = uvs->texelSize;
        row["efficiency"] = bench::roundDigits(uvs->efficiency, 4);
        row["seconds"] = bench::seconds(seconds);
        if (isShipped && size == 1024) {
          worstShipped = std::min(worstShipped, uvs->efficiency);
          if (uvs->efficiency < kTargetEfficiency) met = false;
        }
      }
      rows.push_back(row);
    }
  }
  Json out{{"machine", bench::cpuModel()},
           {"threads", std::thread::hardware_concurrency()},
           {"date", bench::utcNow()},
           {"build", bench::buildDescription()},
           {"padding_texels", padding},
           {"target", {{"shipped_efficiency_min", kTargetEfficiency}, {"atlas_size", 1024}, {"worst_shipped", bench::roundDigits(worstShipped, 4)}, {"met", onlyNamed ? Json(nullptr) : Json(met)}}},
           {"scenes", rows}};
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
