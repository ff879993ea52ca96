// `lambert solve`: solve a scene's radiosity and export every vertex's outgoing radiance (no
// image), for comparison with the reference path tracer or other renderers. With --adaptive the
// vertices are those of the quad-tree's finest level.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/vertices.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct SolveOnlyOptions {
  SolveCommandOptions solve;
  ExportCommandOptions exported;
  double exposure = 0;  // of the --export's COLOR_0
  std::string exportVertices;
};

int runSolve(const SolveOnlyOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("solve", o.solve);
  if (!scene) return 2;
  const double loadSeconds = total.seconds();
  if (Status ok = checkExportOptions(o.exported); !ok) return fail("solve", ok.error().message);
  if (o.exported.glb.empty())
    if (Status ok = refuseGiven(o.exported, {"--exposure"}, "it scales --export's COLOR_0, and no --export is asked for"); !ok)
      return fail("solve", ok.error().message);
  std::unique_ptr<Radiosity> engine = makeEngine("solve", *scene, o.solve);
  if (!engine) return 2;
  if (Result<SolveCallReport> solved = engine->solve(); !solved) return fail("solve", solved.error().message);
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
  if (Status exported = exportSolution(o.exported, engine->solution(), o.exposure); !exported) {
    std::fprintf(stderr, "lambert solve: %s\n", exported.error().message.c_str());
    return 1;
  }
  const double outputSeconds = output.seconds();
  Stats stats = engine->stats();
  if (!o.exportVertices.empty()) stats.add("vertices_file", "vertices written to", o.exportVertices);
  if (!o.exported.glb.empty()) stats.add("export", "glTF written to", o.exported.glb);
  stats.add("load_seconds", "scene load time", loadSeconds, "s");
  stats.add("output_seconds", "output time (vertex values and files)", outputSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addSolveCommand(CLI::App& app) {
  auto options = std::make_shared<SolveOnlyOptions>();
  CLI::App* cmd = app.add_subcommand("solve", "Solve a scene's radiosity; export per-vertex radiance (CSV or PLY)");
  addSolveOptions(*cmd, options->solve);
  addExportOptions(*cmd, options->exported);
  cmd->add_option("--exposure", options->exposure, "Exposure in stops of --export's COLOR_0")->capture_default_str();
  cmd->add_option("--export-vertices", options->exportVertices,
                  "Write every mesh vertex: position, normal, outgoing radiance L = B/pi (.csv or .ply)");
  return [options] { return runSolve(*options); };
}

}  // namespace lambert::cli
