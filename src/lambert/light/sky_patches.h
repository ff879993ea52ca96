#pragma once
// The sky divided into patches, the basis of daylight coefficients (Tregenza and Waters 1983,
// "Daylight coefficients", Lighting Research & Technology 15(2) 65–71): Tregenza's 145 patches
// (Tregenza 1987, "Subdivision of the sky hemisphere for luminance measurements", LR&T 19(1) 13–14)
// and Reinhart's subdivisions of them (MF:n, as Radiance's reinhart.cal and gendaymtx number them:
// 144 n² + 1 patches; MF:2 577, MF:4 2305).
//
// Tregenza's sky: seven rings of equal altitude height, 30, 30, 24, 24, 18, 12 and 6 patches from
// the horizon up, and a cap of half a ring's height around the zenith. MF:n splits each ring into n
// rings of n times as many patches; the rings' height is 90° / (7n + ½) (12° for Tregenza's) and the
// cap keeps half of one. In each ring the first patch is centred on north and the others follow
// clockwise seen from above (toward east), as Radiance numbers them. Radiance's patch 0, the
// ground, is not one of these: lambert's skies give nothing below the horizon, where the scene's
// own geometry is the ground.
//
// Cost: patchOf is an asin and an atan2; a patch's mean luminance n² evaluations of the sky model.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"
#include "lambert/light/sky.h"

namespace lambert {

class SkyPatches {
 public:
  // MF:subdivisions (1 is Tregenza's), north a horizontal scene direction (east = north × up).
  static Result<SkyPatches> reinhart(int subdivisions, const Vec3& north = {0, 0, -1});
  SkyPatches() : SkyPatches(1, {0, 0, -1}) {}  // Tregenza's, north −z

  int subdivisions() const { return subdivisions_; }
  int count() const { return static_cast<int>(patchStart_.back()) + 1; }  // the cap is the last
  const Vec3& north() const { return north_; }

  // The patch holding a direction above the horizon (any length); −1 at or below it.
  int patchOf(const Vec3& direction) const;
  // A patch's bounds: altitude from lo to hi and azimuth (from north, clockwise) from lo to hi,
  // degrees; the cap spans every azimuth (0 to 360).
  struct Bounds {
    double altitudeLo = 0, altitudeHi = 0, azimuthLo = 0, azimuthHi = 0;
  };
  Bounds bounds(int patch) const;
  // Solid angle in steradians: (az_hi − az_lo)·(sin alt_hi − sin alt_lo). Σ over the patches = 2π.
  double solidAngle(int patch) const;
  // The direction through the middle of a patch (its mid altitude and azimuth; the zenith for the
  // cap), unit, scene frame.
  Vec3 centre(int patch) const;
  // Weights on up to four patches' centres that interpolate a quantity smooth over the sky at a
  // direction above the horizon: linear in azimuth between the two nearest centres of each of the
  // two rings whose centre altitudes enclose it, then linear in altitude between the rings (the cap's
  // one centre at the zenith; below the lowest ring's centres, that ring alone). Unused entries
  // are {−1, 0}; the weights add up to 1. All {−1, 0} at or below the horizon.
  struct Interpolation {
    std::array<int, 4> patch{-1, -1, -1, -1};
    std::array<double, 4> weight{0, 0, 0, 0};
  };
  Interpolation interpolation(const Vec3& direction) const;
  // The mean luminance (cd/m²) of a sky over a patch, by the midpoint rule on an m × m grid of cells
  // of equal solid angle (equal steps of sin altitude and of azimuth; the cap in rings), m = ⌈4/n⌉.
  double meanLuminance(const SkyModel& sky, int patch) const;

 private:
  SkyPatches(int subdivisions, const Vec3& north);
  int subdivisions_ = 1;
  double ringHeightDegrees_ = 12;
  Vec3 north_{0, 0, -1}, east_{1, 0, 0};
  std::vector<int> ringPatches_;         // patches in each ring, from the horizon
  std::vector<std::uint32_t> patchStart_;  // first patch of each ring, and one more: the cap's index
};

// The sky of luminance 1 cd/m² in every direction above the horizon (CIE standard sky 5), whose
// hemispheres skyPatchIlluminance integrates over.
const SkyModel& unitLuminanceSky();

// A point's sky daylight coefficients: per patch p, ∫_p V(ω) max(0, n·ω) dω, the illuminance in lux
// that the patch alone gives at luminance 1 cd/m² (the rest of the sky dark). One pass over the
// directions skyIlluminance traces at n (`directions`, edges followed as `edges` says), each
// visible sample counted in the patch it falls in, so that Σ_p coefficient_p · L_p is skyIlluminance
// of a sky whose luminance is L_p over each patch p. `visible` as skyIlluminance's; perPatch has
// patches.count() entries, overwritten.
template <class Visible>
void skyPatchIlluminance(const SkyPatches& patches, const Vec3& n, int directions, Visible&& visible, SkyEdges edges,
                         std::span<double> perPatch) {
  SkyHemisphere& hemisphere = skyHemisphere(unitLuminanceSky(), n, skyGridSide(directions));
  std::fill(perPatch.begin(), perPatch.end(), 0.0);
  skyIntegrate(hemisphere, visible, edges, [&](const Vec3& direction, double luminance, double share) {
    const int p = patches.patchOf(direction);
    if (p >= 0) perPatch[static_cast<std::size_t>(p)] += luminance * share;
  });
  const double m = hemisphere.gridSide();
  for (double& e : perPatch) e *= kPi / (m * m);
}

}  // namespace lambert
