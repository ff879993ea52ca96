// `lambert report`: solve a scene and write its lighting report (design/report.h) as an HTML page,
// a PDF or both (by the extension of each --output), with the CSV of every calculation surface
// (and of --points) beside it: the columns its figures come from.
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <sstream>
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
  std::vector<std::string> outputs;
  std::vector<std::string> observers;  // "x,y,z,dx,dy,dz" in the scene file's frame and unit
};

// "x,y,z,dx,dy,dz": an eye and its line of sight (made horizontal), in the scene file's frame, as --points' rows.
Result<GlareObserverSpec> parseObserver(const std::string& text, const Scene& scene, std::size_t index) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string field;
  while (std::getline(in, field, ',')) {
    char* end = nullptr;
    const double x = std::strtod(field.c_str(), &end);
    if (end == field.c_str() || !std::isfinite(x)) return Error{"--ugr-observer \"" + text + "\": \"" + field + "\" is not a number"};
    v.push_back(x);
  }
  if (v.size() != 6) return Error{"--ugr-observer \"" + text + "\": give x,y,z,dx,dy,dz: the eye and the line of sight"};
  const FileFrame& frame = scene.fileFrame;
  GlareObserverSpec o;
  o.name = "observer " + std::to_string(index + 1);
  o.eye = frame.scenePoint({v[0], v[1], v[2]});
  // UGR's line of sight is horizontal: its scene-horizontal part.
  const Vec3 sight = frame.sceneDirection({v[3], v[4], v[5]});
  o.viewDirection = {sight.x, 0, sight.z};
  if (!(length(o.viewDirection) > 0)) return Error{"--ugr-observer \"" + text + "\": the line of sight must have a horizontal part"};
  return o;
}

std::string today() {
  const std::time_t now = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d", std::gmtime(&now));
  return buffer;
}

int runReport(ReportOptions o) {
  Timer total;
  for (const std::string& output : o.outputs) {
    const std::string e = lowercaseExtension(output);
    if (e != ".html" && e != ".htm" && e != ".pdf")
      return fail("report", "--output " + output + ": a report is an HTML page or a PDF; give a path ending in .html or .pdf");
  }
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
  for (std::size_t k = 0; k < o.observers.size(); ++k) {
    Result<GlareObserverSpec> observer = parseObserver(o.observers[k], *scene, k);
    if (!observer) return fail("report", observer.error().message);
    request->glareObservers.push_back(*observer);
  }
  // Without observers given, a room lit by measured luminaires is rated from the middle of each side.
  bool measuredLuminaire = false;
  for (const Light& light : scene->lights) measuredLuminaire |= light.kind == LightKind::Luminaire;
  if (o.observers.empty() && measuredLuminaire) request->glareObservers = defaultGlareObservers(*scene);
  std::unique_ptr<Radiosity> engine = makeEngine("report", *scene, o.solve);
  if (!engine) return 2;
  if (Result<SolveReport> solved = engine->solve(); !solved) return fail("report", solved.error().message);
  (void)engine->saveCache();
  Result<LightingResults> lighting = measureLighting(engine->solution(), *request);
  if (!lighting) return fail("report", lighting.error().message);

  // The CSVs beside the first output: <stem>-<surface>.csv, <stem>-points.csv.
  const std::filesystem::path first(o.outputs.front());
  const std::string prefix = (first.parent_path() / first.stem()).string() + "-";
  const Scene& solved = engine->solution().scene();
  Result<std::vector<std::string>> written = writeGridFiles(prefix, *lighting, solved.fileFrame, planOptions(solved, engine->solution().lights()));
  if (!written) return fail("report", written.error().message);
  ReportInput input;
  for (std::size_t k = 0; k < written->size(); k += 2) input.gridFiles.push_back(std::filesystem::path((*written)[k]).filename().string());
  if (!o.lighting.points.empty()) {
    input.pointsFile = prefix + "points.csv";
    if (Status ok = writePointsCsv(input.pointsFile, points, lighting->points, lighting->pointDaylightFactor); !ok) return fail("report", ok.error().message);
    input.pointsFile = std::filesystem::path(input.pointsFile).filename().string();
  }
  input.solution = &engine->solution();
  input.lighting = &*lighting;
  input.points = o.lighting.points.empty() ? nullptr : &points;
  input.figures = engine->stats();
  input.generator = std::string("lambert ") + version();
  input.date = today();
  input.sceneFile = o.solve.scene;
  Result<LightingReport> report = lightingReport(input);
  if (!report) return fail("report", report.error().message);
  for (const std::string& output : o.outputs)
    if (Status ok = writeReportFile(*report, output); !ok) {
      std::fprintf(stderr, "lambert report: %s\n", ok.error().message.c_str());
      return 1;
    }
  Stats stats;
  addLightingStats(stats, *lighting);
  for (std::size_t k = 0; k < lighting->glare.size(); ++k)
    if (const double ugr = lighting->glare[k].rating.ugr; std::isfinite(ugr))  // −∞: no luminaire in view, nothing to rate
      stats.add("ugr" + std::to_string(k + 1), "UGR, " + lighting->glare[k].observer.name, ugr);
    else
      stats.add("ugr" + std::to_string(k + 1), "UGR, " + lighting->glare[k].observer.name, std::string("no glare source in view"));
  std::string files;
  for (const std::string& output : o.outputs) files += (files.empty() ? "" : ", ") + output;
  stats.add("report", "report written to", files);
  stats.add("total_seconds", "total time", total.seconds(), "s");
  printStats(stats, o.solve.json, o.solve.quiet);
  return 0;
}

}  // namespace

std::function<int()> addReportCommand(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "Solve a scene and write its lighting report: maintained lux on work planes and grids, "
                                               "uniformity, plans, luminaire schedule, UGR, power density (HTML and/or PDF)");
  addSolveOptions(*cmd, options->solve);
  addLightingOptions(*cmd, options->lighting);
  cmd->add_option("-o,--output", options->outputs, "The report: an HTML page (.html) or a PDF (.pdf); repeat for both")->required();
  cmd->add_option("--ugr-observer", options->observers,
                  "A UGR observer: x,y,z,dx,dy,dz (the eye and the line of sight, made horizontal, in the scene file's frame; repeatable). "
                  "Default: seated eyes at the middle of each side, looking across");
  return [options] { return runReport(*options); };
}

}  // namespace lambert::cli
