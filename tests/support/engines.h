#pragma once
// Engines for the tests: the options they start from, a scene solved through the front door
// (Radiosity::create, then solve), the figures its stats report, and the path tracer's options
// to check them against. Every failure on the way is a test failure naming why, never a crash:
// the helpers return null or an empty report instead.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "lambert/engine/radiosity.h"
#include "lambert/reference/reference.h"

namespace lambert::testing {

// The library's defaults (the hierarchical method, Gauss–Seidel to its tolerance) without the
// flat method's progress line.
inline RadiosityOptions quietOptions() {
  RadiosityOptions options;
  options.formFactors.showProgress = false;
  return options;
}

// The flat method on a uniform mesh of about `patches` patches, the rest as quietOptions().
inline RadiosityOptions uniformOptions(std::size_t patches, SolverKind solver = RadiosityOptions{}.solver) {
  RadiosityOptions options = quietOptions();
  options.meshing = MeshStrategy::Uniform;
  options.uniform.targetPatches = patches;
  options.solver = solver;
  return options;
}

// The form-factor estimators' options, called without an engine, without the progress line.
inline FormFactorOptions quietFormFactorOptions() {
  FormFactorOptions options;
  options.showProgress = false;
  return options;
}

// The path tracer's options at `vertexSamples` a vertex and `samplesPerPixel` a pixel, without
// its progress line.
inline ReferenceOptions quietReferenceOptions(int vertexSamples, int samplesPerPixel = ReferenceOptions{}.samplesPerPixel) {
  ReferenceOptions options;
  options.vertexSamples = vertexSamples;
  options.samplesPerPixel = samplesPerPixel;
  options.showProgress = false;
  return options;
}

// An engine for the scene; null (after a test failure) where create refuses it.
inline std::unique_ptr<Radiosity> engineFor(const Scene& scene, const RadiosityOptions& options) {
  Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(scene, options);
  EXPECT_TRUE(engine.ok()) << engine.error().message;
  return engine.ok() ? std::move(*engine) : nullptr;
}

// One solve() within the budget: its report, or an empty one after a test failure.
inline SolveReport solveCall(Radiosity& engine, const SolveBudget& budget = {}) {
  Result<SolveReport> report = engine.solve(budget);
  EXPECT_TRUE(report.ok()) << report.error().message;
  return report.ok() ? *report : SolveReport{};
}

// The engine after its first solve, with no budget: it must reach the options' tolerance.
inline std::unique_ptr<Radiosity> solved(const Scene& scene, const RadiosityOptions& options = quietOptions()) {
  std::unique_ptr<Radiosity> engine = engineFor(scene, options);
  if (!engine) return nullptr;
  EXPECT_TRUE(solveCall(*engine).converged) << "the solve stopped before its tolerance";
  return engine;
}

// The same under `lights` instead of the scene's own.
inline std::unique_ptr<Radiosity> solved(const Scene& scene, const RadiosityOptions& options, std::vector<Light> lights) {
  std::unique_ptr<Radiosity> engine = engineFor(scene, options);
  if (!engine) return nullptr;
  engine->setLights(std::move(lights));
  EXPECT_TRUE(solveCall(*engine).converged) << "the solve stopped before its tolerance";
  return engine;
}

// A count the stats report; -1 (after a test failure) where there is none.
inline std::int64_t statCount(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (!entry || !std::holds_alternative<std::int64_t>(entry->value)) {
    ADD_FAILURE() << "no count " << key;
    return -1;
  }
  return std::get<std::int64_t>(entry->value);
}

// A number the stats report (a count or a real); NaN (after a test failure) where there is none.
inline double statNumber(const Stats& stats, const std::string& key) {
  const Stats::Entry* entry = stats.find(key);
  if (const auto* count = entry ? std::get_if<std::int64_t>(&entry->value) : nullptr) return static_cast<double>(*count);
  if (const auto* real = entry ? std::get_if<double>(&entry->value) : nullptr) return *real;
  ADD_FAILURE() << "no number " << key;
  return NAN;
}

}  // namespace lambert::testing
