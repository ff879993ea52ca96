#pragma once
// Sky luminance distributions for daylight: the fifteen CIE standard general skies (ISO 15469:2004 /
// CIE S 011/E:2003) and the traditional CIE overcast sky (Moon and Spencer 1942, adopted by the CIE
// in 1955), scaled absolutely by a zenith luminance or an unobstructed horizontal illuminance. The
// sky is a dome at infinity above the horizon; below it, it gives nothing (the ground is whatever
// geometry the scene has). And one that is not daylight: a uniform environment, radiance L (RGB)
// from every direction at infinity, below the horizon too, as Blender's and Cycles' world colour
// lights a scene (and a glTF viewer's uniform environment). And the Perez all-weather sky (Perez,
// Seals and Michalsky 1993, light/perez_sky.h), whose five coefficients come from an hour's weather.
// Its light reaches a point through a light of LightKind::Sky
// (light/lights.h), which estimates ∫ L(ω) V(x, ω) max(0, n·ω) dω over stratified directions.
//
// Frame: lambert is y-up, so the zenith is +y. North is a horizontal scene direction (default −z,
// so east = north × up = +x); azimuths run from north clockwise seen from above (east 90°).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/core/photometric.h"  // kLumensPerWatt
#include "lambert/scene/scene.h"

namespace lambert {

// Luminance (cd/m²) turns into radiance (W/(m²·sr)) for white light at kLumensPerWatt = 683 lm/W
// (load/gltf.h), as everywhere in lambert (docs/photometry.md).

// ISO 15469 / CIE S 011 parameters: the gradation φ(Z) = 1 + a·exp(b / cos Z) (φ(90°) = 1) and
// the scattering indicatrix f(χ) = 1 + c·(exp(d·χ) − exp(d·π/2)) + e·cos²χ.
struct CieSkyParameters {
  double a = 0, b = 0, c = 0, d = 0, e = 0;
  bool operator==(const CieSkyParameters&) const = default;
};

// Standard sky types 1–15 (the standard's table 1: six gradation groups × six indicatrix groups).
// Type 1 is the CIE standard overcast sky, 5 the uniform sky, 12 the CIE standard clear sky.
CieSkyParameters cieStandardSkyParameters(int type);
// The standard's short description of a type ("CIE standard overcast sky, steep luminance
// gradation towards zenith, azimuthal uniformity", ...).
std::string cieStandardSkyDescription(int type);

// The Perez all-weather sky's state for one hour (Perez, Seals and Michalsky, "All-weather model for
// sky luminance distribution — preliminary configuration and validation", Solar Energy 50(3),
// 1993, pp. 235–245): its sky clearness ε and brightness Δ, the ε bin (1–8) and the five
// coefficients of the relative luminance lv = (1 + a·exp(b / cos Z))·(1 + c·exp(d·γ) + e·cos²γ).
// light/perez_sky.h computes it from irradiances; SkyModel::perez reads a–e alone.
struct PerezCoefficients {
  double clearness = 1;         // ε, as used: limited to [1, 11.9] as Radiance's gendaymtx
  double brightness = 0;        // Δ, as used: at least 0.01 (and 0.2 in bins 2–4 for a–e: the paper's note)
  int bin = 1;                  // 1 (overcast, ε < 1.065) to 8 (clear, ε ≥ 6.2)
  double sunZenithRadians = 0;  // the sun's zenith angle the coefficients were made for (3° to 90°)
  double a = 0, b = 0, c = 0, d = 0, e = 0;
  bool operator==(const PerezCoefficients&) const = default;
};

class SkyModel {
 public:
  // CIE standard general sky `type` (1–15) with the sun at this azimuth and elevation (degrees,
  // elevation in [−90, 90]: the formula holds for any sun, the standard for one above the
  // horizon) and the given zenith luminance Lz in cd/m².
  static Result<SkyModel> cieStandard(int type, double sunAzimuthDegrees, double sunElevationDegrees,
                                      double zenithLuminance, const Vec3& north = {0, 0, -1});
  // The traditional CIE overcast sky, L(Z) = Lz (1 + 2 cos Z) / 3: no sun dependence.
  static SkyModel traditionalOvercast(double zenithLuminance, const Vec3& north = {0, 0, -1});
  // The Perez all-weather sky with these coefficients (a–e are read; the rest is for the record),
  // the sun at this azimuth and elevation (degrees) and the given zenith luminance Lz in cd/m². The
  // formula's two factors are each clamped at 0 where they would go negative (a few bins' c < 0
  // darken the circumsolar region below zero, a < −1 the zenith): the sky stays a product of a
  // gradation and an indicatrix (SkyLuminanceTable). Radiance's gendaymtx clamps their product
  // instead; the two differ only where both factors are negative, where gendaymtx's sky turns
  // bright again. b > 0 (a few bins at large Δ) would make the horizon infinitely bright
  // (exp(b / cos Z) → ∞, not integrable): b is taken as 0 there, a gradation of 1 + a. Where the
  // formula darkens the whole sky (either factor ≤ 0 everywhere: twilight's large Δ in bin 1, a
  // low sun's b > 0 with a < −1), the sky is uniform, as gendaymtx makes it. Where it darkens the
  // zenith alone, `zenithLuminance` (and zenithLuminance()) is no longer the zenith's luminance but
  // a scale: the factor that vanishes there is taken relative to its largest value instead
  // (relativeGradation, relativeIndicatrix). perezSkyForHour scales by the horizontal illuminance,
  // which either way is what it should be.
  static Result<SkyModel> perez(const PerezCoefficients& coefficients, double sunAzimuthDegrees, double sunElevationDegrees,
                                double zenithLuminance, const Vec3& north = {0, 0, -1});
  // A uniform environment of radiance L in W/(m²·sr) per channel from every direction, the
  // whole sphere: finite, not negative, not black.
  static Result<SkyModel> uniformEnvironment(const Rgb& radiance);

