// Scene loading at scale: a generated binary glTF of N triangles (default 10^6) through
// loadScene (tinygltf, accessors, welding, regions) and then the uniform mesher with an edge limit
// that keeps every input triangle one patch; then every shipped scene under scenes/ the same way.
// Prints one JSON document on stdout; progress and scenes that fail to load go to stderr.
//
//   load_bench [--triangles 1000000] [--scenes DIR] [--bands 8] [--keep FILE.glb]
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_common.h"
#include "lambert/core/timer.h"
#include "lambert/mesh/mesh.h"
#include "lambert/load/scene_file.h"

using namespace lambert;
using Json = nlohmann::ordered_json;

namespace {

using namespace lambert::bench;

constexpr double kTargetLoadSeconds = 5;
constexpr double kTargetPeakRssMib = 2048;

struct Options {
  std::size_t triangles = 1000000;
  int bands = 8;
#ifdef LAMBERT_SOURCE_DIR
  std::string scenes = LAMBERT_SOURCE_DIR "/scenes";
#else
  std::string scenes = "scenes";
#endif
  std::string keep;
};

Options parseOptions(int argc, char** argv) {
  Options options;
  CLI::App app{"load_bench: loading and meshing a generated N-triangle .glb and the shipped scenes, as JSON"};
  app.add_option("--triangles", options.triangles, "Triangles in the generated binary glTF")
      ->check(CLI::Range(std::size_t{2}, std::size_t{100000000}))
      ->capture_default_str();
  app.add_option("--bands", options.bands, "Primitives (bands of grid rows) in the generated file, each of one of 4 materials")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--scenes", options.scenes, "Directory of shipped scenes (.json, .gltf, .glb, searched recursively)")->capture_default_str();
  app.add_option("--keep", options.keep, "Also keep the generated .glb at this path");
  parseOrExit(app, argc, argv);
  return options;
}

// ---------------------------------------------------------------------------------------------
// The generated file: a rolling terrain, a grid of unit squares split into two triangles each,
// rows grouped into bands; each band is a primitive of its own (its own vertices, indexed with
// uint32) with one of four materials.

struct Band {
  std::size_t firstRow, rows;  // grid rows of squares
  std::size_t triangles;       // the last band may stop part way through its last row
};

double terrainHeight(double x, double z) { return 3 * std::sin(x / 23) * std::cos(z / 17) + 1.5 * std::sin((x + z) / 11); }

void appendBytes(std::vector<unsigned char>& out, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  out.insert(out.end(), p, p + n);
}

void pad4(std::vector<unsigned char>& out, unsigned char with) {
  while (out.size() % 4) out.push_back(with);
}

struct Generated {
  std::size_t triangles = 0, vertices = 0, columns = 0, rows = 0;
  std::uintmax_t bytes = 0;
  double seconds = 0;
};

Generated writeTerrainGlb(const std::string& path, std::size_t triangles, int bandCount) {
  Timer timer;
  Generated g;
  g.columns = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(triangles) / 2)));
  g.rows = (triangles + 2 * g.columns - 1) / (2 * g.columns);
  std::vector<Band> bands;
  const std::size_t rowsPerBand = std::max<std::size_t>(1, (g.rows + static_cast<std::size_t>(bandCount) - 1) / static_cast<std::size_t>(bandCount));
  std::size_t left = triangles;
  for (std::size_t row = 0; row < g.rows && left > 0; row += rowsPerBand) {
    const std::size_t rows = std::min(rowsPerBand, g.rows - row);
    const std::size_t count = std::min(left, rows * g.columns * 2);
    bands.push_back({row, rows, count});
    left -= count;
  }

  std::vector<unsigned char> bin;
  Json doc;
  doc["asset"] = Json{{"version", "2.0"}, {"generator", "lambert bench/load_bench.cpp"}};
  doc["scene"] = 0;
  const char* names[4] = {"grass", "rock", "sand", "soil"};
  const double colours[4][3] = {{0.12, 0.3, 0.08}, {0.35, 0.33, 0.3}, {0.6, 0.52, 0.38}, {0.25, 0.17, 0.1}};
  for (int m = 0; m < 4; ++m)
    doc["materials"].push_back(
        Json{{"name", names[m]},
             {"pbrMetallicRoughness", Json{{"baseColorFactor", {colours[m][0], colours[m][1], colours[m][2], 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}});
  Json primitives = Json::array();
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const Band& band = bands[b];
    // Vertices: (rows + 1) × (columns + 1) grid points, x along columns, z along rows.
    const std::size_t stride = g.columns + 1;
    const std::size_t vertexCount = (band.rows + 1) * stride;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    pad4(bin, 0);
    const std::size_t positionOffset = bin.size();
    for (std::size_t r = 0; r <= band.rows; ++r)
      for (std::size_t c = 0; c <= g.columns; ++c) {
        const double x = static_cast<double>(c), z = static_cast<double>(band.firstRow + r);
        const float p[3] = {static_cast<float>(x), static_cast<float>(terrainHeight(x, z)), static_cast<float>(z)};
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], p[k]);
          hi[k] = std::max(hi[k], p[k]);
        }
        appendBytes(bin, p, sizeof p);
      }
    const std::size_t positionBytes = bin.size() - positionOffset;
    const std::size_t indexOffset = bin.size();
    std::size_t emitted = 0;
    for (std::size_t r = 0; r < band.rows && emitted < band.triangles; ++r)
      for (std::size_t c = 0; c < g.columns && emitted < band.triangles; ++c) {
        // Counter-clockwise seen from above (+y): (c, r) → (c, r + 1) → (c + 1, r + 1), ...
        const auto v00 = static_cast<std::uint32_t>(r * stride + c), v10 = v00 + 1;
        const auto v01 = static_cast<std::uint32_t>((r + 1) * stride + c), v11 = v01 + 1;
        const std::uint32_t first[3] = {v00, v01, v11}, second[3] = {v00, v11, v10};
        appendBytes(bin, first, sizeof first);
        if (++emitted < band.triangles) {
          appendBytes(bin, second, sizeof second);
          ++emitted;
        }
      }
    const std::size_t indexBytes = bin.size() - indexOffset;
    const std::size_t view = doc["bufferViews"].size();
    doc["bufferViews"].push_back(Json{{"buffer", 0}, {"byteOffset", positionOffset}, {"byteLength", positionBytes}, {"target", 34962}});
    doc["bufferViews"].push_back(Json{{"buffer", 0}, {"byteOffset", indexOffset}, {"byteLength", indexBytes}, {"target", 34963}});
    const std::size_t accessor = doc["accessors"].size();
    doc["accessors"].push_back(Json{{"bufferView", view}, {"componentType", 5126}, {"count", vertexCount}, {"type", "VEC3"},
                                    {"min", {lo[0], lo[1], lo[2]}}, {"max", {hi[0], hi[1], hi[2]}}});
    doc["accessors"].push_back(Json{{"bufferView", view + 1}, {"componentType", 5125}, {"count", 3 * emitted}, {"type", "SCALAR"}});
    primitives.push_back(Json{{"attributes", Json{{"POSITION", accessor}}}, {"indices", accessor + 1}, {"material", b % 4}, {"mode", 4}});
    g.triangles += emitted;
    g.vertices += vertexCount;
  }
  doc["meshes"] = Json::array({Json{{"name", "terrain"}, {"primitives", std::move(primitives)}}});
  doc["nodes"] = Json::array({Json{{"name", "terrain"}, {"mesh", 0}}});
  doc["scenes"] = Json::array({Json{{"nodes", {0}}}});
  pad4(bin, 0);
  doc["buffers"] = Json::array({Json{{"byteLength", bin.size()}}});

  std::string json = doc.dump();
  while (json.size() % 4) json.push_back(' ');
  const auto u32 = [](std::size_t v) { return static_cast<std::uint32_t>(v); };
  const std::uint32_t header[3] = {0x46546C67u, 2u, u32(12 + 8 + json.size() + 8 + bin.size())};
  const std::uint32_t jsonChunk[2] = {u32(json.size()), 0x4E4F534Au};
  const std::uint32_t binChunk[2] = {u32(bin.size()), 0x004E4942u};
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(header), sizeof header);
  out.write(reinterpret_cast<const char*>(jsonChunk), sizeof jsonChunk);
  out.write(json.data(), static_cast<std::streamsize>(json.size()));
  out.write(reinterpret_cast<const char*>(binChunk), sizeof binChunk);
  out.write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "load_bench: could not write %s\n", path.c_str());
    std::exit(1);
  }
  g.bytes = std::filesystem::file_size(path);
  g.seconds = timer.seconds();
  return g;
}

