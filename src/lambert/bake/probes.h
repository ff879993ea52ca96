#pragma once
// Light probes: an irradiance volume of order-2 (L2, nine coefficients) spherical harmonics over a
// regular grid in the scene's open space, baked from a solved SolutionView, for lighting objects
// that move through the scene (Greger, Shirley, Hubbard & Greenberg, "The Irradiance Volume",
// 1998; Ramamoorthi & Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
// SIGGRAPH 2001).
//
// Grid. Probes sit at the centres of cubic cells of side `spacing` laid over the scene's bounding
// box (or the bounds asked for): dims = ceil(extent / spacing) cells per axis (at least one), the
// cells centred on the box, so every probe lies inside it and none on its faces.
//
// Per probe. `raysPerProbe` directions over the sphere, a scrambled (0,2)-sequence mapped onto it
// with equal area (stratified; scrambled per (seed, probe index), so the volume does not depend on
// the thread count). Each ray takes the radiance of the first surface it meets: the solution's
// outgoing radiance L = B/π at that point, interpolated over the hit patch of
// SolutionView::vertexMesh() from its corners' vertexRadiance() (the fan triangles Gouraud shading
// draws); a back face or a miss gives nothing. The point, spot and directional lights reach a probe
// as delta directions: E⊥ (I/d², times the spot's falloff, or a sun's E⊥) toward the light where
// a shadow ray finds it unoccluded. The radiance is projected onto the real SH basis (weight 4π/N
// per ray, with the rays' mean radiance as a control variate projected exactly onto Y00, so that a
// uniform environment gives exactly π L; the deltas exactly), and turned into irradiance SH by the clamped-cosine convolution
// E_lm = Â_l L_lm, Â_0 = π, Â_1 = 2π/3, Â_2 = π/4 (Ramamoorthi & Hanrahan 2001, eq. 8). The
// irradiance a surface of unit normal n receives there is E(n) = Σ_lm E_lm Y_lm(n).
//
// Accuracy. L2 keeps the low frequencies of irradiance: for smooth environments its error is a few
// per cent (Ramamoorthi & Hanrahan: under 3% on average); for a single delta light of E⊥ it is at
// most 0.094 E⊥ (at 90° from the light; 6% too bright facing it), and a bright area light close
// above a probe is spread the same way (docs/lightmaps.md gives the Cornell box's figures).
//
// Validity. A probe inside a closed object sees the backs of its faces: where more than
// `invalidBackFaceFraction` of its rays first meet a back face (the convention of
// geometry/coverage.h's isCovered), the probe is marked invalid, its coefficients are zero, and
// readers interpolate over the valid probes only.
//
// Cost: O(probes × raysPerProbe) ray casts plus a shadow ray per light per probe, parallel over
// probes; memory 27 floats and a byte per probe. The file format is in docs/lightmaps.md
// ("Light probes") and writeProbes below.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

class SolutionView;

// Coefficients per channel of an order-2 SH expansion, and per probe (RGB).
inline constexpr int kShCoefficients = 9;
inline constexpr int kProbeFloats = 3 * kShCoefficients;

// The nine real SH basis functions at a unit direction (x, y, z in scene axes), in the order
// k = l² + l + m: Y00; Y1,-1 = c1 y, Y10 = c1 z, Y11 = c1 x; Y2,-2 = c2 xy, Y2,-1 = c2 yz,
// Y20 = c3 (3z² − 1), Y21 = c2 xz, Y22 = c4 (x² − y²), orthonormal over the sphere
// (c0 = 1/(2√π), c1 = √(3/4π), c2 = √(15/4π), c3 = √(5/16π), c4 = √(15/16π)).
std::array<double, kShCoefficients> shBasis(const Vec3& unitDirection);

// An RGB function on the sphere in that basis.
using ShRgb = std::array<Rgb, kShCoefficients>;

// Projects a radiance function onto the basis from `rays` stratified directions with the mean as a
// control variate (see above), scrambled by (seed, stream).
ShRgb projectRadiance(const std::function<Rgb(const Vec3&)>& radiance, int rays, std::uint64_t seed,
                      std::uint64_t stream);
