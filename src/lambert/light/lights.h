#pragma once
// Direct light from point, spot and directional lights (after Keller's "Instant
// Radiosity", 1997): the irradiance a light gives a surface point, with a shadow ray through the
// RayCaster, and its average over each patch. A patch's share, ρ·E_direct, is injected into the
// radiosity system as if the patch emitted it; the solver then adds every bounce after the first.
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Hermite smoothstep: 0 below edge0, 1 above edge1, 3t² − 2t³ between (a step where they are equal).
double smoothstep(double edge0, double edge1, double x);

// The spot's smooth edge: 1 inside the inner cone, 0 outside coneAngle, smoothstep between.
double spotFalloff(const Light& spot, const Vec3& towardPoint);

// A luminaire's photometric axes in the scene: the nadir (γ = 0, its aim) and the directions of
// its C = 0° and C = 90° half planes (C turns from c0 toward c90, counter-clockwise seen from
// above a luminaire aimed down: for the default aim −y and no rotation, c0 = +x and c90 = −z).
struct LuminaireFrame {
  Vec3 nadir, c0, c90;
};

// Luminaire aiming after IES LM-72 as AGi32 and Photometric Toolbox apply it ("counter-clockwise
// from east"), in degrees. With all four 0 the luminaire points straight down, C0 due east (+x),
// C90 due north (−z). Applied in this order, each about the luminaire's axes as the turns before
// left them (frame = R_orient · R_tilt · R_roll · R_spin applied to C0 = east, C90 = north,
// nadir = down):
//   orient: about the vertical, east toward north (counter-clockwise seen from above);
//   tilt:   about the C90 axis, the nadir toward C0 (a positive tilt lifts the aim on the C0 side:
//           orient 0, tilt 90 aims due east at the horizon; orient 90, tilt 90 due north);
//   roll:   about the C0 axis, the nadir toward C90;
//   spin:   about the nadir's axis, C0 toward C90 (counter-clockwise seen from above a downlight).
struct LuminaireAiming {
  double orientDegrees = 0, tiltDegrees = 0, rollDegrees = 0, spinDegrees = 0;
};
// The one photometric frame function: the axes the four angles give, in lambert's scene axes
// (x east, y up, north −z). Exact for any angles; continuous in every angle.
LuminaireFrame luminaireFrame(const LuminaireAiming& aiming);
// The angles of an aim vector and a spin, as AGi32 aims at a point: orient the plan azimuth of
// the aim counter-clockwise from east in [0, 360), tilt the angle from straight down to the aim in
// [0, 180], roll 0, spin as given. An aim within 1e-9 rad of vertical (straight down or up) has no
// azimuth: orient 0 there. aim: any non-zero length.
LuminaireAiming aimingOfDirection(const Vec3& aim, double spinDegrees);
// A luminaire's frame: that of its aim (light.direction, the nadir) and its spin (light.rotationDegrees)
// through aimingOfDirection. Continuous in the aim except exactly at vertical aims, where the
// azimuth is undefined; a downlight's C0 is +x turned by the spin toward north (−z).
LuminaireFrame luminaireFrame(const Light& light);
// Aims a luminaire so that its frame has the given nadir and (any non-zero, not parallel) C0
// direction: light.direction = the unit nadir, light.rotationDegrees = the spin in (−180, 180]
// about it that brings the frame's C0 onto c0 made perpendicular to the nadir.
void setLuminaireFrame(Light& light, const Vec3& nadir, const Vec3& c0);
// Aims a luminaire by the four angles: its frame becomes luminaireFrame(aiming) (to rounding),
// stored as direction + spin (roll folds into them: every frame has aim-point angles with roll 0).
void aimLuminaire(Light& light, const LuminaireAiming& aiming);
// The (C, γ) in degrees of a unit direction leaving the luminaire.
void photometricAngles(const LuminaireFrame& frame, const Vec3& direction, double& cDegrees, double& gammaDegrees);
// Radiant intensity in W/sr that a luminaire sends along the unit direction `outward`: its
// candela × the tilt factor of its aim (IES TILT, the angle between the aim and straight down −y)
// × light.intensity (its colour × multiplier) / 683 lm/W.
Rgb luminaireIntensity(const Light& light, const Vec3& outward);
// The point sources a luminaire is lit from, in scene units: its centre (FarField), or the centres
// of an n × m grid over its luminous opening (Opening: n, m ≤ openingSamplesPerSide in
// proportion to the sides; a round opening keeps the cells whose centres lie inside it), each
// sending 1/count of the intensity. A luminaire without an opening size is one point either way.
std::vector<Vec3> luminaireSources(const Light& light, double metresPerUnit);

