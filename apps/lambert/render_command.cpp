// `lambert render`: solve a scene's radiosity and write an image of it from the scene camera.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "lambert/core/timer.h"
#include "lambert/io/png.h"
#include "lambert/render/tonemap.h"
#include "lambert/solve/energy.h"
#include "options.h"

namespace lambert::cli {
namespace {

struct RenderCommandOptions {
  SolveCommandOptions solve;
  ImageCommandOptions image;
  std::string output = "out/cornell.png";
};

// Seed 003's adaptive mesh: a few refine-and-solve passes.
std::unique_ptr<AdaptiveRadiosity> solveAdaptive(const Scene& scene, const SolveCommandOptions& o, Stats& stats) {
  AdaptiveOptions options = adaptiveOptions(scene, o);
  auto created = AdaptiveRadiosity::create(scene, options);
  if (!created) {
    std::fprintf(stderr, "lambert render: %s\n", created.error().message.c_str());
    return nullptr;
  }
  std::unique_ptr<AdaptiveRadiosity> adaptive = std::move(*created);
  AdaptiveUpdate sum;
  for (int pass = 0; pass < o.adaptPasses; ++pass) {
    AdaptiveUpdate u = adaptive->update(scene.lights);
    sum.refined += u.refined;
    sum.coarsened += u.coarsened;
    sum.adaptSeconds += u.adaptSeconds;
    sum.formFactorSeconds += u.formFactorSeconds;
    sum.solveSeconds += u.solveSeconds;
    sum.iterations = u.iterations;
  }
  const AdaptiveMesh& mesh = adaptive->mesh();
  stats.add("scene", "scene", scene.name);
  stats.add("mesh", "mesh", std::string("adaptive quad-tree"));
  stats.add("base_edge_length", "coarsest cell edge", options.quadtree.baseEdgeLength, "scene units");
  stats.add("max_level", "deepest level", static_cast<std::int64_t>(options.quadtree.maxLevel));
  stats.add("patches", "active cells (patches)", static_cast<std::int64_t>(mesh.activeNodes().size()));
  stats.add("cells_created", "cells ever created", static_cast<std::int64_t>(mesh.numNodes()));
  stats.add("refined", "cells split", static_cast<std::int64_t>(sum.refined));
  stats.add("coarsened", "cells merged", static_cast<std::int64_t>(sum.coarsened));
  stats.add("adapt_seconds", "refinement time", sum.adaptSeconds, "s");
  stats.add("formfactor_method", "form-factor method", formFactorMethodName(options.formFactors.method));
  stats.add("pairs_estimated", "cell pairs estimated (master table)", static_cast<std::int64_t>(adaptive->table().pairsEstimated()));
  stats.add("pairs_reused", "cell pairs reused from the table", static_cast<std::int64_t>(adaptive->table().pairsReused()));
  // The solve is done: no more pairs will be added, so the table is saved now, whatever follows.
  saveAdaptiveTable(*adaptive, stats);
  stats.add("formfactor_seconds", "form-factor time", sum.formFactorSeconds, "s");
  stats.add("iterations", "iterations (last pass)", static_cast<std::int64_t>(sum.iterations));
  stats.add("solve_seconds", "solve time", sum.solveSeconds, "s");
  EnergyBalance balance = energyBalance(adaptive->problem(), adaptive->radiosity(), scene.metresPerUnit);
  stats.add("emitted_watts", scene.lights.empty() ? "emitted power" : "emitted + injected power", balance.emittedWatts, "W");
  stats.add("absorbed_watts", "absorbed power", balance.absorbedWatts, "W");
  stats.add("escaped_watts", "escaped power (openings)", balance.escapedWatts, "W");
  return adaptive;
}

int runRender(const RenderCommandOptions& o) {
  Timer total;
  std::optional<Scene> scene = findScene("render", o.solve.scene);
  if (!scene) return 2;

  Stats stats;
  std::unique_ptr<AdaptiveRadiosity> adaptive;
  std::optional<RadiositySolution> solution;
  if (o.solve.adaptive) {
    adaptive = solveAdaptive(*scene, o.solve, stats);
    if (!adaptive) return 2;
  } else {
    solution = solveScene(*scene, pipelineOptions(o.solve));
    stats = solution->stats;
  }

  Timer renderTimer;
  Image image = adaptive ? renderAdaptiveImage(*scene, scene->lights, *adaptive, o.image)
                         : renderImage(*scene, scene->lights, solution->mesh, *solution->caster, solution->radiosity,
                                       solution->indirectRadiosity(), solution->problem.albedo, o.image);
  std::vector<std::uint8_t> pixels = toSrgb8(image, o.image.exposure);
  double renderSeconds = renderTimer.seconds();

  Status written = writePng(o.output, image.width, image.height, pixels);
  if (!written) {
    std::fprintf(stderr, "lambert render: %s\n", written.error().message.c_str());
    return 1;
  }

  stats.add("image_width", "image width", static_cast<std::int64_t>(image.width), "px");
  stats.add("image_height", "image height", static_cast<std::int64_t>(image.height), "px");
  stats.add("lighting", "lighting", std::string(o.image.lighting == Lighting::Hybrid && !scene->lights.empty() ? "hybrid" : "radiosity"));
  stats.add("render_seconds", "render time", renderSeconds, "s");
  stats.add("total_seconds", "total time", total.seconds(), "s");
  stats.add("output", "output", o.output);
  printStats(stats, o.solve.json, o.solve.quiet, "wrote " + o.output);
  return 0;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Solve a scene's radiosity and render it to a PNG");
  addSolveOptions(*cmd, options->solve);
  addImageOptions(*cmd, options->image);
  cmd->add_option("-o,--output", options->output, "Output PNG path")->capture_default_str();
  return [options] { return runRender(*options); };
}

}  // namespace lambert::cli