  // The same sky scaled to an unobstructed horizontal illuminance of `lux` (> 0).
  SkyModel withHorizontalIlluminance(double lux) const;

  bool isTraditionalOvercast() const { return type_ == 0; }
  bool isUniformEnvironment() const { return type_ == kUniformEnvironment; }
  bool isPerez() const { return type_ == kPerez; }
  // 1–15; 0 for the traditional overcast sky, −1 for a uniform environment, −2 for a Perez sky
  int cieType() const { return type_; }
  // A Perez sky's coefficients (a–e as used: b ≤ 0); for the others, a default.
  const PerezCoefficients& perezCoefficients() const { return perez_; }
  // What a candela per square metre of it is in radiance, W/(m²·sr) per channel, × 683: (1, 1, 1)
  // for the white daylight skies, the environment's colour (its Rec. 709 luminance 1) otherwise.
  const Rgb& colour() const { return colour_; }
  double sunAzimuthDegrees() const { return sunAzimuthDegrees_; }
  double sunElevationDegrees() const { return sunElevationDegrees_; }
  const Vec3& north() const { return north_; }
  Vec3 sunDirection() const { return sun_; }  // toward the sun, unit, scene frame
  double zenithLuminance() const { return zenithLuminance_; }  // cd/m²

  // L(Z, α) / Lz at zenith angle Z and azimuth α (radians, α from north clockwise), by the
  // standard's angular formula: cos χ = cos Zs cos Z + sin Zs sin Z cos(α − αs).
  double relativeLuminance(double zenithAngle, double azimuth) const;
  // Luminance in cd/m² seen looking along `direction` (scene frame, any length); 0 below the
  // horizon, but for a uniform environment.
  double luminance(const Vec3& direction) const;
  // Radiance in W/(m²·sr) per channel: colour × luminance / 683 (white for the daylight skies).
  Rgb radiance(const Vec3& direction) const { return colour_ * (luminance(direction) / kLumensPerWatt); }

  // Illuminance in lux on an unobstructed horizontal plane, ∫ L cos Z dω over the sky, by a
  // Simpson (zenith, 256 intervals) × midpoint (azimuth, 512) rule, computed once at construction
  // (π L for a uniform environment).
  double horizontalIlluminance() const { return horizontalIlluminance_; }

  // L / Lz from cos Z and the cosine of the angle χ to the sun (the formula of relativeLuminance):
  // relativeGradation(cos Z) × relativeIndicatrix(cos χ), the gradation relative to its zenith value
  // and the indicatrix relative to its value at the zenith (χ = the sun's zenith angle), each ≥ 0.
  double relativeFromCosines(double cosZenith, double cosSunAngle) const {
    return relativeGradation(cosZenith) * relativeIndicatrix(cosSunAngle);
  }
  double relativeGradation(double cosZenith) const;
  double relativeIndicatrix(double cosSunAngle) const;

