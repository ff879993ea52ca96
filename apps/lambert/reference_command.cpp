// `lambert reference`: the ground truth. An unbiased path tracer of the same diffuse scene renders
// the camera's image and the outgoing radiance at every vertex that `lambert solve` with the same
// options exports (solutionVertexMesh: the default method's own vertices, or the flat mesh's), for
// `lambert compare` and for other tools.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/vertices.h"
#include "lambert/reference/reference.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct ReferenceCommandOptions {
  SolvingOptions mesh;  // the method and options whose vertices --export-vertices traces at
  ReferenceOptions reference;
  CameraCommandOptions camera;
  int width = 512, height = 512;
  double exposure = 0;
  std::string output;          // image; none unless asked for
  std::string exportVertices;  // vertex radiance; none unless asked for
};

int runReference(const ReferenceCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("reference", o.mesh);
  if (!scene) return 2;
  if (o.output.empty() && o.exportVertices.empty())
    return fail("reference", "nothing to do: give -o IMAGE.png and/or --export-vertices FILE");
  if (o.exportVertices.empty()) {
    if (Status s = refuseGiven(o.mesh, {"--patches", "--max-edge", "--vertex-samples"}, "they choose the vertices, and no --export-vertices is asked for"); !s)
      return fail("reference", s.error().message);
    if (Status s = refuseGiven(o.mesh, solveOnlyOptions(), "the solve's options choose the vertices, and no --export-vertices is asked for"); !s)
      return fail("reference", s.error().message);
  }
  if (!o.output.empty())
    if (Status s = checkImagePath(o.output, o.mesh); !s) return fail("reference", s.error().message);
  if (o.output.empty())
    if (Status s = refuseGiven(o.mesh, {"--spp", "--width", "--height", "--exposure", "--eye", "--target", "--up", "--fov"},
                               "they shape the image, and no -o IMAGE.png is asked for");
        !s)
      return fail("reference", s.error().message);
  Stats cameraStats;
  if (!o.output.empty())
    if (Status s = chooseCamera(*scene, o.camera, cameraStats); !s) return fail("reference", s.error().message);
  ReferenceOptions options = o.reference;
  options.seed = o.mesh.seed;
  options.showProgress = !o.mesh.quiet && !o.mesh.json;
  // The tracer's own geometry: each surface as a triangle fan, the smallest exact description.
  Mesh geometry = subdivideScene(*scene, sceneDiagonal(*scene) * 2);
  ReferenceRenderer renderer(*scene, geometry, options);

  Stats stats;
  stats.add("scene", "scene", scene->name);
  stats.append(cameraStats);
  if (!o.exportVertices.empty()) {
    Timer timer;
    Result<Mesh> vertexMesh = exportedVertexMesh(*scene, o.mesh);
    if (!vertexMesh) return fail("reference", vertexMesh.error().message);
    const Mesh& mesh = *vertexMesh;
    stats.add("vertex_mesh_seconds", "vertex mesh time (the solve's)", timer.seconds(), "s");
    std::vector<Rgb> radiance = renderer.vertexRadiance(mesh);
    Status written = writeVertices(o.exportVertices, vertexSamples(mesh, radiance));
    if (!written) {
      std::fprintf(stderr, "lambert reference: %s\n", written.error().message.c_str());
      return 1;
    }
    stats.add("vertices", "mesh vertices", static_cast<std::int64_t>(mesh.numVertices()));
    stats.add("vertex_samples", "samples per vertex", static_cast<std::int64_t>(options.vertexSamples));
    stats.add("vertex_seconds", "vertex time", timer.seconds(), "s");
    stats.add("vertices_file", "vertices written to", o.exportVertices);
  }
  if (!o.output.empty()) {
    Timer timer;
    Image image = renderer.render(o.width, o.height);
    const double exposure = imageExposureStops(o.mesh, o.exposure, *scene, image, stats);
    Status written = writeImageFile(o.output, image, exposure);
    if (!written) {
      std::fprintf(stderr, "lambert reference: %s\n", written.error().message.c_str());
      return 1;
    }
    stats.add("samples_per_pixel", "samples per pixel", static_cast<std::int64_t>(options.samplesPerPixel));
    stats.add("image_seconds", "image time", timer.seconds(), "s");
    stats.add("output", "image written to", o.output);
  }
  stats.add("rays", "rays", static_cast<std::int64_t>(renderer.raysCast()));
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.mesh.json, o.mesh.quiet);
  return 0;
}

}  // namespace

void addReferenceOptions(CLI::App& cmd, ReferenceOptions& o) {
  cmd.add_option("--spp", o.samplesPerPixel, "Reference: samples per pixel")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  cmd.add_option("--vertex-samples", o.vertexSamples, "Reference: hemisphere samples per vertex")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  cmd.add_option("--max-bounces", o.maxBounces, "Reference: cap on reflections per path (its only bias)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
}

std::function<int()> addReferenceCommand(CLI::App& app) {
  auto options = std::make_shared<ReferenceCommandOptions>();
  CLI::App* cmd = app.add_subcommand("reference", "Path-trace the ground truth: an image and/or per-vertex radiance");
  // A solve's options, so that the same command line as `solve` gives the same vertices.
  addSolveOptions(*cmd, options->mesh);
  addReferenceOptions(*cmd, options->reference);
  cmd->add_option("--width", options->width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", options->height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--exposure", options->exposure, "Exposure in stops (radiance × 2^stops before sRGB)")
      ->default_str("the scene's, else automatic (log-average luminance to middle grey)");
  addCameraOptions(*cmd, options->camera);
  cmd->add_option("-o,--output", options->output, "Image to write: .png or .exr (linear float radiance)");
  cmd->add_option("--export-vertices", options->exportVertices,
                  "Write outgoing radiance at every vertex `lambert solve` with the same options exports (the default method's own "
                  "vertices, or the flat mesh's): .csv or .ply");
  return [options] { return runReference(*options); };
}

}  // namespace lambert::cli
