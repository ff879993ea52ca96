#include "lambert/engine/radiosity_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include "lambert/flat/form_factors.h"

namespace lambert {

const RadiosityOptions& defaultRadiosityOptions() {
  static const RadiosityOptions defaults{};
  return defaults;
}

namespace {

std::string defaultCacheDirectory() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/lambert";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/lambert";
  return ".lambert-cache";
}

template <typename Enum>
std::string namesOf(const std::vector<std::pair<std::string, Enum>>& names) {
  std::string out;
  for (const auto& [name, value] : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

std::string shortNumber(double x) {
  std::ostringstream out;
  out << std::setprecision(6) << x;
  return out.str();
}

// Each named setting: its range (numbers) and how a value sets it.
struct SettingRule {
  const char* name;
  SettingRange range;
  std::function<Status(RadiositySettings&, const SettingValue&)> set;
};

Result<double> number(std::string_view name, const SettingValue& value) {
  if (const auto* d = std::get_if<double>(&value)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&value)) return static_cast<double>(*i);
  return Error{std::string(name) + " takes a number"};
}

template <typename T>
SettingRule numeric(const char* name, SettingRange range, T RadiositySettings::*field, bool whole) {
  return {name, range, [=](RadiositySettings& s, const SettingValue& value) -> Status {
            Result<double> x = number(name, value);
            if (!x) return x.error();
            if (!(std::isfinite(*x) && *x >= range.least && *x <= range.most))
              return Error{std::string(name) + " must lie in [" + shortNumber(range.least) + ", " + shortNumber(range.most) + "], not " + shortNumber(*x)};
            if (whole && *x != std::floor(*x)) return Error{std::string(name) + " takes a whole number, not " + shortNumber(*x)};
            s.*field = static_cast<T>(*x);
            return Ok{};
          }};
}

SettingRule flag(const char* name, bool RadiositySettings::*field) {
  return {name, {0, 1}, [=](RadiositySettings& s, const SettingValue& value) -> Status {
            const auto* b = std::get_if<bool>(&value);
            if (!b) return Error{std::string(name) + " takes true or false"};
            s.*field = *b;
            return Ok{};
          }};
}

template <typename Enum>
SettingRule named(const char* name, Enum RadiositySettings::*field, const std::vector<std::pair<std::string, Enum>>& names) {
  return {name, {0, 0}, [=, &names](RadiositySettings& s, const SettingValue& value) -> Status {
            const auto* text = std::get_if<std::string>(&value);
            const auto it = text ? std::find_if(names.begin(), names.end(), [&](const auto& n) { return n.first == *text; }) : names.end();
            if (it == names.end()) return Error{std::string(name) + " takes one of " + namesOf(names)};
            s.*field = it->second;
            return Ok{};
          }};
}

const std::vector<SettingRule>& settingRules() {
  static const std::vector<SettingRule> rules = {
      numeric("--patches", {1, 200000}, &RadiositySettings::patches, true),
      numeric("--max-edge", {1e-9, 1e12}, &RadiositySettings::maxEdge, false),
      numeric("--seed", {0, 1.8e19}, &RadiositySettings::seed, true),
      named("--formfactor", &RadiositySettings::formFactor, formFactorNames()),
      {"--hemicube-resolution", {2, 4096}, [](RadiositySettings& s, const SettingValue& v) -> Status {
         Status set = numeric("--hemicube-resolution", {2, 4096}, &RadiositySettings::hemicubeResolution, true).set(s, v);
         if (set && s.hemicubeResolution % 2 != 0) return Error{"--hemicube-resolution must be even"};
         return set;
       }},
      numeric("--hemisphere-rays", {1, 1 << 24}, &RadiositySettings::hemisphereRays, true),
      numeric("--samples", {1, 4096}, &RadiositySettings::samples, true),
      numeric("--light-samples", {1, 4096}, &RadiositySettings::lightSamples, true),
      numeric("--shadow-tolerance", {0, 0.5}, &RadiositySettings::shadowTolerance, false),
      named("--solver", &RadiositySettings::solver, solverNames()),
      numeric("--tolerance", {1e-15, 1}, &RadiositySettings::tolerance, false),
      numeric("--max-iterations", {1, 1000000}, &RadiositySettings::maxIterations, true),
      {"--cache-dir", {0, 0}, [](RadiositySettings& s, const SettingValue& v) -> Status {
         const auto* text = std::get_if<std::string>(&v);
         if (!text) return Error{"--cache-dir takes a directory"};
         s.cacheDir = *text;
         return Ok{};
       }},
      flag("--no-cache", &RadiositySettings::noCache),
      flag("--normalize-rows", &RadiositySettings::normalizeRows),
      named("--method", &RadiositySettings::method, methodNames()),
      numeric("--link-error", {1e-12, 1}, &RadiositySettings::linkError, false),
      numeric("--min-area", {1e-30, 1e30}, &RadiositySettings::minElementArea, false),
      numeric("--visibility-rays", {1, 255}, &RadiositySettings::visibilityRays, true),
      flag("--no-clusters", &RadiositySettings::noClusters),
      numeric("--refine-passes", {1, 20}, &RadiositySettings::refinePasses, true),
      numeric("--memory-limit", {1, 1e18}, &RadiositySettings::memoryLimitBytes, false),
      flag("--adaptive", &RadiositySettings::adaptive),
      numeric("--base-edge", {1e-9, 1e12}, &RadiositySettings::baseEdge, false),
      numeric("--max-level", {0, 8}, &RadiositySettings::maxLevel, true),
      numeric("--gradient-threshold", {0, 1e6}, &RadiositySettings::gradientThreshold, false),
      numeric("--adapt-passes", {1, 20}, &RadiositySettings::adaptPasses, true),
  };
  return rules;
}

}  // namespace

const std::vector<std::pair<std::string, SolverKind>>& solverNames() {
  static const std::vector<std::pair<std::string, SolverKind>> names{
      {"gs", SolverKind::GaussSeidel}, {"jacobi", SolverKind::Jacobi}, {"direct", SolverKind::Direct}, {"shoot", SolverKind::Shooting}};
  return names;
}

const std::vector<std::pair<std::string, MeshStrategy>>& methodNames() {
  static const std::vector<std::pair<std::string, MeshStrategy>> names{{"hierarchical", MeshStrategy::Hierarchical},
                                                                       {"flat", MeshStrategy::Uniform}};
  return names;
}

const std::vector<std::pair<std::string, FormFactorMethod>>& formFactorNames() {
  static const std::vector<std::pair<std::string, FormFactorMethod>> names{{"mc", FormFactorMethod::AreaMonteCarlo},
                                                                           {"point", FormFactorMethod::PointToPoint},
                                                                           {"hemicube", FormFactorMethod::Hemicube},
                                                                           {"hemisphere", FormFactorMethod::HemisphereRays}};
  return names;
}

Status setSolveSetting(RadiositySettings& settings, std::string_view cliName, const SettingValue& value) {
  for (const SettingRule& rule : settingRules())
    if (cliName == rule.name) return rule.set(settings, value);
  std::string known;
  for (const std::string& name : solveSettingNames()) known += (known.empty() ? "" : ", ") + name;
  return Error{"no setting " + std::string(cliName) + "; the settings are " + known};
}

std::vector<std::string> solveSettingNames() {
  std::vector<std::string> names;
  for (const SettingRule& rule : settingRules()) names.emplace_back(rule.name);
  return names;
}

SettingRange solveSettingRange(std::string_view cliName) {
  for (const SettingRule& rule : settingRules())
    if (cliName == rule.name) return rule.range;
  return {0, 0};
}

const std::initializer_list<const char*>& flatMethodSettings() {
  static const std::initializer_list<const char*> options = {
      "--patches", "--max-edge", "--adaptive", "--formfactor", "--samples", "--hemicube-resolution", "--hemisphere-rays",
      "--normalize-rows"};
  return options;
}

UniformMeshOptions uniformMeshOptions(const Scene& scene, const RadiositySettings& o, const GivenSetting& given) {
  if (given("--patches") || given("--max-edge") || (scene.defaults.patches == 0 && scene.defaults.maxEdgeLength == 0))
    return {o.patches, o.maxEdge};
  return {scene.defaults.patches > 0 ? scene.defaults.patches : o.patches, scene.defaults.maxEdgeLength};
}

Result<RadiosityOptions> radiosityOptions(const Scene& scene, const RadiositySettings& o, const GivenSetting& given) {
  const auto refuseGiven = [&](std::initializer_list<const char*> options, const std::string& why) -> Status {
    for (const char* option : options)
      if (given(option)) return Error{std::string(option) + " has no effect: " + why};
    return Ok{};
  };
  // Each setting the chosen path would not read is refused, saying what reads it.
  struct Rule {
    bool unused;
    std::initializer_list<const char*> options;
    std::string why;
  };
  // The scene file's defaults, where the settings do not say.
  SolverKind solver = o.solver;
  if (!given("--solver") && !scene.defaults.solver.empty()) {
    const auto& names = solverNames();
    const auto it = std::find_if(names.begin(), names.end(), [&](const auto& n) { return n.first == scene.defaults.solver; });
    if (it == names.end()) return Error{"scene '" + scene.name + "': its default solver '" + scene.defaults.solver + "' is none of " + namesOf(names)};
    solver = it->second;
  }
  const bool solverNamed = given("--solver") || !scene.defaults.solver.empty();
  const bool needsMatrix = solver == SolverKind::Shooting || solver == SolverKind::Direct;
  // The method: --method, or hierarchical unless something asks for a flat one: a mesh size
  // (in the settings or the scene file), a form-factor setting, or a solver that needs the
  // dense matrix. Settings every method reads (the cache, threads, budgets, outputs) choose none.
  bool hierarchical = o.method == MeshStrategy::Hierarchical;
  if (!given("--method")) {
    bool flatAsked = scene.defaults.patches > 0 || scene.defaults.maxEdgeLength > 0 || (solverNamed && needsMatrix);
    for (const char* option : flatMethodSettings()) flatAsked |= given(option);
    hierarchical = !flatAsked;
  }
  // The hierarchical method gathers over links: where nothing chose a solver, a command whose
  // own default needs the dense matrix (animate's shoot) gathers with gs instead.
  if (hierarchical && !solverNamed && needsMatrix) solver = SolverKind::GaussSeidel;
  const double tolerance = !given("--tolerance") && scene.defaults.tolerance > 0 ? scene.defaults.tolerance : o.tolerance;
  const bool mc = o.formFactor == FormFactorMethod::AreaMonteCarlo;
  const std::string method = formFactorMethodName(o.formFactor);
  const Rule rules[] = {
      {hierarchical, flatMethodSettings(),
       "it is for --method flat; the hierarchical method sizes its elements by --link-error and --min-area"},
      {!hierarchical, {"--link-error", "--min-area", "--visibility-rays", "--no-clusters", "--refine-passes"},
       "it applies to --method hierarchical only"},
      {o.adaptive, {"--patches", "--max-edge"}, "they size the uniform mesh; --adaptive cells are sized by --base-edge and --max-level"},
      {!o.adaptive, {"--base-edge", "--max-level", "--gradient-threshold", "--adapt-passes"}, "it applies to --adaptive meshing only"},
      {!mc, {"--samples"}, "sample pairs are for --formfactor mc, not " + method},
      {o.formFactor != FormFactorMethod::Hemicube, {"--hemicube-resolution"}, "it is for --formfactor hemicube, not " + method},
      {o.formFactor != FormFactorMethod::HemisphereRays, {"--hemisphere-rays"}, "it is for --formfactor hemisphere, not " + method},
      {solver == SolverKind::Direct, {"--tolerance", "--max-iterations"}, "the direct solver is exact; they are for gs, jacobi and shoot"},
      {o.noCache, {"--cache-dir"}, "--no-cache turns the cache off"},
      {scene.lights.empty(), {"--light-samples", "--shadow-tolerance"}, "scene '" + scene.name + "' has no point, spot or directional lights"},
  };
  for (const Rule& rule : rules)
    if (rule.unused)
      if (Status refused = refuseGiven(rule.options, rule.why); !refused) return refused.error();

  RadiosityOptions r;
  r.meshing = hierarchical ? MeshStrategy::Hierarchical : o.adaptive ? MeshStrategy::Adaptive : MeshStrategy::Uniform;
  r.hierarchical.links.linkError = o.linkError;
  r.hierarchical.links.minElementArea = o.minElementArea;
  r.hierarchical.links.visibilityRays = o.visibilityRays;
  r.hierarchical.links.clusters = !o.noClusters;
  r.hierarchical.links.seed = o.seed;
  r.hierarchical.links.showProgress = o.showProgress;
  r.hierarchical.refinePasses = o.refinePasses;
  r.uniform = uniformMeshOptions(scene, o, given);
  r.adaptive.quadtree.baseEdgeLength = o.baseEdge;
  r.adaptive.quadtree.maxLevel = o.maxLevel;
  r.adaptive.gradientThreshold = o.gradientThreshold;
  r.adaptive.passesPerSolve = o.adaptPasses;
  r.formFactors.method = o.formFactor;
  r.formFactors.samplePairs = o.samples;
  r.formFactors.hemicubeResolution = o.hemicubeResolution;
  r.formFactors.hemisphereRays = o.hemisphereRays;
  r.formFactors.seed = o.seed;
  r.formFactors.showProgress = o.showProgress;
  r.normalizeRows = o.normalizeRows;
  r.directLight.samplesPerPatch = o.lightSamples;
  r.directLight.shadowTolerance = o.shadowTolerance;
  r.directLight.seed = o.seed;
  r.solver = solver;
  r.tolerance = tolerance;
  r.maxIterations = o.maxIterations;
  r.memoryLimitBytes = o.memoryLimitBytes;
  r.cacheDirectory = o.noCache ? "" : (o.cacheDir.empty() ? defaultCacheDirectory() : o.cacheDir);
  return r;
}

}  // namespace lambert