// Irradiance E in W/m² that `light` gives a point x with unit normal n, ignoring occluders.
// metresPerUnit converts scene distances so that the inverse-square law is in metres.
Rgb unshadowedIrradiance(const Light& light, const Vec3& x, const Vec3& n, double metresPerUnit);

// The same, with a shadow ray from x (lifted by epsilon along n) toward the light. A sky's
// estimate follows its edges as `skyEdges` says (light/sky.h): Traced at calculation points,
// Cells for the solve's patches.
Rgb irradiance(const Light& light, const Vec3& x, const Vec3& n, const RayCaster& caster, double epsilon,
               double metresPerUnit, SkyEdges skyEdges = SkyEdges::Cells);

struct DirectLightOptions {
  int samplesPerPatch = 16;  // points per patch the irradiance is averaged over
  std::uint64_t seed = 1;
  // Ward's adaptive shadow testing (light/many_lights.h): at each point the lights get shadow
  // rays in decreasing order of their unoccluded irradiance until the untested rest is at most
  // this fraction of the unoccluded total, which bounds the error there (|E − E_exact| ≤ τ·U).
  // 0: every light a ray, the exact sum. With at most kPerLightInjectionLights lights the
  // injection keeps each light's trace apart and exact (so that a moving light re-traces only
  // its own patches); more are traced together under this tolerance.
  double shadowTolerance = 0.01;
};
inline constexpr std::size_t kPerLightInjectionLights = 8;

// Each patch's mean direct irradiance from one light, in W/m², over low-discrepancy points.
std::vector<Rgb> patchIrradiance(const Mesh& mesh, const RayCaster& caster, const Light& light, double metresPerUnit,
                                 const DirectLightOptions& options = {});

// The same for the listed patches only, over rays lifted by `epsilon` (rayEpsilon(mesh)):
// irradiance[i] for each listed i is what the function above gives it; the other entries are
// left as they are. irradiance holds one entry per patch.
void patchIrradiance(const Mesh& mesh, const RayCaster& caster, const Light& light, double metresPerUnit,
                     const DirectLightOptions& options, double epsilon, std::span<const std::uint32_t> patches,
                     std::vector<Rgb>& irradiance);

// The patches a spot may light, found without testing each: a binary tree of bounding spheres over
// the patches' bounding spheres (median splits of their centroids along the longest axis), whose
// subtrees the cone misses are skipped whole. Built once per mesh in O(n log n); a spot's query
// costs O(log n) per patch it returns. Its spheres hold their patches' with a margin above
// rounding, so the candidates hold every patch patchIrradiance can light.
class PatchSphereTree {
 public:
  explicit PatchSphereTree(const Mesh& mesh);
  // A spot's candidates: every patch whose bounding sphere reaches into its cone, and some
  // beside them, in increasing order. Every patch for a point or directional light.
  std::vector<std::uint32_t> candidates(const Light& light) const;

 private:
  static constexpr std::uint32_t kLeafSize = 8;  // patches under a node that is not split
  struct Node {
    Vec3 centre;
    double radius = 0;
    std::uint32_t begin = 0, end = 0;  // its patches, a range of patches_
    std::uint32_t firstChild = 0;      // the two children are firstChild and firstChild + 1; 0: none
  };
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> patches_;  // the patches, each node's contiguous
  std::size_t numPatches_ = 0;
};

// What a light injects into the radiosity system: ρ_i times its patch irradiance, in W/m².
std::vector<Rgb> injectedRadiosity(const Mesh& mesh, const std::vector<Rgb>& albedo, const std::vector<Rgb>& irradiance);

// Radiance in W/(m²·sr) that a Lambertian point of albedo ρ reflects of the lights' direct light,
// ρ/π Σ_l E_l(x), with a shadow ray per light: what the hybrid renderer adds per pixel.
Rgb reflectedDirectRadiance(std::span<const Light> lights, const Vec3& x, const Vec3& n, const Rgb& albedo,
                            const RayCaster& caster, double epsilon, double metresPerUnit);

// The light as it is `seconds` after the scene's start: its direction turned by its angular
// velocity (a rotation by |ω|·t about ω).
Light lightAtTime(const Light& light, double seconds);

// The luminous flux in lm a light sends out, 683 × the luminance of its radiant power: a point
// 4π·I, a spot ∫ I·falloff dω over its cone (midpoint rule, 0.01° steps), a luminaire its
// distribution's flux (Photometry::luminousFlux) × its multiplier and maintenance factor (in
// `intensity`) × its tilt factor. 0 for a sun or a sky, whose power has no bound.
double lightLumens(const Light& light);

}  // namespace lambert