// Radiance SH → irradiance SH: each band l scaled by Â_l (π, 2π/3, π/4).
ShRgb irradianceFromRadiance(const ShRgb& radiance);
// Σ_k c_k Y_k(n): the irradiance (W/m²) a surface of unit normal n receives, for irradiance SH.
Rgb evaluateSh(const ShRgb& coefficients, const Vec3& unitNormal);

struct ProbeOptions {
  // Distance between neighbouring probes, scene units; 0: the spacing of about 4096 probes over
  // the bounds' volume, cbrt(volume / 4096) (16³ in a cube), and no less than a 64th of its
  // diagonal (a flat or thin box).
  double spacing = 0;
  std::optional<Bounds> bounds;  // the grid's box; none: sceneBounds(scene)
  int raysPerProbe = 512;        // sphere directions per probe (rounded up to a power of two)
  double invalidBackFaceFraction = 0.5;  // more back-face hits than this: the probe is inside geometry
  std::uint64_t seed = 1;
  bool showProgress = true;      // on a TTY
};

// A baked volume. Probe (i, j, k) (0 ≤ i < dims[0], …) lies at origin + spacing·(i, j, k) and is
// entry i + dims[0]·(j + dims[1]·k).
struct ProbeVolume {
  Vec3 origin;                       // the position of probe (0, 0, 0), scene units
  double spacing = 0;                // scene units
  std::array<std::uint32_t, 3> dims{};
  std::vector<std::uint8_t> valid;   // per probe: 1 valid, 0 inside geometry
  // Per probe, kProbeFloats floats: irradiance SH, coefficient-major (k = 0..8, each r, g, b),
  // W/m²; zero for invalid probes.
  std::vector<float> coefficients;
  std::size_t numValid = 0;
  // How the bake went (not stored in the file).
  std::uint64_t raysCast = 0;  // sphere rays (shadow rays not counted)
  double seconds = 0;          // the whole bake
  double radianceSeconds = 0;  // of which: the solution's vertex radiance (the final gather, where it runs)

  std::size_t numProbes() const { return valid.size(); }
  Vec3 position(std::size_t probe) const;
  ShRgb irradianceSh(std::size_t probe) const;
  // E(n) at one probe.
  Rgb irradiance(std::size_t probe, const Vec3& unitNormal) const;
  // The irradiance SH at any point: the eight probes of the grid cell around it blended
  // trilinearly over those that are valid (invalid probes left out, the weights of the rest
  // renormalised); a point outside the grid takes the nearest place on it. None where no probe
  // around it is valid (inside geometry). As examples/read_probes.cpp blends, which reads the
  // file alone; clamp E(n) = evaluateSh(sh, n) at zero where it is used (L2 rings below zero
  // facing a dark region opposite a bright one).
  std::optional<ShRgb> irradianceShAt(const Vec3& position) const;
};

// The grid the options give for the scene (no probe computed): origin, spacing and dims, with
// empty valid and coefficients. Errors: a spacing that is negative or not finite, empty bounds,
// or more than 2²⁴ probes (the message says which spacing fits).
Result<ProbeVolume> probeGrid(const Scene& scene, const ProbeOptions& options);

// Bakes the volume from the solved view (solve() first). Errors as probeGrid's, and rays per probe
// outside [1, 2²⁰] or a back-face share outside [0, 1].
Result<ProbeVolume> bakeProbes(const SolutionView& solution, const ProbeOptions& options = {});

// The probe file (little-endian; docs/lightmaps.md): a 64-byte header — magic "LMBPROBE", uint32
// version (1), uint32 coefficients per channel (9), float64 origin x, y, z, float64 spacing,
// uint32 dims x, y, z, uint32 valid probe count — then one byte per probe (1 valid, 0 invalid),
// zero bytes up to a multiple of 4, then kProbeFloats float32 per probe as in ProbeVolume. Probes
// run x fastest, then y, then z. Written atomically (core/atomic_file.h).
Status writeProbes(const std::string& path, const ProbeVolume& volume);
// Reads a file writeProbes wrote; refuses, naming the file and what is wrong, a file with another
// magic or version, or whose size does not match its header.
Result<ProbeVolume> readProbes(const std::string& path);

}  // namespace lambert
