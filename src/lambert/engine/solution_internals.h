#pragma once
// What the library's own consumers read behind a SolutionView and a program using lambert does
// not: the system the solver last solved, and the hierarchical method's final gather at points
// and at vertices as weights on the node means (method/point_gather.h), which lightmap updates
// (bake/lightmap_updates.h) apply again after the light changes. Internal, not installed: their
// types are the solvers' and the gathers'. The view itself keeps what a user calls, the light at
// points (SolutionView::pointIrradiance). Each reads the engine's current state, as the view does.
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/method/point_gather.h"
#include "lambert/method/solution.h"

namespace lambert {

struct RadiosityProblem;  // solve/solver.h

// The system the solver last solved, B = E + ρFB (E here includes the injected light), for
// programs that solve it another way.
const RadiosityProblem& radiosityProblem(const SolutionView& view);

// The element radiosity B = E + ρFB (W/m²) that `injected` (E per element of view.mesh(): a light's
// ρ·E_direct) alone gives, solved over the engine's transport by its gathering solver to its
// tolerance, from B = E; the engine's own solution is untouched. A daylight coefficient's response
// to one sky patch or one sun (design/daylight_coefficients.h).
std::vector<Rgb> radiosityFromInjected(const SolutionView& view, std::vector<Rgb> injected);

// SolutionView::pointIrradiance's two parts apart: where each point is gathered (the site shadow
// rays to the lights start from), the light from the surfaces there, and the weights that give
// that light again from a later solution, as `part` asks (method/point_gather.h). Hierarchical
// only (an Error for the others).
Result<PointGather> pointGather(const SolutionView& view, std::span<const SurfacePoint> points, PointGatherRequest part);
// The lights' direct light at a point gather's sites (shadow rays from rayEpsilon above them),
// W/m², as SolutionView::pointIrradiance adds it to the light from the surfaces.
std::vector<Rgb> directIrradiance(const SolutionView& view, std::span<const VertexSite> sites, double rayEpsilon);
// The same at vertices of the view's vertexMesh(), where vertexValues gathers them (their sites),
// for what their radiosity B = E + ρ (E_surfaces + E_lights) will be after the light changes.
Result<PointGather> vertexGather(const SolutionView& view, std::span<const std::uint32_t> vertices, PointGatherRequest part);
// Per node of the hierarchy (the hierarchical method's elements and clusters): the mean
// radiosity B̄ of the leaves under it, W/m², what PointGather's node weights multiply.
// Hierarchical only (an Error for the others).
Result<std::vector<Rgb>> nodeMeanRadiosity(const SolutionView& view);

}  // namespace lambert
