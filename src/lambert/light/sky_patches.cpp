#include "lambert/light/sky_patches.h"

#include <algorithm>
#include <cmath>

#include "lambert/core/photometric.h"
#include "lambert/light/sky.h"
#include "lambert/light/sun.h"

namespace lambert {
namespace {
constexpr double kDegree = kPi / 180;
// Tregenza's patches per ring, from the horizon.
constexpr int kTregenzaRing[7] = {30, 30, 24, 24, 18, 12, 6};
}  // namespace

Result<SkyPatches> SkyPatches::reinhart(int subdivisions, const Vec3& north) {
  if (subdivisions < 1 || subdivisions > 32) return Error{"the sky's subdivision (Reinhart's MF) must be 1 to 32, not " + std::to_string(subdivisions)};
  if (!(std::fabs(north.x) + std::fabs(north.z) > 0) || !std::isfinite(north.x) || !std::isfinite(north.z))
    return Error{"north must be a finite horizontal direction (not along y)"};
  return SkyPatches(subdivisions, north);
}

SkyPatches::SkyPatches(int subdivisions, const Vec3& north)
    : subdivisions_(subdivisions), ringHeightDegrees_(90.0 / (7 * subdivisions + 0.5)), north_(normalize(Vec3{north.x, 0, north.z})) {
  east_ = cross(north_, Vec3{0, 1, 0});
  std::uint32_t start = 0;
  for (int ring = 0; ring < 7 * subdivisions; ++ring) {
    ringPatches_.push_back(kTregenzaRing[ring / subdivisions] * subdivisions);
    patchStart_.push_back(start);
    start += static_cast<std::uint32_t>(ringPatches_.back());
  }
  patchStart_.push_back(start);
}

int SkyPatches::patchOf(const Vec3& d) const {
  const double len = length(d);
  if (!(len > 0) || !(d.y > 0)) return -1;
  const double altitude = std::asin(std::min(1.0, d.y / len)) / kDegree;
  const int ring = static_cast<int>(altitude / ringHeightDegrees_);
  if (ring >= static_cast<int>(ringPatches_.size())) return count() - 1;
  double azimuth = std::atan2(dot(d, east_), dot(d, north_)) / kDegree;
  if (azimuth < 0) azimuth += 360;
  const int n = ringPatches_[ring];
  const double width = 360.0 / n;
  int i = static_cast<int>((azimuth + width / 2) / width);
  if (i >= n) i -= n;
  return static_cast<int>(patchStart_[ring]) + i;
}

SkyPatches::Interpolation SkyPatches::interpolation(const Vec3& d) const {
  Interpolation out;
  const double len = length(d);
  if (!(len > 0) || !(d.y > 0)) return out;
  const double altitude = std::asin(std::min(1.0, d.y / len)) / kDegree;
  double azimuth = std::atan2(dot(d, east_), dot(d, north_)) / kDegree;
  if (azimuth < 0) azimuth += 360;
  const int rings = static_cast<int>(ringPatches_.size());
  // Ring r's centres lie at altitude (r + ½)·H; the cap's at 90°.
  const double u = altitude / ringHeightDegrees_ - 0.5;
  int lower = static_cast<int>(std::floor(u));
  double t = u - lower;  // toward the ring above
  if (lower < 0) lower = 0, t = 0;
  int slot = 0;
  auto ring = [&](int r, double share) {
    if (share <= 0) return;
    if (r >= rings) {
      out.patch[slot] = count() - 1, out.weight[slot++] = share;
      return;
    }
    const int n = ringPatches_[r];
    const double v = azimuth / (360.0 / n);
    const int i0 = static_cast<int>(std::floor(v)) % n;
    const double s = v - std::floor(v);
    out.patch[slot] = static_cast<int>(patchStart_[r]) + i0, out.weight[slot++] = share * (1 - s);
    out.patch[slot] = static_cast<int>(patchStart_[r]) + (i0 + 1) % n, out.weight[slot++] = share * s;
  };
  if (lower >= rings - 1) {
    // Between the top ring's centres and the zenith: altitude from (R − ½)·H up to 90°.
    const double top = (rings - 0.5) * ringHeightDegrees_;
    const double toCap = std::clamp((altitude - top) / (90 - top), 0.0, 1.0);
    ring(rings - 1, 1 - toCap);
    ring(rings, toCap);
    return out;
  }
  ring(lower, 1 - t);
  ring(lower + 1, t);
  return out;
}

SkyPatches::Bounds SkyPatches::bounds(int patch) const {
  const int rings = static_cast<int>(ringPatches_.size());
  if (patch == count() - 1) return {rings * ringHeightDegrees_, 90, 0, 360};
  const int ring = static_cast<int>(std::upper_bound(patchStart_.begin(), patchStart_.end(), static_cast<std::uint32_t>(patch)) - patchStart_.begin()) - 1;
  const double width = 360.0 / ringPatches_[ring];
  const int i = patch - static_cast<int>(patchStart_[ring]);
  return {ring * ringHeightDegrees_, (ring + 1) * ringHeightDegrees_, (i - 0.5) * width, (i + 0.5) * width};
}

double SkyPatches::solidAngle(int patch) const {
  const Bounds b = bounds(patch);
  return (b.azimuthHi - b.azimuthLo) * kDegree * (std::sin(b.altitudeHi * kDegree) - std::sin(b.altitudeLo * kDegree));
}

Vec3 SkyPatches::centre(int patch) const {
  if (patch == count() - 1) return {0, 1, 0};
  const Bounds b = bounds(patch);
  return skyDirection((b.azimuthLo + b.azimuthHi) / 2, (b.altitudeLo + b.altitudeHi) / 2, north_);
}

double SkyPatches::meanLuminance(const SkyModel& sky, int patch) const {
  const Bounds b = bounds(patch);
  const int m = (4 + subdivisions_ - 1) / subdivisions_;
  const bool cap = patch == count() - 1;
  const int mAzimuth = cap ? 4 * m : m;
  const double s0 = std::sin(b.altitudeLo * kDegree), s1 = std::sin(b.altitudeHi * kDegree);
  double sum = 0;
  for (int j = 0; j < m; ++j) {
    const double altitude = std::asin(s0 + (s1 - s0) * (j + 0.5) / m) / kDegree;
    for (int i = 0; i < mAzimuth; ++i) {
      const double azimuth = b.azimuthLo + (b.azimuthHi - b.azimuthLo) * (i + 0.5) / mAzimuth;
      sum += sky.luminance(skyDirection(azimuth, altitude, north_));
    }
  }
  return sum / (m * mAzimuth);
}

const SkyModel& unitLuminanceSky() {
  static const SkyModel sky = *SkyModel::cieStandard(5, 0, 90, 1.0);
  return sky;
}

}  // namespace lambert