  bool operator==(const SkyModel&) const = default;

 private:
  static constexpr int kUniformEnvironment = -1;
  static constexpr int kPerez = -2;
  SkyModel() = default;
  void finish();  // sun_, the zenith values, horizontalIlluminance_ from the rest

  int type_ = 0;
  Rgb colour_{1, 1, 1};
  CieSkyParameters p_;      // the CIE parameters, or a Perez sky's a–e
  PerezCoefficients perez_;  // a Perez sky's, as given (b ≤ 0)
  double sunAzimuthDegrees_ = 0, sunElevationDegrees_ = 90;
  Vec3 north_{0, 0, -1};
  Vec3 sun_{0, 1, 0};
  double zenithLuminance_ = 0;
  double gradationAtZenith_ = 1, indicatrixAtZenith_ = 1;  // φ(0) and f(Zs): relative* divide by them
  double horizontalIlluminance_ = 0;
};

// Illuminance in lux at a point with unit normal n from the sky, ∫ L(ω) V(ω) max(0, n·ω) dω,
// over an m × m grid of cells on the unit square (m² ≥ `directions`), mapped to the hemisphere
// about n by Shirley and Chiu's concentric map with cosine weighting (pdf cos θ/π), so that
// E = (π / m²) Σ_cells (mean of L·V over the cell). Each cell is first sampled once, at a point
// jittered within it by a fixed hash (the same set at every point: the estimate is deterministic
// and a smooth function of the point, never noise from point to point). A cell whose lit state
// (L > 0 and visible) differs from one of its four neighbours' holds an edge (a window's frame)
// and is resampled on a kSkyEdgeRefinement² sub-grid: a sharp edge's error falls from about a cell
// per edge cell to a sub-cell. A lit cell beside the unknown (the square's rim, the horizon) is
// probed on its sub-samples along that side first, and resampled only if one is dark. Where a
// resampled cell's sub-samples along a side differ from the cell beyond it, the edge goes on into
// that cell (its first sample missed it: a window's corner, a sliver a few cells wide) and it is
// resampled too, until they agree; then each sub-cell whose state differs from a neighbouring
// sub-cell's is resampled on a kSkyFineRefinement² grid that keeps its own sample (the façade
// window's work plane at 4096: largest error 1.58% → 0.85% under the overcast sky, for ~35% more rays). `visible(directions, out)` sets out[i] where the point
// sees the sky along directions[i]; it is asked only where L(ω) > 0 (above the horizon). An opening smaller than about a cell
// (≈ 2.8° across at 4096 directions) can fall between the first samples and be missed.
// How far edges are followed: SkyEdges (scene/scene.h).
template <class Visible>
double skyIlluminance(const SkyModel& sky, const Vec3& n, int directions, Visible&& visible, SkyEdges edges);

// Sub-grid side of a cell on an edge (above).
inline constexpr int kSkyEdgeRefinement = 4;
// Sub-grid side of a sub-cell on an edge.
inline constexpr int kSkyFineRefinement = 2;

// The grid side m for a requested count (m² ≥ directions, m ≥ 1).
int skyGridSide(int directions);
// The direction at (u, v) ∈ [0, 1)² about unit normal n (tangents t, b): concentric map, cosine lift.
Vec3 skySquareToDirection(const Vec3& n, const Vec3& tangent, const Vec3& bitangent, double u, double v);
// The fixed jitter in [0, 1)² of sample `index` of a cell: a hash, the same at every point.
void skyJitter(std::uint64_t index, double& du, double& dv);

// The sky's luminance from two tables, for the many directions an estimate asks for: the
// standard's formula (and the Perez sky's) is a product of the gradation, a function of cos Z, and the indicatrix, a
// function of the angle χ to the sun, each tabulated at kSkyTableIntervals intervals and
// interpolated linearly (the indicatrix over sin(χ/2) toward the sun and cos(χ/2) away from it, in
// which it is smooth at both ends): within 10⁻⁶ of SkyModel::luminance
// (SkyTest.TheLuminanceTableFollowsTheFormula), without its acos and two exps.
class SkyLuminanceTable {
 public:
  explicit SkyLuminanceTable(const SkyModel& sky);
  const SkyModel& sky() const { return sky_; }
  // cd/m² along a unit direction; 0 below the horizon.
  double luminance(const Vec3& unitDirection) const;