// ---------------------------------------------------------------------------------------------
// One measurement: loadScene, then subdivideScene with an edge limit no face reaches (each fan
// triangle of each face stays one patch).

std::optional<Json> measure(const std::string& path) {
  const double rssBefore = currentRssMib();
  const double cpuBefore = processCpuSeconds();
  Timer loadTimer;
  Result<Scene> scene = loadScene(path);
  const double loadSeconds = loadTimer.seconds();
  if (!scene) {
    std::fprintf(stderr, "load_bench: skipped %s: %s\n", path.c_str(), scene.error().message.c_str());
    return std::nullopt;
  }
  std::size_t faces = 0;
  double maxEdge = 0;
  for (const Surface& surface : scene->surfaces)
    for (const auto& face : surfaceFaces(surface)) {
      ++faces;
      maxEdge = std::max(maxEdge, polygonExtent(facePositions(surface, face)));
    }
  maxEdge *= 1.001;  // a face's bounding-box diagonal is at least its longest edge and diagonal
  Timer meshTimer;
  const Mesh mesh = subdivideScene(*scene, maxEdge);
  const double meshSeconds = meshTimer.seconds();
  const double cpuSeconds = processCpuSeconds() - cpuBefore;

  Json row;
  row["path"] = path;
  row["load_seconds"] = seconds(loadSeconds);
  row["mesh_seconds"] = seconds(meshSeconds);
  row["cpu_seconds"] = seconds(cpuSeconds);  // process CPU time over load + mesh
  row["faces"] = faces;
  row["surfaces"] = scene->surfaces.size();
  row["max_edge"] = maxEdge;
  row["patches"] = mesh.numPatches();
  row["mesh_vertices"] = mesh.numVertices();
  row["rss_before_mib"] = rssBefore;
  row["rss_after_mib"] = currentRssMib();  // scene and mesh still held
  row["peak_rss_mib"] = peakRssMib();      // the process's high-water mark so far
  return row;
}

