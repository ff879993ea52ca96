// `lambert report`: solve a scene and write one HTML page of its lighting-design results
// (design/report.h): calculation surfaces in lux with their figures and false-colour pictures,
// points, light sources in photometric units, the solve's figures.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/atomic_file.h"
#include "lambert/core/text.h"
#include "lambert/core/timer.h"
#include "lambert/design/report.h"
#include "lambert/version.h"
#include "lighting_options.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct ReportOptions {
  SolvingOptions solve;
  LightingCommandOptions lighting;
  std::string output;
};

int runReport(ReportOptions o) {
  Timer total;
  if (lowercaseExtension(o.output) != ".html" && lowercaseExtension(o.output) != ".htm")
    return fail("report", "--output " + o.output + ": a report is an HTML page; give a path ending in .html");
  std::optional<Scene> scene = findScene("report", o.solve);
  if (!scene) return 2;
  // Without a calculation surface asked for, the usual one: a work plane 0.8 m above the floor
  // (a quarter of the height in a scene lower than 1.6 m, such as a model box).
  if (!o.lighting.any()) {
    const Bounds bounds = sceneBounds(*scene);
    const double height = (bounds.hi.y - bounds.lo.y) * scene->metresPerUnit;
    o.lighting.workPlanes.push_back(height >= 1.6 ? 0.8 : 0.25 * height);
  }
  PointsTable points;
  Result<LightingRequest> request = lightingRequest(*scene, o.lighting, &points, !o.solve.quiet && !o.solve.json);
  if (!request) return fail("report", request.error().message);
  request->illuminance.shadowTolerance = o.solve.shadowTolerance;  // the solve's own testing of the lights
  std::unique_ptr<Radiosity> engine = makeEngine("report", *scene, o.solve);
  if (!engine) return 2;
  if (Result<SolveReport> solved = engine->solve(); !solved) return fail("report", solved.error().message);
  (void)engine->saveCache();
  Result<LightingResults> lighting = measureLighting(engine->solution(), *request);
  if (!lighting) return fail("report", lighting.error().message);
  ReportInput input;
  input.solution = &engine->solution();
  input.lighting = &*lighting;
  input.points = o.lighting.points.empty() ? nullptr : &points;
  input.figures = engine->stats();
  input.generator = std::string("lambert ") + version();
  Result<std::string> html = lightingReportHtml(input);
  if (!html) return fail("report", html.error().message);
  if (Status ok = writeFileAtomically(o.output, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(html->data()), html->size()));
      !ok) {
    std::fprintf(stderr, "lambert report: %s\n", ok.error().message.c_str());
    return 1;
  }
  Stats stats;
  addLightingStats(stats, *lighting);
  stats.add("report", "report written to", o.output);
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addReportCommand(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "Solve a scene and write its lighting report: lux on work planes and grids, "
                                               "uniformity, false colour, light sources (one HTML page)");
  addSolveOptions(*cmd, options->solve);
  addLightingOptions(*cmd, options->lighting);
  cmd->add_option("-o,--output", options->output, "The report, an HTML page")->required();
  return [options] { return runReport(*options); };
}

}  // namespace lambert::cli