 private:
  SkyModel sky_;
  std::vector<double> zenithward_;  // Lz · relativeGradation(cos Z) at cos Z = i / N
  std::vector<double> sunward_;     // relativeIndicatrix(cos χ) at sin(χ/2) = √½ · i / N (χ ≤ 90°)
  std::vector<double> awayward_;    // relativeIndicatrix(cos χ) at cos(χ/2) = √½ · i / N (χ ≥ 90°)
};
inline constexpr int kSkyTableIntervals = 4096;

// skyIlluminance's directions about one normal and the sky's luminance along each. They depend on
// the normal alone, not on the point, so all the points of a wall share one set: the directions
// come from a table about the z axis made once per grid side (turned to the normal: three
// multiply-adds each) and the luminances from SkyLuminanceTable, so that even a curved surface,
// a new normal at every element, pays little beyond its rays. The cells' first samples are made
// at reset, an edge cell's sub-grid the first time a point asks for it. Not thread-safe:
// skyHemisphere gives each thread its own.
class SkyHemisphere {
 public:
  void reset(const SkyLuminanceTable& sky, const Vec3& n, int gridSide);
  bool matches(const SkyModel& sky, const Vec3& n, int gridSide) const { return m_ == gridSide && n_ == n && sky_ && sky_->sky() == sky; }
  int gridSide() const { return m_; }
  // Cell k = j·m + i's first sample.
  const Vec3& direction(std::size_t k) const { return first_[k].direction; }
  double luminance(std::size_t k) const { return first_[k].luminance; }
  // Sub-sample q ∈ [0, r²) of cell k's kSkyEdgeRefinement² sub-grid.
  const Vec3& edgeDirection(std::size_t k, int q) { return edgeSamples(k)[q].direction; }
  double edgeLuminance(std::size_t k, int q) { return edgeSamples(k)[q].luminance; }
  // Sub-sub-sample p ∈ [0, s²) of sub-cell q of cell k (s = kSkyFineRefinement): a sub-cell on an
  // edge, resampled (made the first time a point asks for it).
  const Vec3& fineDirection(std::size_t k, int q, int p) { return fineSamples(k, q)[p].direction; }
  double fineLuminance(std::size_t k, int q, int p) { return fineSamples(k, q)[p].luminance; }
  // skyIlluminance with nothing in the way, in lux: computed once.
  double unobstructedIlluminance();

 private:
  struct Sample {
    Vec3 direction;
    double luminance = 0;
  };
  Sample turned(const Vec3& local) const;
  const Sample* edgeSamples(std::size_t k);
  const Sample* fineSamples(std::size_t k, int q);

