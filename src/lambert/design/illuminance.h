#pragma once
// Illuminance at calculation points: what a lighting designer asks of a solved scene ("how many
// lux reach this desk"), at any point and facing any way — on a face, or in the air above the
// floor where a work plane lies (the points of design/calculation_grid.h).
//
// The irradiance E at a point x with unit normal n is split as lighting programs report it:
//  - direct: from every light (point, spot, directional, luminaire, sky), with shadow rays (Ward's
//    adaptive testing over many lights, light/many_lights.h: within shadowTolerance × the
//    unoccluded light), plus the emitting surfaces' own emission. An emitting surface
//    whose light at x may matter (its bound B_e·min(1, A cos⁺ cos⁺/(π (d − r)²)) over its bounding
//    sphere, the cosines' bounds from the sphere too, at least 2% of the largest
//    emitter's bound there) is integrated explicitly: each of its triangles gives B_e·F·V̄, F its
//    exact unoccluded point-to-polygon form factor (Lambert's contour integral, F = 1/(2π) Σ_i θ_i
//    n·û_i over its edges, after clipping it to the half-space in front of x), V̄ the
//    kernel-weighted visible fraction (weights cos θ_x cos θ_y / r²) of stratified points on it,
//    `emitterSamples` per surface, each in a triangle picked in proportion to its factor, and four
//    times as many where those disagree (a penumbra: 16 gave 7% there on the Cornell floor). Exact
//    where the emitter is wholly visible or wholly hidden; consistent in between. An emitter
//    under a quarter of the largest bound is integrated so only where one probe ray to it finds
//    it visible (another room's lamp costs a ray, not emitterSamples). The other
//    emitters (a building's other rooms, small far lamps) are counted by the hemisphere rays
//    below where they meet them: the two estimators split the emitters, so none is counted twice.
//  - indirect: the light the surfaces reflect, ∫ L_r cos θ dω over the hemisphere about n, from
//    `indirectRays` cosine-weighted stratified directions (a scrambled (0,2)-sequence):
//    E_ind = (1/N) Σ ρ_hit E_hit, where E_hit is the solution's irradiance at the hit
//    (SolutionView::vertexValues(Irradiance) interpolated over the hit patch) and ρ_hit its
//    albedo, so that the emission is not counted twice. A ray that meets a back face or nothing
//    brings nothing. Every point uses the same directions (in its own frame): the estimate's error
//    is then a smooth field over a grid of points, not speckle that would break isolux lines.
//    Bright reflectors — elements whose ρE is at least 8× the scene's area-weighted mean (the
//    ceiling over an uplight, a sun patch), at most 8192 — are integrated as the emitters are
//    (exact factors, sampled visibility) where they may matter, and the hemisphere rays leave
//    them out there: 256 rays sample a small bright spot poorly (25% between mirror-image points
//    under RenderPark's examp1.ies pendant; docs/photometry.md).
//
// Cost: per point, a shadow ray per light that faces it, emitterSamples rays per emitting
// triangle in front of it, and indirectRays rays; the solution's vertex irradiance once (the
// hierarchical method's final gather at the vertices). Parallel over points; the result does not
// depend on the thread count.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"

namespace lambert {

struct Mesh;
class RayCaster;
class SolutionView;

// A point the illuminance is asked for, in the scene's frame and units (y up).
struct CalculationPoint {
  Vec3 position;
  Vec3 normal;  // unit: the side whose light is measured (up for a work plane)
};

// The irradiance at a point, W/m² (RGB), as it is reported: lux = illuminanceLux(E)
// (core/photometric.h).
struct PointIrradiance {
  Rgb direct;    // lights and emitting surfaces, with their shadows
  Rgb sky;       // of which from skies (light/sky.h): the sky component
  Rgb sun;       // of which from directional lights (suns)
  Rgb indirect;  // reflected by the surfaces
  Rgb total() const { return direct + indirect; }
};

struct IlluminanceOptions {
  int indirectRays = 256;   // hemisphere directions per point (rounded up to a power of two)
  int emitterSamples = 16;  // visibility samples per emitting surface integrated explicitly at a point
  // The lights' shadow testing (light/many_lights.h, Ward's adaptive testing): at most this share of
  // a point's unoccluded direct light is left untested; 0 traces a ray to every light that reaches.
  double shadowTolerance = 0.01;
  std::uint64_t seed = 1;
  bool showProgress = false;  // a progress line on a terminal
};

// The hemisphere directions every point's indirect light is gathered along, each in the point's own
// frame (z along its normal): a scrambled (0,2)-sequence of `rays` rounded up to a power of two,
// mapped to the cosine-weighted hemisphere (Malley's method: the unit disc lifted onto it), so that
// E = (π/N)·Σ L along them.
std::vector<Vec3> cosineDirections(int rays, std::uint64_t seed);

// Measures the irradiance at points of a solved scene. Made once per solution (it takes the
// solution's vertex irradiance and builds a ray caster over its vertex mesh), then asked for as
// many points as wanted. The solution must outlive it and stay unchanged while it is used.
class IlluminanceMeter {
 public:
  IlluminanceMeter(const SolutionView& solution, const IlluminanceOptions& options = {});
  ~IlluminanceMeter();
  IlluminanceMeter(IlluminanceMeter&&) noexcept;
  IlluminanceMeter& operator=(IlluminanceMeter&&) noexcept;

  // An Error for a point whose normal is not a finite non-zero vector (naming its index).
  Result<std::vector<PointIrradiance>> measure(std::span<const CalculationPoint> points) const;
  // Rays cast by measure() so far (shadow rays, emitter visibility and hemisphere rays).
  std::uint64_t raysCast() const;
  // Seconds spent making the meter (mostly the solution's vertex irradiance).
  double setupSeconds() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace lambert
