#pragma once
// Direct light from many lights at a point without a shadow ray per light: Ward's adaptive
// shadow testing (G. Ward, "Adaptive Shadow Testing for Ray Tracing", 2nd Eurographics Workshop
// on Rendering, 1991).
//
// At a receiving point x with normal n, every light's unoccluded irradiance E_l(x) is computed
// first: arithmetic only, no ray. A light behind the surface, outside a spot's cone, or (an area
// of zero intensity) in a direction it does not emit gives 0 and is dropped there (the cull by
// side and cone). The rest are taken in decreasing order of E_l and given a shadow ray each, until
// the untested remainder R = Σ_untested E_l is at most τ of the total unoccluded irradiance
// U = Σ_l E_l, in every channel. The remainder is added weighted by the visibility ratio of the
// tested lights, Σ_tested V_l E_l / Σ_tested E_l (Ward's estimate). Far lights and dim ones (the
// cull by distance and contribution) are the ones that end in the remainder: their share falls as
// I/d², so a light's distance decides only through its contribution, and no range is guessed.
//
// The bound: the untested lights' true share Σ_untested V_l E_l lies in [0, R], and so does what is
// added for them (R times a ratio in [0, 1]), so in each channel
//     |E(x) − E_exact(x)| ≤ R ≤ τ · U(x),
// where E_exact is the every-light, every-ray sum. Since U ≥ E_exact, the bound is also a fraction
// of the unoccluded light, never of the shadowed one: a point in a dark corner lit by one of 200
// lights through a gap may be off by τ of what it would receive unoccluded (the test in
// many_lights_test.cpp builds that case). τ = 0 is the exact sum (every light with E_l > 0 its
// ray, in the lights' order, bit for bit what lights.h's irradiance() summed over the lights gives).
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

// What one DirectLighting evaluation did, for statistics.
struct DirectLightingCounts {
  std::uint64_t points = 0;          // receivers evaluated
  std::uint64_t lightsReaching = 0;  // Σ over points of the lights with E_l > 0 there
  std::uint64_t shadowRays = 0;      // rays traced
  void add(const DirectLightingCounts& o) {
    points += o.points;
    lightsReaching += o.lightsReaching;
    shadowRays += o.shadowRays;
  }
};

// The lights a region of receivers (a sphere about a centre, facing n: a patch, an element, or a
// point with radius 0) needs evaluated at its points: `kept`, and `dropped`, whose upper bounds on
// E_l anywhere in the region sum to `droppedBound` (W/m² per channel). A point of the region
// evaluates only the kept lights, and drops the rest when droppedBound ≤ τ/2 of its kept lights'
// unoccluded sum there (else it evaluates them too): the cull by distance and cone without an
// evaluation per light and point, bounded like the rest.
struct LightSelection {
  std::vector<std::uint32_t> kept, dropped;
  Rgb droppedBound;
};

class DirectLighting {
 public:
  // `tolerance` τ in [0, 1): the untested share of the unoccluded irradiance allowed at a point.
  // metresPerUnit converts scene distances so that the inverse-square law is in metres.
  DirectLighting(std::span<const Light> lights, double metresPerUnit, double tolerance);

  // E(x) in W/m², shadow rays from x lifted by epsilon along n, as described above. Thread safe.
  Rgb irradiance(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, DirectLightingCounts* counts = nullptr) const;
  // The same for a point of a region `selection` was made for (select()): the lights it kept are
  // evaluated, the dropped ones only where their bound is not small enough there. The bound
  // becomes |E − E_exact| ≤ τ/2·U (Ward's, over the evaluated lights) + τ/2·U (the dropped) when
  // any light was dropped.
  Rgb irradiance(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, const LightSelection& selection,
                 DirectLightingCounts* counts = nullptr) const;
  // The selection for receivers within `radius` of `centre` facing n (exact(): every light kept).
  void select(const Vec3& centre, double radius, const Vec3& n, LightSelection& out) const;
  // An upper bound on E_l(x) over x within `radius` of `centre` facing n, per channel; INFINITY
  // where none is known (a directional light, a light inside the region, a kind not bounded).
  Rgb upperBound(std::size_t light, const Vec3& centre, double radius, const Vec3& n) const;

  // U(x) = Σ_l E_l(x), no rays.
  Rgb unoccluded(const Vec3& x, const Vec3& n) const;
  // One light's E_l(x), no ray: unshadowedIrradiance up to rounding, the cone's cosines
  // precomputed.
  Rgb unoccluded(std::size_t light, const Vec3& x, const Vec3& n) const { return contribution(light, x, n); }

  bool exact() const { return tolerance_ <= 0; }
  double tolerance() const { return tolerance_; }
  std::size_t size() const { return lights_.size(); }

 private:
  // A point or spot light with what its E_l needs precomputed (the spot's cone cosines, which
  // lights.cpp's spotFalloff computes per call); any other kind through unshadowedIrradiance.
  struct Prepared {
    Vec3 position, axis;
    Rgb intensityPerSquareMetre;  // I / metresPerUnit² (luminaire: per candela, tilt included)
    double cosOuter = -2, cosInner = -2, sinOuter = 0;
    bool fast = false, spot = false;
    // A far-field luminaire: its frame and, per measured vertical angle γ_k, the largest candela
    // of any plane at γ_k or beyond (candela interpolates monotonically between measured angles,
    // so no direction at γ ≥ γ_k exceeds it).
    bool luminaire = false;
    LuminaireFrame frame;
    std::vector<double> candelaBeyond;
  };
  Rgb contribution(std::size_t l, const Vec3& x, const Vec3& n) const;
  Rgb ward(const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon, std::span<const std::uint32_t> lights,
           std::span<const std::uint32_t> more, const Rgb& droppedBound, DirectLightingCounts* counts) const;

  std::vector<Light> lights_;
  std::vector<Prepared> prepared_;
  double metresPerUnit_;
  double tolerance_;
};

// Each listed patch's mean direct irradiance from all the lights together, W/m², over the same
// low-discrepancy points lights.h's patchIrradiance averages one light over (options'
// samplesPerPatch and seed), each point's E by `lighting`; the other entries are left as they
// are. With an exact `lighting` it is the sum over the lights of patchIrradiance up to rounding.
void patchIrradiance(const Mesh& mesh, const RayCaster& caster, const DirectLighting& lighting, const DirectLightOptions& options,
                     double epsilon, std::span<const std::uint32_t> patches, std::vector<Rgb>& irradiance,
                     DirectLightingCounts* counts = nullptr);

}  // namespace lambert
