#pragma once
// A luminaire's goniometric luminous intensity distribution, as manufacturers publish it: IES
// LM-63 files (ANSI/IES LM-63-1995, -2002, -2019) and EULUMDAT files (.ldt). Type C photometry:
// the vertical angle γ runs from the photometric nadir (0°, the direction the luminaire is aimed)
// to the zenith (180°); the horizontal angle C names the half plane through the nadir axis,
// counter-clockwise seen from above the luminaire, 0..360°. Every symmetry a file declares is
// expanded on reading, so candela(C, γ) covers the whole sphere. The files are read by
// load/photometry_file.h.
//
// Units: luminous intensity in candela (cd), luminous flux in lumen (lm), lengths in metres.
// A light built from it gives W/sr = cd × its colour / 683 (scene/scene.h, LightKind::Luminaire).
#include <string>
#include <vector>

namespace lambert {

// An IES tilt table (TILT=INCLUDE, or a TILT=<file>): the factor the candela values are
// multiplied by when the lamp is tilted from the position it was measured in (LM-63-2002 §5.8).
struct TiltTable {
  int lampGeometry = 1;         // 1: vertical base-up or base-down lamp; 2: horizontal lamp along
                                // the 0–180° axis; 3: horizontal lamp along the 90–270° axis
  std::vector<double> degrees;  // tilt angles, ascending
  std::vector<double> factors;  // candela multipliers, one per angle
  // The factor at a tilt angle, linear between the listed ones, the end values beyond them.
  double factor(double tiltDegrees) const;
};

class Photometry {
 public:
  std::string path;    // the file it was read from (for messages and for writing a scene back)
  std::string format;  // "IES LM-63-2002", "EULUMDAT", ...
  std::string name;    // the luminaire's name or catalogue number, where the file gives one

  // The measured grid after symmetry expansion: vertical angles γ (ascending, within [0, 180]),
  // horizontal angles C (ascending, within [0, 360), one entry for a rotationally symmetric
  // distribution), and candela values candelaGrid[c · verticalDegrees.size() + v], with every
  // multiplier of the file (candela multiplier, ballast factor, ballast-lamp factor; EULUMDAT:
  // cd/klm × the lamps' flux / 1000 × the conversion factor) applied.
  std::vector<double> verticalDegrees;
  std::vector<double> horizontalDegrees;
  std::vector<double> candelaGrid;

  // The rated flux of the lamps (number of lamps × lumens per lamp) in lm; 0 for absolute
  // photometry (IES lumens per lamp −1, as for LED luminaires), which has no lamp flux.
  double lampLumens = 0;
  // The luminaire's flux as the file states it (EULUMDAT: lamp flux × light output ratio), in lm;
  // 0 where it does not say.
  double statedLuminaireLumens = 0;
  double inputWatts = 0;  // the luminaire's input power in W, 0 where not given

  // The luminous opening, in metres: `length` along the C = 0–180° axis, `width` along the
  // C = 90–270° axis, `height` along the nadir axis. A circular opening has width = length =
  // its diameter and `round` set.
  double openingLength = 0, openingWidth = 0, openingHeight = 0;
  bool round = false;

  TiltTable tilt;  // empty degrees: TILT=NONE

  // Luminous intensity in cd toward (C, γ) in degrees: a monotone cubic (Steffen 1990) in γ
  // between the measured vertical angles, periodic in C, across the poles through the opposite
  // plane; never negative (a monotone cubic does not overshoot its data). Zero beyond the
  // measured vertical range (a 0–90° file emits nothing upward).
  double candela(double cDegrees, double gammaDegrees) const;
  // The largest measured value, cd.
  double maxCandela() const;
  // Total luminous flux in lm: ∫∫ I(C, γ) sin γ dγ dC over the sphere, by the midpoint rule over
  // 0.5° × 1° cells of the interpolated distribution (computed once on reading).
  double luminousFlux() const { return flux_; }
  // Recomputes luminousFlux() after the grid changed (the readers call it).
  void integrateFlux();

 private:
  double rowValue(std::size_t row, double cDegrees) const;
  double flux_ = 0;
};

}  // namespace lambert
