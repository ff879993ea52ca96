#pragma once
// lambert's one entry point: a radiosity solve of a scene that it owns from start to finish.
//
//   auto engine = Radiosity::create(scene, options);   // mesh, BVH, form factors (cached)
//   (*engine)->solve();                                 // inject the lights, solve to tolerance
//   const SolutionView& view = (*engine)->solution();   // B, vertex values, what to draw
//   (*engine)->setLights(moved);                        // next frame: lights move …
//   (*engine)->solve({.maxSweeps = 1});                 // … re-solved warm, within a budget
//
// The engine owns the mesh, the ray caster over it and the transport between its elements (the
// links of the element hierarchy, by default; the dense form-factor matrix of a uniform mesh, or
// the master table of an adaptive quad-tree; see method/method.h). It is created behind a unique_ptr and can be neither copied nor moved, so
// the views and references it hands out stay valid for its whole life. See docs/api.md.
#include <memory>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/stats.h"
#include "lambert/method/options.h"
#include "lambert/method/solution.h"
#include "lambert/method/solve_call.h"
#include "lambert/light/lights.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Held by rank 0 of a distributed solve while it computes its outputs (Radiosity::
// leadDistributedOutputs); letting go of it lets the other ranks go. An opaque handle.
class DistributedOutputs {
 public:
  DistributedOutputs(DistributedOutputs&& other) noexcept;
  DistributedOutputs& operator=(DistributedOutputs&&) = delete;
  ~DistributedOutputs();

 private:
  friend class Radiosity;
  struct Lead;  // engine/radiosity.cpp
  explicit DistributedOutputs(std::unique_ptr<Lead> lead);
  std::unique_ptr<Lead> lead_;  // null: one process, or moved from
};

// The uniform mesh an engine with these options solves on, for tools that need its vertices
// without solving (the reference path tracer).
Mesh uniformMesh(const Scene& scene, const UniformMeshOptions& options);

// The vertex mesh an engine with these options exports after its first solve()
// (SolutionView::vertexMesh, what `lambert solve --export-vertices` writes), vertex for vertex in
// the same order, for tools that evaluate something else at those vertices (the reference path
// tracer). The uniform mesh is made directly, without form factors. The hierarchical and adaptive
// elements follow the lights and the solution, so an engine is created and solved with these
// options (no final gather): that solve's cost, and its errors.
Result<Mesh> solutionVertexMesh(const Scene& scene, RadiosityOptions options);

class Radiosity {
 public:
  // Meshes the scene, builds the ray caster and (uniform meshing) computes or loads the form
  // factors. Fails, saying why, for combinations that cannot work (an adaptive mesh of a scene
  // that is not all quads, or with a row-wise form-factor method). The scene's lights are the
  // initial lights.
  static Result<std::unique_ptr<Radiosity>> create(Scene scene, RadiosityOptions options);
  ~Radiosity();
  Radiosity(const Radiosity&) = delete;
  Radiosity& operator=(const Radiosity&) = delete;

  // The lights for the next solve(): any number, in any order. Lights equal to the one at the
  // same index last time are not traced again.
  void setLights(std::vector<Light> lights);
  const std::vector<Light>& lights() const;

  // Brings the solution up to date: (adaptive) refines the mesh, injects the lights that
  // changed, and solves warm from the last state, to the tolerance or within the budget.
  // Errors: a budget the solver cannot honour (shots for gs, sweeps for shoot, any for direct).
  Result<SolveReport> solve(const SolveBudget& budget = {});

  // The current solution. Valid for the engine's life; its contents change with solve().
  const SolutionView& solution() const;

  // Figures describing the current solution and how it was made: mesh, form factors and cache,
  // lights, solver (iterations and convergence of the last solve, times summed over all),
  // residual, energy balance in watts. Keys are stable (README lists them).
  Stats stats() const;

  // Writes what the cache directory should keep that creation did not already write (the
  // adaptive master table, grown by refinement); Ok, doing nothing, otherwise. A failure is also
  // reported through warning() and never affects the solution.
  Status saveCache();
  // A distributed solve's outputs (RadiosityOptions::communicator, docs/distributed.md): after
  // solve(), rank 0 computes and writes them while it holds the lead this returns, and every other
  // rank calls serveDistributedOutputs(). Each final gather rank 0 asks for (the vertices', and at
  // points: lightmap texels, meter points) is then spread over all the ranks, each gathering at
  // the points on its own leaves through its own links, and serveDistributedOutputs() returns when
  // rank 0 lets go of the lead (on any path out). Nothing for one process.
  [[nodiscard]] DistributedOutputs leadDistributedOutputs();
  void serveDistributedOutputs();

  const Scene& scene() const;
  const RadiosityOptions& options() const;

 private:
  friend struct SolutionInternals;  // engine/radiosity.cpp: what the view reads
  struct Impl;                      // the engine's state and its steps (engine/radiosity.cpp)
  Radiosity(Scene scene, RadiosityOptions options);
  std::unique_ptr<Impl> impl_;
};

}  // namespace lambert