  const SkyLuminanceTable* sky_ = nullptr;
  Vec3 n_, t_, b_;
  int m_ = 0;
  std::vector<Sample> first_;              // one per cell
  std::vector<std::int32_t> edgeAt_;       // per cell: where its sub-samples start in edge_, or −1
  std::vector<Sample> edge_;               // r² per cell asked for
  std::vector<std::int32_t> fineAt_;       // per sub-sample in edge_: where its sub-sub-samples start in fine_, or −1
  std::vector<Sample> fine_;               // s² per sub-cell asked for
  double unobstructed_ = -1;               // < 0 until asked
};

// This thread's hemisphere for (sky, n, grid side), from a small per-thread cache (a wall's patches
// come one after another, so the last few normals are the ones asked again). n is first rounded to
// 2⁻³⁰ per component and renormalised: a wall's patches' normals, each from its own corners, differ
// in their last bits, and a pure rounding keeps the result the same whichever thread asks first.
SkyHemisphere& skyHemisphere(const SkyModel& sky, const Vec3& n, int gridSide);

// skyIlluminance's integration over a hemisphere's directions, handing each sample that counts to
// `add(direction, luminance, share)`: a visible sample above the horizon, `share` the part of a
// cell it stands for (1 for a cell's first sample, 1/r² for a sub-sample, 1/(r² s²) for a fine one),
// so that ∫ L V cos dω = (π / cells) Σ luminance · share. The first samples go to `visible` as one
// batch, the probes a second and the edge cells' sub-samples a third, so that a ray tracer can
// trace them as streams.
template <class Visible, class Add>
void skyIntegrate(SkyHemisphere& hemisphere, Visible&& visible, SkyEdges edges, Add&& add) {
  const int m = hemisphere.gridSide();
  const std::size_t cells = static_cast<std::size_t>(m) * m;
  constexpr int r = kSkyEdgeRefinement;
  thread_local std::vector<double> luminance;  // L·V of each cell's first sample
  thread_local std::vector<Vec3> asked;        // directions of one batch
  thread_local std::vector<std::size_t> askedIndex;
  thread_local std::unique_ptr<bool[]> seen;
  thread_local std::size_t seenCapacity = 0;
  auto ask = [&]() {
    if (seenCapacity < asked.size()) {
      seenCapacity = asked.size();
      seen = std::make_unique<bool[]>(seenCapacity);
    }
    visible(std::span<const Vec3>(asked), std::span<bool>(seen.get(), asked.size()));
  };
  luminance.assign(cells, 0.0);
  asked.clear();
  askedIndex.clear();
  for (std::size_t k = 0; k < cells; ++k)
    if (hemisphere.luminance(k) > 0) {
      asked.push_back(hemisphere.direction(k));
      askedIndex.push_back(k);
    }
  ask();
  for (std::size_t a = 0; a < asked.size(); ++a)
    if (seen[a]) luminance[askedIndex[a]] = hemisphere.luminance(askedIndex[a]);
  // A lit cell beside the unknown (beyond the square's edge, the hemisphere's rim at n·ω = 0, or
  // below the horizon) may hold an edge too close to that side for its sample to see: a window's
  // sill seen at a grazing angle, a parapet on the horizon. It is probed along that side (its
  // sub-samples nearest it): all lit, it counts whole (its sub-samples' luminance, which the
  // horizon may cut); one dark, it is resampled like a cell on an edge between lit and dark.
  // (Resampling every such cell, as before, cost the 56% of a sky-lit helmet's edge cells that
  // only the rim or the horizon made; the probes cost a quarter of it.)
  auto known = [&](int i, int j) { return i >= 0 && i < m && j >= 0 && j < m && hemisphere.luminance(static_cast<std::size_t>(j) * m + i) > 0; };
  auto litAt = [&](int i, int j) { return known(i, j) && luminance[static_cast<std::size_t>(j) * m + i] > 0; };
  constexpr int kSides[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  auto onSide = [](int q, int side) { return side == 0 ? q % r == 0 : side == 1 ? q % r == r - 1 : side == 2 ? q / r == 0 : q / r == r - 1; };
  thread_local std::vector<double> whole;  // what a cell not resampled counts: its sample, or its probes'
  whole.assign(luminance.begin(), luminance.end());
  thread_local std::vector<unsigned char> countsSubSamples;  // per cell: it counts its probes' sub-samples
  countsSubSamples.assign(cells, 0);
  thread_local std::vector<std::size_t> resampled;              // cells resampled whole
  thread_local std::vector<std::pair<std::size_t, int>> probed;  // cells probed, and their sides (bits)
  resampled.clear();
  probed.clear();
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * m + i;
      const bool lit = luminance[k] > 0;
      // Most cells agree with their four neighbours (the unknown counted as dark): a lit cell
      // beside lit ones, a dark cell beside dark or unknown ones.
      if (litAt(i - 1, j) == lit && litAt(i + 1, j) == lit && litAt(i, j - 1) == lit && litAt(i, j + 1) == lit) continue;
      bool edge = false;
      int unknownSides = 0;
      for (int side = 0; side < 4; ++side) {
        const int ii = i + kSides[side][0], jj = j + kSides[side][1];
        if (!known(ii, jj))
          unknownSides |= 1 << side;
        else
          edge |= litAt(ii, jj) != lit;
      }
      // A cell whose own sample lies below the horizon is unknown too: lit beside it, resampled.
      if (!known(i, j)) edge = litAt(i - 1, j) || litAt(i + 1, j) || litAt(i, j - 1) || litAt(i, j + 1);
      if (edge) {
        resampled.push_back(k);
      } else if (lit && unknownSides) {
        probed.push_back({k, unknownSides});
      }
    }
  asked.clear();
  askedIndex.clear();
  for (std::size_t c = 0; c < probed.size(); ++c)
    for (int q = 0; q < r * r; ++q) {
      bool probe = false;
      for (int side = 0; side < 4; ++side) probe |= (probed[c].second >> side & 1) && onSide(q, side);
      if (probe && hemisphere.edgeLuminance(probed[c].first, q) > 0) {
        asked.push_back(hemisphere.edgeDirection(probed[c].first, q));
        askedIndex.push_back(c);
      }
    }
  ask();
  thread_local std::vector<unsigned char> probeDark;
  probeDark.assign(probed.size(), 0);
  for (std::size_t a = 0; a < asked.size(); ++a)
    if (!seen[a]) probeDark[askedIndex[a]] = 1;
  for (std::size_t c = 0; c < probed.size(); ++c) {
    if (probeDark[c]) {
      resampled.push_back(probed[c].first);
      continue;
    }
    double cell = 0;
    for (int q = 0; q < r * r; ++q) cell += hemisphere.edgeLuminance(probed[c].first, q);
    whole[probed[c].first] = cell / (r * r);
    countsSubSamples[probed[c].first] = 1;
  }
  // The resampled cells' sub-samples, in rounds: where a sub-sample on a cell's side differs from
  // the neighbouring cell's state (its first sample, or its probes), the edge goes on into that
  // cell, which its first sample missed (a window's corner, a sliver thinner than a cell): it is
  // resampled too, until the sub-samples agree across every resampled cell's sides.
  thread_local std::vector<unsigned char> subLit;  // r² per resampled cell: lit (L > 0 and visible)
  thread_local std::vector<std::int32_t> slot;     // per cell: its place in `resampled`, or −1
  slot.assign(cells, -1);
  subLit.clear();
  const int mr = m * r;
  // The state at sub-grid position (I, J) ∈ [0, m·r)²: a resampled cell's sub-sample, else its
  // cell's; beyond the square, dark (as the cells' test counts it).
  auto subLitAt = [&](int I, int J) {
    if (I < 0 || J < 0 || I >= mr || J >= mr) return false;
    const std::size_t k = static_cast<std::size_t>(J / r) * m + I / r;
    return slot[k] >= 0 ? subLit[static_cast<std::size_t>(slot[k]) * (r * r) + (J % r) * r + I % r] != 0 : whole[k] > 0;
  };
  for (std::size_t done = 0; done < resampled.size();) {
    const std::size_t end = resampled.size();
    for (std::size_t c = done; c < end; ++c) slot[resampled[c]] = static_cast<std::int32_t>(c);
    subLit.resize(end * r * r, 0);
    asked.clear();
    askedIndex.clear();
    for (std::size_t c = done; c < end; ++c)
      for (int q = 0; q < r * r; ++q)
        if (hemisphere.edgeLuminance(resampled[c], q) > 0) {
          asked.push_back(hemisphere.edgeDirection(resampled[c], q));
          askedIndex.push_back(c * (r * r) + q);
        }
    ask();
    for (std::size_t a = 0; a < asked.size(); ++a) subLit[askedIndex[a]] = seen[a] ? 1 : 0;
    for (std::size_t c = done; c < end && edges == SkyEdges::Traced; ++c) {
      const std::size_t k = resampled[c];
      const int i = static_cast<int>(k % m), j = static_cast<int>(k / m);
      for (int side = 0; side < 4; ++side) {
        const int ii = i + kSides[side][0], jj = j + kSides[side][1];
        if (ii < 0 || ii >= m || jj < 0 || jj >= m) continue;
        const std::size_t kk = static_cast<std::size_t>(jj) * m + ii;
        if (slot[kk] >= 0) continue;
        const bool neighbourLit = whole[kk] > 0;
        for (int t = 0; t < r; ++t) {
          const int q = side == 0 ? t * r : side == 1 ? t * r + r - 1 : side == 2 ? t : (r - 1) * r + t;
          if ((subLit[c * (r * r) + q] != 0) != neighbourLit) {
            slot[kk] = static_cast<std::int32_t>(resampled.size());  // claimed; set again above
            resampled.push_back(kk);
            break;
          }
        }
      }
    }
    done = end;
  }
  for (std::size_t k = 0; k < cells; ++k) {
    if (slot[k] >= 0) continue;
    if (countsSubSamples[k]) {
      for (int q = 0; q < r * r; ++q)
        if (hemisphere.edgeLuminance(k, q) > 0) add(hemisphere.edgeDirection(k, q), hemisphere.edgeLuminance(k, q), 1.0 / (r * r));
    } else if (luminance[k] > 0) {
      add(hemisphere.direction(k), luminance[k], 1.0);
    }
  }
  // A sub-cell whose state differs from a neighbouring sub-cell's holds the edge: it is resampled
  // on a kSkyFineRefinement² grid, the others count their sub-sample.
  constexpr int s = kSkyFineRefinement;
  thread_local std::vector<std::size_t> fineIndex;  // c·r² + q of each sub-cell refined
  fineIndex.clear();
  asked.clear();
  askedIndex.clear();
  for (std::size_t c = 0; c < resampled.size(); ++c) {
    const std::size_t k = resampled[c];
    const int i = static_cast<int>(k % m), j = static_cast<int>(k / m);
    for (int q = 0; q < r * r; ++q) {
      const bool lit = subLit[c * (r * r) + q] != 0;
      const int I = i * r + q % r, J = j * r + q / r;
      const bool edge = edges == SkyEdges::Traced && s > 1 && (subLitAt(I - 1, J) != lit || subLitAt(I + 1, J) != lit || subLitAt(I, J - 1) != lit ||
                                  subLitAt(I, J + 1) != lit);
      if (!edge) {
        if (lit) add(hemisphere.edgeDirection(k, q), hemisphere.edgeLuminance(k, q), 1.0 / (r * r));
        continue;
      }
      fineIndex.push_back(c * (r * r) + q);
      for (int p = 0; p < s * s; ++p)
        if (hemisphere.fineLuminance(k, q, p) > 0) {
          asked.push_back(hemisphere.fineDirection(k, q, p));
          askedIndex.push_back((fineIndex.size() - 1) * (s * s) + p);
        }
    }
  }
  ask();
  for (std::size_t a = 0; a < asked.size(); ++a)
    if (seen[a]) {
      const std::size_t f = fineIndex[askedIndex[a] / (s * s)];
      const std::size_t k = resampled[f / (r * r)];
      const int q = static_cast<int>(f % (r * r)), p = static_cast<int>(askedIndex[a] % (s * s));
      add(hemisphere.fineDirection(k, q, p), hemisphere.fineLuminance(k, q, p), 1.0 / (r * r * s * s));
    }
}

// ∫ L V cos dω over a hemisphere's directions, in lux (skyIntegrate).
template <class Visible>
double skyIlluminance(SkyHemisphere& hemisphere, Visible&& visible, SkyEdges edges) {
  double sum = 0;
  skyIntegrate(hemisphere, visible, edges, [&](const Vec3&, double luminance, double share) { sum += luminance * share; });
  const double m = hemisphere.gridSide();
  return sum * kPi / (m * m);
}

template <class Visible>
double skyIlluminance(const SkyModel& sky, const Vec3& n, int directions, Visible&& visible, SkyEdges edges) {
  return skyIlluminance(skyHemisphere(sky, n, skyGridSide(directions)), visible, edges);
}

// skyIlluminance with nothing in the way (an upper bound of every shadowed estimate at n).
inline double unobstructedSkyIlluminance(const SkyModel& sky, const Vec3& n, int directions) {
  return skyHemisphere(sky, n, skyGridSide(directions)).unobstructedIlluminance();
}

// Daylight factor in percent: interior illuminance over the unobstructed horizontal illuminance of
// the same sky, DF = 100 · E_interior / E_h. Meant for the CIE overcast sky (type 1 or the
// traditional one), under which it does not depend on orientation or the sky's scale.
inline double daylightFactorPercent(double interiorLux, const SkyModel& sky) {
  return 100 * interiorLux / sky.horizontalIlluminance();
}

// The sky a scene's daylight factor is taken under: its one light when that is a sky and nothing
// else lights the scene (no other light, no emitting surface), else null: a daylight factor counts
// the sky's light alone, direct and interreflected. The caller decides whether a sky other than an
// overcast one (isOvercast) makes sense for it.
const SkyModel* daylightFactorSky(const Scene& scene);
// Whether the sky is one of the CIE overcast skies a daylight factor is defined under: the
// traditional one or standard type 1.
inline bool isOvercast(const SkyModel& sky) { return sky.isTraditionalOvercast() || sky.cieType() == 1; }

}  // namespace lambert
