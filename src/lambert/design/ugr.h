#pragma once
// Discomfort glare from luminaires: the CIE Unified Glare Rating (UGR).
//
//  - At an observer (CIE 117-1995 §3, eq. 3.1):  UGR = 8 log10( (0.25 / L_b) Σ_i L_i² ω_i / p_i² ),
//    L_i the luminance of luminaire i's luminous area seen from the eye (its candela toward the
//    eye / its luminous area projected toward the eye, cd/m²), ω_i that area's solid angle at the
//    eye (projected area / r², sr), p_i its Guth position index, L_b the background luminance
//    (cd/m²: the indirect vertical illuminance at the eye / π, CIE 117 §3.2). Since L_i² ω_i =
//    I_i² / (A_p,i r_i²), only the projected area A_p enters, and it must be known: a luminaire
//    whose photometric file gives no luminous opening is refused (an Error naming it) when it
//    lies in the field of view — a point has no luminance.
//  - The position index p: CIE 117-1995 Table 4.1 (Guth's index tabulated against H/R and T/R,
//    R the distance along the line of sight, T across it, H above the eye; the table EN 12464-1
//    tools use), bilinear between its entries. The table ends at T/R = 3 and H/R = 1.9 and leaves
//    blank the cells high above the line of sight: a luminaire there is outside the field of view
//    and excluded. Its transcription (from CIE 117 via eulumdat-ugr, MIT) is checked in the test
//    against the published cells and against Levin's closed form of Guth's index (1975), which it
//    follows within 11% everywhere.
//  - Exclusions (GlareSourceStatus): a luminaire at or behind the plane through the eye
//    perpendicular to the line of sight (R ≤ 0); below eye level (H < 0: Guth's index and the
//    table are for the field above the line of sight); outside the table (the field of view);
//    lights that are not luminaires (point, spot, sky, sun: no luminous area to rate).
//  - The standard UGR table of a luminaire (CIE 190:2010, the tabular method of CIE 117 §5): the
//    formula above at an observer seated at the middle of one wall (eye at the reference plane),
//    looking horizontally across the room along Y, under a regular array of the luminaire at
//    spacing S (0.25H as CIE 117 and the catalogue tools use; CIE 190 presents S = 1H, its
//    values are the same to a few hundredths, UGR's Σ and L_b both scale with the count), H =
//    2 m above the eye, in rooms X × Y (X across the line of sight) of 2H..12H and the five
//    reflectance sets ceiling/walls/reference plane 0.7/0.5/0.2 … 0.3/0.3/0.2, viewed crosswise
//    (the luminaire's C0–C180 axis, its length, across the line of sight) and endwise (along it).
//    The background (CIE 190 §4.3, eqs. 7–12): L_b = E_WID/π, E_WID = B·F_UWID the walls' mean
//    indirect illuminance, B = Φ_lamp N / A_w (N luminaires, A_w = 2H(X + Y)), F_UWID = F_DF F_T,FW
//    + F_DW F_T,WW−1 + F_DC F_T,CW, with F_DF, F_DW, F_DC the shares of the lamp flux that reach
//    the reference plane, the walls and the ceiling directly, and F_T the flux transfer factors of
//    the three-surface room (floor, walls, ceiling) with its exact form factors: these reproduce
//    CIE 190 Table 5 (k = 2.67) to its three digits. Where CIE 190 takes F_DF from the zonal
//    fluxes and its Table 4 coefficients (CIE 52's approximation of the distribution in four
//    zones), F_DF here is the exact direct share of the actual distribution over the actual array
//    (docs/photometry.md, "Glare (UGR)", gives the difference). Values are "uncorrected" (the lamp
//    flux scaled to Φ0 = 1000 lm, CIE 190 §4.1); at the lamp flux Φ add 8 log10(Φ/Φ0) (eq. 2).
//
// Units: luminance cd/m², intensity cd, solid angle sr, lengths m (scene positions are converted
// through metresPerUnit), flux lm. Cost: the formula is O(lights); a table is 38 rooms × the
// array (≤ 48 × 48 luminaires) plus one 90 × 180 direction grid of the distribution.
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/vec3.h"
#include "lambert/light/photometry.h"
#include "lambert/scene/scene.h"