std::vector<std::string> shippedScenes(const std::string& dir) {
  std::vector<std::string> paths;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    std::fprintf(stderr, "load_bench: no scenes directory %s (use --scenes DIR)\n", dir.c_str());
    return paths;
  }
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".json" || extension == ".gltf" || extension == ".glb") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);

  Json doc;
  doc["machine"] = cpuModel() + " (" + std::to_string(std::thread::hardware_concurrency()) + " hardware threads)";
  doc["date"] = utcNow();
  doc["build"] = buildDescription();
  doc["load_average_at_start"] = loadAverage();
  doc["rss_at_start_mib"] = currentRssMib();

  // The shipped scenes first, while the process is small, so their peaks mean something.
  Json scenes = Json::array();
  for (const std::string& path : shippedScenes(options.scenes)) {
    std::fprintf(stderr, "%s\n", path.c_str());
    if (std::optional<Json> row = measure(path)) scenes.push_back(std::move(*row));
  }

  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("lambert-load-bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string glb = (dir / "terrain.glb").string();
  std::fprintf(stderr, "generating %zu triangles into %s\n", options.triangles, glb.c_str());
  const Generated generated = writeTerrainGlb(glb, options.triangles, options.bands);
  if (!options.keep.empty()) std::filesystem::copy_file(glb, options.keep, std::filesystem::copy_options::overwrite_existing);
  std::fprintf(stderr, "loading %s (%.1f MiB)\n", glb.c_str(), static_cast<double>(generated.bytes) / (1024.0 * 1024.0));
  std::optional<Json> big = measure(glb);
  std::filesystem::remove_all(dir);
  if (!big) return 1;

  Json synthetic;
  synthetic["kind"] = "terrain grid, binary glTF, uint32 indices";
  synthetic["triangles"] = generated.triangles;
  synthetic["vertices"] = generated.vertices;
  synthetic["grid"] = Json{{"columns", generated.columns}, {"rows", generated.rows}};
  synthetic["file_mib"] = roundDigits(static_cast<double>(generated.bytes) / (1024.0 * 1024.0), 1);
  synthetic["generate_seconds"] = seconds(generated.seconds);
  synthetic["primitives"] = std::min<std::size_t>(static_cast<std::size_t>(options.bands), generated.rows);
  for (auto& [key, value] : big->items()) synthetic[key] = value;
  synthetic["path"] = "(temporary) terrain.glb";
  const double load = (*big)["load_seconds"].get<double>(), peak = (*big)["peak_rss_mib"].get<double>();
  synthetic["targets"] = Json::array({Json{{"name", "load_seconds"}, {"max", kTargetLoadSeconds}, {"value", load}, {"target_met", load < kTargetLoadSeconds}},
                                      Json{{"name", "peak_rss_mib"}, {"max", kTargetPeakRssMib}, {"value", peak}, {"target_met", peak < kTargetPeakRssMib}}});
  std::fprintf(stderr, "  %zu triangles: load %.3f s, mesh %.3f s, %lld patches, peak RSS %.1f MiB\n", generated.triangles, load,
               (*big)["mesh_seconds"].get<double>(), static_cast<long long>((*big)["patches"].get<std::int64_t>()), peak);

  doc["generated"] = std::move(synthetic);
  doc["scenes"] = std::move(scenes);
  std::cout << doc.dump(2) << std::endl;
  return 0;
}
