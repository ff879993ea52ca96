// `lambert info SCENE`: what a scene holds and what solving it would take, before solving it:
// surfaces (smooth regions), faces, materials, lights, bounds and unit, area, emitted power, and
// the patch count and dense form-factor memory that --patches / --max-edge would give.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/memory.h"
#include "lambert/engine/radiosity.h"
#include "lambert/light/emission.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct InfoCommandOptions {
  MeshCommandOptions mesh;
  bool json = false;
};

int runInfo(const InfoCommandOptions& o) {
  std::optional<Scene> scene = findScene("info", o.mesh);
  if (!scene) return 2;
  Stats stats;
  stats.add("scene", "scene", scene->name);
  std::size_t faces = 0;
  double area = 0, emittedWatts = 0;
  int emitters = 0;
  const double m2 = scene->metresPerUnit * scene->metresPerUnit;
  for (const Surface& s : scene->surfaces) {
    faces += surfaceFaces(s).size();
    const double a = surfaceArea(s);
    area += a;
    // Through the emission texture: a surface where it is black emits nothing.
    const Rgb radiance = meanEmittedRadiance(*scene, s);
    emittedWatts += a * m2 * kPi * radiance.luminance();
    emitters += radiance.maxComponent() > 0;
  }
  const auto [lo, hi] = sceneBounds(*scene);
  stats.add("surfaces", "surfaces (smooth regions)", static_cast<std::int64_t>(scene->surfaces.size()));
  stats.add("faces", "faces", static_cast<std::int64_t>(faces));
  stats.add("materials", "materials", static_cast<std::int64_t>(scene->materials.size()));
  stats.add("emitting_surfaces", "emitting surfaces", static_cast<std::int64_t>(emitters));
  stats.add("lights", "point, spot and directional lights", static_cast<std::int64_t>(scene->lights.size()));
  stats.add("metres_per_unit", "metres per scene unit", scene->metresPerUnit, "m");
  char bounds[160];
  std::snprintf(bounds, sizeof bounds, "(%g, %g, %g) to (%g, %g, %g)", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
  stats.add("bounds", "bounds (scene units)", std::string(bounds));
  // The same box in the file's own coordinates, the frame --eye and --target are given in.
  Bounds file{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (const Surface& s : scene->surfaces)
    for (const Vec3& p : s.vertices) {
      const Vec3 q = scene->fileFrame.filePoint(p);
      file.lo = componentMin(file.lo, q);
      file.hi = componentMax(file.hi, q);
    }
  std::snprintf(bounds, sizeof bounds, "(%g, %g, %g) to (%g, %g, %g)", file.lo.x, file.lo.y, file.lo.z, file.hi.x, file.hi.y, file.hi.z);
  stats.add("bounds_file", "bounds (file coordinates, for --eye/--target)", std::string(bounds));
  const Vec3 up = scene->fileFrame.up;
  std::snprintf(bounds, sizeof bounds, "%g,%g,%g", up.x, up.y, up.z);
  stats.add("up_file", "up axis (file coordinates)", std::string(bounds));
  stats.add("area_m2", "surface area", area * m2, "m2");
  stats.add("emitted_watts", "power emitted by surfaces (watts of luminance, lm/683)", emittedWatts, "W");

  const Mesh mesh = uniformMesh(*scene, uniformMeshOptions(*scene, o.mesh));
  const double n = static_cast<double>(mesh.numPatches());
  const double matrixBytes = n * n * sizeof(float);
  stats.add("patches", o.mesh.maxEdge > 0 ? "patches at --max-edge" : "patches at --patches", static_cast<std::int64_t>(mesh.numPatches()));
  stats.add("formfactor_matrix_mib", "dense form-factor matrix", matrixBytes / (1024.0 * 1024.0), "MiB");
  if (const double available = availableMemoryBytes(); available > 0)
    stats.add("fits_in_memory", "fits in available memory", std::string(matrixBytes < 0.8 * available ? "yes" : "no"));
  printStats(stats, o.json, false);
  return 0;
}

}  // namespace

std::function<int()> addInfoCommand(CLI::App& app) {
  auto options = std::make_shared<InfoCommandOptions>();
  CLI::App* cmd = app.add_subcommand("info", "What a scene holds, and the patches and memory a dense solve would take");
  addMeshOptions(*cmd, options->mesh, PatchOptions::DenseEstimate);
  cmd->add_flag("--json", options->json, "Print as JSON");
  return [options] { return runInfo(*options); };
}

}  // namespace lambert::cli