namespace lambert {

// Guth's position index p of a glare source at height H above the eye, R ahead along the line of
// sight and T across it, from the ratios H/R and T/R (their absolute values are used): CIE 117
// Table 4.1, bilinear between its entries. NaN outside the table (T/R > 3, H/R > 1.9, or the
// blank cells above the line of sight): the source is outside the field of view.
double guthPositionIndex(double heightOverDistance, double lateralOverDistance);

// The luminous opening's area projected toward (C, γ), m²: the opening's face cos⁺γ (a rectangle
// openingLength × openingWidth, or an ellipse/circle of those axes where `round`) plus, where the
// opening has a height, its sides (sin γ times their widths seen from C). 0 where the file gives
// no opening size.
double projectedLuminousArea(const Photometry& photometry, double cDegrees, double gammaDegrees);

// The background luminance L_b of CIE 117 from the indirect illuminance on a vertical plane at the
// eye facing along the line of sight (lux, e.g. IlluminanceMeter's `indirect` at the eye with the
// view direction as normal): L_b = E_ind / π, cd/m².
double backgroundLuminanceFromIndirect(double indirectVerticalIlluminanceLux);

// The observer: eye position in scene units and line of sight, horizontal by definition (the
// direction's vertical component is dropped).
struct UgrObserver {
  Vec3 eye;
  Vec3 viewDirection{0, 0, -1};
  double backgroundLuminance = 0;  // L_b, cd/m², > 0
};

enum class GlareSourceStatus {
  Counted,             // in the sum
  NotALuminaire,       // a point, spot, directional or sky light: nothing to rate
  BehindObserver,      // R ≤ 0
  BelowEyeLevel,       // H < 0
  OutsideFieldOfView,  // beyond the position index table
  NotVisible,          // its luminous area shows no projected area toward the eye (a flat opening seen from above)
};

// One light's part in the sum (one per light, in the lights' order).
struct GlareSource {
  GlareSourceStatus status = GlareSourceStatus::NotALuminaire;
  double distanceAhead = 0, lateral = 0, height = 0;  // R, |T|, H: m, in the observer's frame
  double candela = 0;         // I toward the eye, cd (the light's multiplier and colour's luminance, IES tilt applied)
  double projectedArea = 0;   // A_p toward the eye, m²
  double luminance = 0;       // L = I / A_p, cd/m²
  double solidAngle = 0;      // ω = A_p / r², sr
  double positionIndex = 0;   // p
  double term() const { return status == GlareSourceStatus::Counted ? luminance * luminance * solidAngle / (positionIndex * positionIndex) : 0; }
};

struct UgrResult {
  // 8 log10(0.25 Σ / L_b); −infinity where no luminaire counts (or all are dark): no glare to rate.
  double ugr = 0;
  double glareSum = 0;             // Σ L² ω / p², cd²/(m⁴·sr)
  double backgroundLuminance = 0;  // L_b used, cd/m²
  // Counted sources whose ω lies outside 0.0003..0.1 sr, the range CIE 117 §3.3 validates UGR
  // for (smaller sources are overrated, larger underrated: CIE 147).
  int outsideValidityRange = 0;
  std::vector<GlareSource> sources;
};

// UGR at an observer from the scene's luminaires. An Error for a non-positive or non-finite L_b,
// a view direction without a horizontal part, or a luminaire in the field of view without a
// luminous opening size (naming it).
Result<UgrResult> unifiedGlareRating(std::span<const Light> lights, double metresPerUnit, const UgrObserver& observer);

// ---- The standard UGR table (CIE 190:2010) ----

struct UgrRoom {
  double xOverH = 0, yOverH = 0;  // X across the line of sight, Y along it, in multiples of H
};
// The 19 rooms of the standard table, in its row order.
inline constexpr std::array<UgrRoom, 19> kUgrTableRooms{{{2, 2},  {2, 3},  {2, 4},  {2, 6},  {2, 8},  {2, 12}, {4, 2},
                                                         {4, 3},  {4, 4},  {4, 6},  {4, 8},  {4, 12}, {8, 4},  {8, 6},
                                                         {8, 8},  {8, 12}, {12, 4}, {12, 6}, {12, 8}}};

struct UgrReflectances {
  double ceiling = 0, walls = 0, floor = 0;  // floor: the reference plane (eye level) cavity
};
// The five reflectance sets of the standard table, in its column order.
inline constexpr std::array<UgrReflectances, 5> kUgrTableReflectances{{{0.7, 0.5, 0.2}, {0.7, 0.3, 0.2}, {0.5, 0.5, 0.2}, {0.5, 0.3, 0.2}, {0.3, 0.3, 0.2}}};

enum class UgrViewing {
  Crosswise,  // the luminaire's C0–C180 axis (openingLength) across the line of sight
  Endwise,    // along it
};

struct UgrTableOptions {
  double heightAboveEye = 2.0;     // H, m: luminaire plane above the eye (= reference plane)
  double spacingOverHeight = 0.25; // S/H of the square array
};

// The parts of one value of the table, at the reference lamp flux Φ0 = 1000 lm.
struct UgrTableEntry {
  double ugr = 0;                  // uncorrected UGR
  double glareSum = 0;             // Σ L² ω / p², cd²/(m⁴·sr)
  double backgroundLuminance = 0;  // L_b, cd/m²
  int luminaires = 0;              // N in the array
  int counted = 0;                 // those inside the field of view
  double directFloor = 0, directWalls = 0, directCeiling = 0;  // F_DF, F_DW, F_DC: shares of the lamp flux
  double transferFloor = 0, transferWalls = 0, transferCeiling = 0;  // F_T,FW, F_T,WW−1, F_T,CW
};

// Flux transfer factors of the room cavity X × Y × H (in any one unit) with the given
// reflectances: the mean indirect flux the walls receive per unit of flux first reaching the
// floor (reference plane), the walls or the ceiling, over the walls' area in units of the first
// flux / (wall area) — F_T,FW, F_T,WW−1, F_T,CW of CIE 190 eq. 8b. Three-surface radiosity with
// the exact form factor between floor and ceiling (parallel rectangles, Howell C-11).
std::array<double, 3> ugrTransferFactors(double x, double y, double h, const UgrReflectances& reflectances);

// One value of the standard table. An Error where the photometry has no opening size, no flux,
// or the spacing leaves the room without a luminaire.
Result<UgrTableEntry> ugrTableEntry(const Photometry& photometry, const UgrRoom& room, const UgrReflectances& reflectances,
                                    UgrViewing viewing, const UgrTableOptions& options = {});

struct UgrTable {
  // uncorrected[viewing][room][reflectance set], UGR at Φ0 = 1000 lm lamp flux.
  std::array<std::array<std::array<double, 5>, 19>, 2> uncorrected{};
  // The lamp flux Φ of the file (its rated lamp lumens; for absolute photometry, which states
  // none, the luminaire's own flux) and 8 log10(Φ / 1000): the table at the file's flux is
  // uncorrected + fluxCorrection (CIE 190 eq. 2).
  double lampLumens = 0;
  double fluxCorrection = 0;
  double value(UgrViewing viewing, std::size_t room, std::size_t reflectances, bool corrected) const {
    return uncorrected[static_cast<int>(viewing)][room][reflectances] + (corrected ? fluxCorrection : 0);
  }
};

Result<UgrTable> ugrTable(const Photometry& photometry, const UgrTableOptions& options = {});

}  // namespace lambert
