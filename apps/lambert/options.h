#pragma once
// Options shared by the subcommands that solve and draw a scene, registered on each of them from
// one place, so `render` and `animate` spell and default every option the same way.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "lambert/core/stats.h"
#include "lambert/pipeline/adaptive.h"
#include "lambert/pipeline/pipeline.h"
#include "lambert/render/rasterizer.h"
#include "lambert/scene/scene.h"

namespace lambert::cli {

enum class Lighting {
  Hybrid,     // lights' direct light per pixel over interpolated indirect radiosity (seed 000)
  Radiosity,  // everything from the interpolated radiosity solution
};

// Which scene, meshed how finely: all that `reference` needs to find the solution's vertices.
struct MeshCommandOptions {
  std::string scene = "cornell";
  std::size_t patches = 784;
  double maxEdge = 0;
  std::uint64_t seed = 1;
};

struct SolveCommandOptions : MeshCommandOptions {
  FormFactorMethod formFactor = FormFactorMethod::AreaMonteCarlo;
  int samples = 16;
  int hemicubeResolution = 256;
  int hemisphereRays = 1024;
  int lightSamples = 16;
  SolverKind solver = SolverKind::GaussSeidel;
  double tolerance = 1e-7;
  int maxIterations = 1000;
  std::string cacheDir;  // empty: the default, $XDG_CACHE_HOME/lambert or ~/.cache/lambert
  bool noCache = false;
  bool normalizeRows = false;
  // Adaptive quad-tree meshing (seed 003) instead of uniform bisection.
  bool adaptive = false;
  double baseEdge = 0;  // scene units; 0: a sixth of the scene's diagonal
  int maxLevel = 3;
  double gradientThreshold = 0.5;
  int adaptPasses = 3;
  bool json = false;
  bool quiet = false;
};

struct ImageCommandOptions {
  int width = 512, height = 512;
  Shading shading = Shading::Gouraud;
  int supersample = 2;
  double exposure = 0;
  Lighting lighting = Lighting::Hybrid;
};

void addMeshOptions(CLI::App& command, MeshCommandOptions& options);
void addSolveOptions(CLI::App& command, SolveCommandOptions& options);
// The uniform mesh the options ask for (the one solveScene builds).
Mesh meshFor(const Scene& scene, const MeshCommandOptions& options);
AdaptiveOptions adaptiveOptions(const Scene& scene, const SolveCommandOptions& options);
// At the end of an adaptive run: saves the master table (when caching is on; a failure is a
// warning, never an error) and reports it: pairs_loaded, formfactor_cache ("loaded <path> (N
// pairs)", "saved <path> (N pairs)", both, or "off") and formfactor_cache_seconds.
void saveAdaptiveTable(AdaptiveRadiosity& adaptive, Stats& stats);
void addImageOptions(CLI::App& command, ImageCommandOptions& options);

// Prints a command's figures: JSON with --json, else the headline (if any) and a table, unless
// --quiet.
void printStats(const Stats& stats, bool json, bool quiet, const std::string& headline = "");

// The named built-in scene, or a message on stderr naming the choices.
std::optional<Scene> findScene(const std::string& command, const std::string& name);
PipelineOptions pipelineOptions(const SolveCommandOptions& options);
RenderOptions renderOptions(const ImageCommandOptions& options);

// Draws an adaptive solution: its finest level with radiosity interpolated from the active level
// (flat shading shows the active cells themselves).
Image renderAdaptiveImage(const Scene& scene, const std::vector<Light>& lights, const AdaptiveRadiosity& adaptive,
                          const ImageCommandOptions& options);

// Draws a solved scene as the image options ask: hybrid (lights per pixel) or radiosity only.
Image renderImage(const Scene& scene, const std::vector<Light>& lights, const Mesh& mesh, const RayCaster& caster,
                  const std::vector<Rgb>& radiosity, const std::vector<Rgb>& indirect, const std::vector<Rgb>& albedo,
                  const ImageCommandOptions& options);

}  // namespace lambert::cli
