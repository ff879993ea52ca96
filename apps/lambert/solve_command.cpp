// `lambert solve`: solve a scene's radiosity and export every vertex's outgoing radiance (no
// image), for comparison with the reference path tracer or other renderers, and with --probes the
// light-probe volume (bake/probes.h). With --adaptive the vertices are those of the quad-tree's
// finest level. With --lightmaps, --export's glb holds the scene's own mesh with baked lightmaps
// (io/lightmap_export.h), their files beside it; with --image, lambert's own picture of that glb
// from its camera (render/lightmap_image.h), to hold a browser's or an engine's beside.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "lighting_options.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/bake/probes.h"
#include "lambert/core/timer.h"
#include "lambert/io/lightmap_export.h"
#include "lambert/io/vertices.h"
#include "lambert/render/lightmap_image.h"
#include "distributed.h"
#include "options.h"

namespace lambert::cli {
namespace {

// --lightmaps and its settings (defaults: the library's, mesh/lightmap_uvs.h).
struct LightmapCommandOptions : GivenOptions {
  bool lightmaps = false;
  double texelSizeMetres = 0;  // 0: the library's default for the scene
  int size = LightmapUvOptions{}.atlasSize;
  int padding = LightmapUvOptions{}.paddingTexels;
  int gatherStep = AdaptiveTexelOptions{}.coarsestStep;
  double gatherTolerance = AdaptiveTexelOptions{}.tolerance;
  std::string image;  // lambert's render of the lightmapped glb (.png or .exr); none unless asked for
  LightmapImageOptions imageOptions;
};

struct SolveCommandOptions {
  SolvingOptions solve;
  ExportCommandOptions exported;
  LightmapCommandOptions lightmaps;
  CameraCommandOptions camera;  // --export's glb camera, and --image's
  double exposure = 0;  // of the --export's COLOR_0, or with --lightmaps of the --image
  std::string exportVertices;
  std::string probes;         // the light-probe volume (bake/probes.h); none unless asked for
  double probeSpacing = 0;    // scene units; 0: the library's default
  LightingCommandOptions lighting;
  std::string exportPoints;  // --points' rows with their lux
  std::string exportGrids;   // prefix of each grid's CSV and false-colour PNG
  bool distributed = false;  // one rank of an MPI job (distributed.h)
};

// --points and --export-points come together; --export-grids needs a grid to write.
Status checkLightingOptions(const SolveCommandOptions& o) {
  if (o.lighting.points.empty() != o.exportPoints.empty())
    return Error{o.exportPoints.empty() ? "--points needs --export-points OUT.csv to write its lux to"
                                        : "--export-points writes the lux at --points' points: give --points IN.csv"};
  if (!o.exportGrids.empty() && o.lighting.workPlanes.empty() && o.lighting.grids.empty())
    return Error{"--export-grids writes each --work-plane's and --grid's CSV and picture, and none is asked for"};
  return Ok{};
}

// --lightmaps needs --export's glb to write into, and replaces its COLOR_0 (so --bake says
// nothing then); its settings need --lightmaps, and --image's size needs --image.
Status checkLightmapOptions(const SolveCommandOptions& o) {
  if (!o.lightmaps.lightmaps)
    return refuseGiven(o.lightmaps, {"--texel-size", "--lightmap-size", "--lightmap-padding", "--lightmap-step", "--lightmap-tolerance", "--image", "--width", "--height", "--supersample"},
                       "it sets up --lightmaps, which is not asked for");
  if (o.lightmaps.image.empty())
    if (Status ok = refuseGiven(o.lightmaps, {"--width", "--height", "--supersample"}, "it sizes --image, which is not asked for"); !ok) return ok;
  if (!o.lightmaps.image.empty())
    if (Status ok = checkImagePath(o.lightmaps.image, o.exported); !ok) return ok;
  if (o.exported.glb.empty()) return Error{"--lightmaps writes the glb of --export and its lightmaps beside it: give --export OUT.glb"};
  return refuseGiven(o.exported, {"--bake"}, "the glb of --lightmaps carries lightmaps, not COLOR_0");
}

LightmapBakeOptions lightmapBakeOptions(const Scene& scene, const LightmapCommandOptions& o, const SolvingOptions& solve) {
  LightmapBakeOptions options;
  options.showProgress = !solve.quiet && !solve.json;
  options.uvs.texelSize = o.texelSizeMetres / scene.metresPerUnit;  // 0 stays 0: the library's default
  options.uvs.atlasSize = o.size;
  // A size asked for is each atlas's: a file's own UVs were packed for it.
  options.uvs.fileSetsShareAtlas = !o.given("--lightmap-size");
  options.uvs.paddingTexels = o.padding;
  options.sampling.coarsestStep = o.gatherStep;
  options.sampling.tolerance = o.gatherTolerance;
  return options;
}

int runSolve(const SolveCommandOptions& given) {
  Timer total;
  SolveCommandOptions o = given;
  std::shared_ptr<Communicator> communicator;
  if (o.distributed) {
    Result<std::shared_ptr<Communicator>> joined = joinDistributedJob();
    if (!joined) return fail("solve", joined.error().message);
    communicator = *joined;
    if (communicator->rank() != 0) o.solve.quiet = true, o.solve.json = false;
  }
  // Every rank of a distributed solve loads the scene itself; a rank that cannot (a file missing
  // on its node) stops them all, with its message, before any of them solves.
  std::optional<Scene> scene;
  if (communicator) {
    Result<Scene> loaded = sceneFor(o.solve);
    if (Status all = communicator->agree(loaded ? Status(Ok{}) : Status(loaded.error())); !all) return fail("solve", all.error().message);
    scene = std::move(*loaded);
  } else {
    scene = findScene("solve", o.solve);
  }
  if (!scene) return 2;
  const double loadSeconds = total.seconds();
  if (Status ok = checkExportOptions(o.exported); !ok) return fail("solve", ok.error().message);
  if (Status ok = checkLightmapOptions(o); !ok) return fail("solve", ok.error().message);
  if (Status ok = checkLightingOptions(o); !ok) return fail("solve", ok.error().message);
  PointsTable pointsTable;
  Result<LightingRequest> lightingRequested = lightingRequest(*scene, o.lighting, &pointsTable, !o.solve.quiet && !o.solve.json);
  if (!lightingRequested) return fail("solve", lightingRequested.error().message);
  lightingRequested->illuminance.shadowTolerance = o.solve.shadowTolerance;  // the solve's own testing of the lights
  // --exposure scales --export's COLOR_0, or with --lightmaps the --image (the glb's lightmaps
  // hold irradiance in W/m², never an exposed value).
  if (o.exported.glb.empty() || (o.lightmaps.lightmaps && o.lightmaps.image.empty()))
    if (Status ok = refuseGiven(o.exported, {"--exposure"},
                                o.lightmaps.lightmaps ? "with --lightmaps it exposes --image, which is not asked for (the glb's lightmaps hold "
                                                        "irradiance in W/m²)"
                                                      : "it scales --export's COLOR_0, and no --export is asked for");
        !ok)
      return fail("solve", ok.error().message);
  if (o.probes.empty())
    if (Status ok = refuseGiven(o.solve, {"--probe-spacing"}, "it spaces --probes' grid, and no --probes is asked for"); !ok)
      return fail("solve", ok.error().message);
  ProbeOptions probeOptions;
  probeOptions.spacing = o.probeSpacing;
  probeOptions.showProgress = !o.solve.quiet && !o.solve.json;
  if (!o.probes.empty())
    if (Result<ProbeVolume> grid = probeGrid(*scene, probeOptions); !grid) return fail("solve", grid.error().message);
  // --export's glb carries a camera and --image draws from it: the view `lambert render` draws,
  // or the one --eye/--target/--up/--fov give (--image needs --lightmaps, which needs --export).
  Stats cameraFigures;
  if (o.exported.glb.empty()) {
    if (Status ok = refuseGiven(o.camera, {"--eye", "--target", "--up", "--fov"},
                                "it places the camera --export's glb carries and --image draws from, and no --export is asked for");
        !ok)
      return fail("solve", ok.error().message);
  } else if (Status ok = chooseCamera(*scene, o.camera, cameraFigures); !ok) {
    return fail("solve", ok.error().message);
  }
  std::unique_ptr<Radiosity> engine = makeEngine("solve", *scene, o.solve, communicator);
  if (communicator) {
    if (Status all = communicator->agree(engine ? Status(Ok{}) : Status(Error{"the engine could not be made"})); !all)
      return fail("solve", all.error().message);
  }
  if (!engine) return 2;
  Result<SolveReport> solved = engine->solve();
  if (communicator) {
    if (Status all = communicator->agree(solved ? Status(Ok{}) : Status(solved.error())); !all) return fail("solve", all.error().message);
    // Rank 0 alone computes and writes the outputs; the final gathers they need are spread over
    // every rank, the others serving them until rank 0 is done.
    if (communicator->rank() != 0) {
      engine->serveDistributedOutputs();
      return 0;
    }
  }
  std::optional<DistributedOutputs> lead;
  if (communicator) lead.emplace(engine->leadDistributedOutputs());
  if (!solved) return fail("solve", solved.error().message);
  (void)engine->saveCache();
  // The outputs first, so that the stats include the final gather they ran.
  Timer output;
  if (!o.exportVertices.empty()) {
    Status written = writeVertices(o.exportVertices, vertexSamples(engine->solution()));
    if (!written) {
      std::fprintf(stderr, "lambert solve: %s\n", written.error().message.c_str());
      return 1;
    }
  }
  std::optional<ProbeVolume> probes;
  if (!o.probes.empty()) {
    Result<ProbeVolume> baked = bakeProbes(engine->solution(), probeOptions);
    Status written = baked ? writeProbes(o.probes, *baked) : Status(baked.error());
    if (!written) {
      std::fprintf(stderr, "lambert solve: %s\n", written.error().message.c_str());
      return 1;
    }
    probes = std::move(*baked);
  }
  Stats lightmapFigures;
  if (o.lightmaps.lightmaps) {
    const SolutionView& solution = engine->solution();
    Result<BakedLightmaps> baked = bakeLightmaps(solution, lightmapBakeOptions(solution.scene(), o.lightmaps, o.solve));
    if (!baked) return fail("solve", baked.error().message);
    Result<LightmapExport> written = writeLightmaps(o.exported.glb, solution.scene(), *baked);
    if (!written) {
      std::fprintf(stderr, "lambert solve: %s\n", written.error().message.c_str());
      return 1;
    }
    lightmapFigures = lightmapStats(solution.scene(), *baked, *written);
    if (!o.lightmaps.image.empty()) {
      // What a client of the glb draws: its RGBM bytes, decoded.
      const Image image = renderLightmapped(solution.scene(), asCarriedByGlb(*baked), solution.scene().camera, o.lightmaps.imageOptions);
      const double exposure = imageExposureStops(o.exported, o.exposure, solution.scene(), image, lightmapFigures);
      if (Status ok = writeImageFile(o.lightmaps.image, image, exposure); !ok) {
        std::fprintf(stderr, "lambert solve: %s\n", ok.error().message.c_str());
        return 1;
      }
      lightmapFigures.add("image", "lightmapped image written to", o.lightmaps.image);
    }
  } else if (Status exported = exportSolution(o.exported, engine->solution(), o.exposure); !exported) {
    std::fprintf(stderr, "lambert solve: %s\n", exported.error().message.c_str());
    return 1;
  }
  Stats lightingFigures;
  if (o.lighting.any()) {
    Result<LightingResults> lighting = measureLighting(engine->solution(), *lightingRequested);
    if (!lighting) return fail("solve", lighting.error().message);
    if (!o.exportPoints.empty()) {
      if (Status ok = writePointsCsv(o.exportPoints, pointsTable, lighting->points, lighting->pointDaylightFactor); !ok) {
        std::fprintf(stderr, "lambert solve: %s\n", ok.error().message.c_str());
        return 1;
      }
      lightingFigures.add("points_file", "illuminance at points written to", o.exportPoints);
    }
    if (!o.exportGrids.empty()) {
      Result<std::vector<std::string>> files = writeGridFiles(o.exportGrids, *lighting, engine->solution().scene().fileFrame,
                                                              planOptions(engine->solution().scene(), engine->solution().lights()));
      if (!files) {
        std::fprintf(stderr, "lambert solve: %s\n", files.error().message.c_str());
        return 1;
      }
      lightingFigures.add("grid_files", "grid files written", static_cast<std::int64_t>(files->size()));
    }
    addLightingStats(lightingFigures, *lighting);
  }
  const double outputSeconds = output.seconds();
  Stats stats = engine->stats();
  stats.append(cameraFigures);
  stats.append(lightingFigures);
  stats.append(lightmapFigures);
  if (!o.exportVertices.empty()) stats.add("vertices_file", "vertices written to", o.exportVertices);
  if (probes) {
    stats.add("probes_file", "light probes written to", o.probes);
    stats.add("probe_spacing", "probe spacing", probes->spacing, "scene units");
    stats.add("probes", "probes", static_cast<std::int64_t>(probes->numProbes()));
    stats.add("probes_valid", "probes in open space", static_cast<std::int64_t>(probes->numValid));
    stats.add("probes_invalid", "probes inside geometry", static_cast<std::int64_t>(probes->numProbes() - probes->numValid));
    stats.add("probe_rays", "probe rays cast", static_cast<std::int64_t>(probes->raysCast));
    stats.add("probe_seconds", "probe bake time", probes->seconds, "s");
    stats.add("probe_radiance_seconds", "of which the solution's vertex radiance", probes->radianceSeconds, "s");
  }
  if (!o.exported.glb.empty()) stats.add("export", "glTF written to", o.exported.glb);
  stats.add("load_seconds", "scene load time", loadSeconds, "s");
  stats.add("output_seconds", "output time (vertex values and files)", outputSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addSolveCommand(CLI::App& app) {
  auto options = std::make_shared<SolveCommandOptions>();
  CLI::App* cmd = app.add_subcommand("solve", "Solve a scene's radiosity; export per-vertex radiance (CSV or PLY)");
  addSolveOptions(*cmd, options->solve);
  addExportOptions(*cmd, options->exported);
  addCameraOptions(*cmd, options->camera);
  cmd->add_option("--exposure", options->exposure, "Exposure in stops of --export's COLOR_0; with --lightmaps, of --image")
      ->default_str("0; --image: the scene's, else automatic");
  LightmapCommandOptions& lightmaps = options->lightmaps;
  lightmaps.command = cmd;
  cmd->add_flag("--lightmaps", lightmaps.lightmaps,
                "Bake lightmaps: --export's glb holds the scene's own mesh with each material's lightmap (irradiance as 8-bit RGBM, "
                "LAMBERT_lightmap, TEXCOORD_1), OUT-lightmap-K.exr (irradiance, W/m², half float) beside it");
  cmd->add_option("--texel-size", lightmaps.texelSizeMetres, "With --lightmaps: lightmap texel size in metres")
      ->check(CLI::Range(1e-6, 1e6))
      ->default_str("from the scene's size");
  cmd->add_option("--lightmap-size", lightmaps.size, "With --lightmaps: texels per side of each atlas, at most (more atlases when one is full); given, also each atlas of the file's own lightmap UVs (else they share one of 1024²)")
      ->check(CLI::Range(16, 16384))
      ->capture_default_str();
  cmd->add_option("--lightmap-padding", lightmaps.padding, "With --lightmaps: empty texels kept around each chart")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_option("--lightmap-step", lightmaps.gatherStep,
                  "With --lightmaps: texels between the points where the light from the surfaces is gathered first; cells whose "
                  "corners disagree are halved, the rest interpolated (1 gathers every texel)")
      ->check(CLI::IsMember({1, 2, 4, 8, 16, 32}))
      ->capture_default_str();
  cmd->add_option("--lightmap-tolerance", lightmaps.gatherTolerance,
                  "With --lightmaps: a cell's texels are interpolated where its corners' light differs by at most this share")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--image", lightmaps.image,
                  "With --lightmaps: render the glb's mesh lit by the lightmaps it carries (its RGBM, decoded) from its camera (the "
                  "scene's, --eye/--target, else `render`'s view), as a glTF viewer draws it: .png (tone mapped) or .exr (linear "
                  "radiance)");
  cmd->add_option("--width", lightmaps.imageOptions.width, "With --image: width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", lightmaps.imageOptions.height, "With --image: height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--supersample", lightmaps.imageOptions.supersample, "With --image: samples per pixel along each axis")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->add_option("--export-vertices", options->exportVertices,
                  "Write every mesh vertex: position, normal, outgoing radiance L = B/pi (.csv or .ply)");
  cmd->add_option("--probes", options->probes,
                  "Write an L2 spherical-harmonic irradiance volume over the scene's box (docs/lightmaps.md)");
  cmd->add_option("--probe-spacing", options->probeSpacing,
                  "Distance between --probes' probes, scene units (default: about 4096 probes over the box)")
      ->check(CLI::PositiveNumber);
  addLightingOptions(*cmd, options->lighting);
  cmd->add_option("--export-points", options->exportPoints,
                  "Write --points' rows with E_direct, E_indirect and E in lux appended (CSV)");
  cmd->add_option("--export-grids", options->exportGrids,
                  "Write each --work-plane's and --grid's points (PREFIX<name>.csv, lux) and false-colour picture with isolux lines "
                  "(PREFIX<name>.png); PREFIX may be a folder ending in /");
  cmd->add_flag("--distributed", options->distributed,
                "Solve as one rank of an MPI job (mpirun -np N lambert solve --distributed …): the hierarchical method's sweeps "
                "spread over the ranks; rank 0 writes the outputs (docs/distributed.md)");
  return [options] { return runSolve(*options); };
}

}  // namespace lambert::cli
