#pragma once
// A solve's settings as the CLI names them (docs/cli.md: --link-error, --solver, …), with the
// library's defaults (RadiosityOptions{}), and the one place they become the library's RadiosityOptions. The CLI's solving
// commands and the Python module (`lambert.Radiosity(scene, link_error=1e-3)`) both go through
// here, so a setting is spelt, defaulted, range-checked and refused the same way everywhere: a
// setting the chosen method would not read is an error naming it, never silently ignored.
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/engine/radiosity.h"

namespace lambert {

// The library's defaults (RadiosityOptions{}), which every setting below starts from: the
// defaults are written once, in the options each layer owns.
const RadiosityOptions& defaultRadiosityOptions();

struct RadiositySettings {
  // The flat method's uniform mesh.
  std::size_t patches = defaultRadiosityOptions().uniform.targetPatches;
  double maxEdge = defaultRadiosityOptions().uniform.maxEdgeLength;
  std::uint64_t seed = defaultRadiosityOptions().formFactors.seed;
  FormFactorMethod formFactor = defaultRadiosityOptions().formFactors.method;
  int samples = defaultRadiosityOptions().formFactors.samplePairs;
  int hemicubeResolution = defaultRadiosityOptions().formFactors.hemicubeResolution;
  int hemisphereRays = defaultRadiosityOptions().formFactors.hemisphereRays;
  int lightSamples = defaultRadiosityOptions().directLight.samplesPerPatch;
  double shadowTolerance = defaultRadiosityOptions().directLight.shadowTolerance;  // Ward's τ; 0: exact
  SolverKind solver = defaultRadiosityOptions().solver;
  double tolerance = defaultRadiosityOptions().tolerance;
  int maxIterations = defaultRadiosityOptions().maxIterations;
  std::string cacheDir;  // empty: the CLI's default, $XDG_CACHE_HOME/lambert or ~/.cache/lambert
  bool noCache = false;
  bool normalizeRows = defaultRadiosityOptions().normalizeRows;
  // Hierarchical radiosity with clustering, or the flat methods (uniform or adaptive mesh, dense
  // F). Read where "--method" is given; otherwise radiosityOptions chooses.
  MeshStrategy method = defaultRadiosityOptions().meshing;
  double linkError = defaultRadiosityOptions().hierarchical.links.linkError;
  double minElementArea = defaultRadiosityOptions().hierarchical.links.minElementArea;  // 0: the scene's area × 1e-5
  int visibilityRays = defaultRadiosityOptions().hierarchical.links.visibilityRays;
  bool noClusters = !defaultRadiosityOptions().hierarchical.links.clusters;
  int refinePasses = defaultRadiosityOptions().hierarchical.refinePasses;
  // Adaptive quad-tree meshing (Heckbert's quad-tree subdivision) instead of uniform bisection (flat only).
  bool adaptive = false;
  double baseEdge = defaultRadiosityOptions().adaptive.quadtree.baseEdgeLength;  // 0: a sixth of the scene's diagonal
  int maxLevel = defaultRadiosityOptions().adaptive.quadtree.maxLevel;
  double gradientThreshold = defaultRadiosityOptions().adaptive.gradientThreshold;
  int adaptPasses = defaultRadiosityOptions().adaptive.passesPerSolve;
  double memoryLimitBytes = defaultRadiosityOptions().memoryLimitBytes;  // 0: the machine's available memory
  bool showProgress = false;    // progress lines on a terminal
};

// Whether the user set the setting of that CLI name ("--link-error"): only those given are
// refused when unused, and the scene file's own defaults yield to them.
using GivenSetting = std::function<bool(std::string_view cliName)>;

// The library's options for a solve of `scene`, or an error naming a given setting the solve
// would not read (a method's own setting under another method, adaptive settings on a uniform
// mesh, …). The method: "--method", or hierarchical unless something asks for a flat one.
Result<RadiosityOptions> radiosityOptions(const Scene& scene, const RadiositySettings& settings, const GivenSetting& given);
// The flat method's mesh size: the settings', or the scene file's where none is given.
UniformMeshOptions uniformMeshOptions(const Scene& scene, const RadiositySettings& settings, const GivenSetting& given);
// The settings only the flat method reads; giving one chooses it.
const std::initializer_list<const char*>& flatMethodSettings();

// The names of the enumerated settings' values, as the CLI takes them.
const std::vector<std::pair<std::string, SolverKind>>& solverNames();
const std::vector<std::pair<std::string, MeshStrategy>>& methodNames();
const std::vector<std::pair<std::string, FormFactorMethod>>& formFactorNames();

// One setting by its CLI name, for programs that take settings by name (the Python module): a
// number, a flag or a name (of a solver, method, form-factor method, or a directory). An error
// names an unknown setting, a value of the wrong kind or outside the CLI's range, and says what
// is allowed.
using SettingValue = std::variant<bool, std::int64_t, double, std::string>;
Status setSolveSetting(RadiositySettings& settings, std::string_view cliName, const SettingValue& value);
// Every name setSolveSetting takes, in the CLI's order.
std::vector<std::string> solveSettingNames();

// The inclusive range the CLI allows for a numeric setting.
struct SettingRange {
  double least, most;
};
SettingRange solveSettingRange(std::string_view cliName);

}  // namespace lambert
