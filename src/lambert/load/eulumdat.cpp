#include "lambert/load/photometry_file.h"

// EULUMDAT (.ldt): the fixed line layout of its header (one value a line), the lamp sets, then the
// C angles, γ angles and intensities in cd/klm, its symmetry said by Isym 0–4.
#include <algorithm>
#include <cmath>
#include <tuple>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/load/photometry_text.h"

namespace lambert {

using namespace photometry_text;

Result<Photometry> parseEulumdat(const std::string& text, const std::string& path) {
  const std::vector<std::string> lines = splitLines(text);
  Photometry out;
  out.path = path;
  out.format = "EULUMDAT";
  bool commaWarned = false;
  // The number on 1-based line `n` (EULUMDAT has one value per line in its header).
  auto number = [&](std::size_t n, const std::string& what, double& value) -> std::string {
    if (n > lines.size())
      return path + ":" + std::to_string(lines.size()) + ": the file ends before line " + std::to_string(n) + " (" + what +
             "): it is truncated; get the complete file from its source";
    std::string t = trim(lines[n - 1]);
    if (parseNumber(t, value)) return {};
    // Some writers use a decimal comma.
    std::string dotted = t;
    std::replace(dotted.begin(), dotted.end(), ',', '.');
    if (parseNumber(dotted, value)) {
      if (!commaWarned) warning(path + ":" + std::to_string(n) + ": decimal comma in \"" + t + "\" read as a point");
      commaWarned = true;
      return {};
    }
    return path + ":" + std::to_string(n) + ": expected a number for " + what + ", found \"" + t.substr(0, 40) +
           "\" (the file is damaged or not a EULUMDAT file)";
  };
  double ityp = 0, isym = 0, mc = 0, dc = 0, ng = 0, dg = 0;
  for (auto [line, what, value] : {std::tuple{2, "the type indicator Ityp", &ityp}, {3, "the symmetry indicator Isym", &isym},
                                   {4, "the number of C planes Mc", &mc}, {5, "the C-plane spacing Dc", &dc},
                                   {6, "the number of intensities per C plane Ng", &ng}, {7, "the γ spacing Dg", &dg}})
    if (std::string e = number(static_cast<std::size_t>(line), what, *value); !e.empty()) return Error{e};
  (void)ityp, (void)dc, (void)dg;  // the angles themselves are listed below; Ityp only classifies
  if (lines.size() >= 9) out.name = trim(lines[8]);
  const int symmetryIndicator = static_cast<int>(isym);
  if (isym != symmetryIndicator || symmetryIndicator < 0 || symmetryIndicator > 4)
    return Error{path + ":3: the symmetry indicator Isym must be 0, 1, 2, 3 or 4, found " + trim(lines[2])};
  if (mc != std::floor(mc) || mc < 1 || mc > static_cast<double>(kMaxAngles))
    return Error{path + ":4: the number of C planes Mc must be a whole number from 1 to " + std::to_string(kMaxAngles)};
  if (ng != std::floor(ng) || ng < 2 || ng > static_cast<double>(kMaxAngles))
    return Error{path + ":6: the number of intensities per C plane Ng must be a whole number from 2 to " + std::to_string(kMaxAngles)};
  const auto numC = static_cast<std::size_t>(mc), nV = static_cast<std::size_t>(ng);
  // The C planes the file gives intensities for (EULUMDAT: Mc1..Mc2): all, one, C0–C180, C90–C270,
  // C0–C90. (The original description's "Mc1 = 3Mc/4 + 1" for Isym 3 is read, as the programs
  // that write these files do, as the planes from C90 to C270.)
  std::size_t firstPlane = 0, planes = numC;
  Symmetry symmetry = Symmetry::Full;
  const std::string divisible = path + ":4: Mc = " + std::to_string(numC) + " C planes cannot hold symmetry Isym " + std::to_string(symmetryIndicator);
  switch (symmetryIndicator) {
    case 0: break;
    case 1: planes = 1, symmetry = Symmetry::Rotational; break;
    case 2:
      if (numC % 2) return Error{divisible + " (Mc must be even)"};
      planes = numC / 2 + 1, symmetry = Symmetry::BilateralC0;
      break;
    case 3:
      if (numC % 4) return Error{divisible + " (Mc must be a multiple of 4)"};
      firstPlane = numC / 4, planes = numC / 2 + 1, symmetry = Symmetry::BilateralC90;
      break;
    case 4:
      if (numC % 4) return Error{divisible + " (Mc must be a multiple of 4)"};
      planes = numC / 4 + 1, symmetry = Symmetry::Quadrant;
      break;
  }
  double lengthMm = 0, widthMm = 0, heights[4] = {}, dff = 0, lor = 0, conversion = 0, tiltDuring = 0, sets = 0;
  for (auto [line, what, value] : {std::tuple{16, "the length or diameter of the luminous area (mm)", &lengthMm},
                                   {17, "the width of the luminous area (mm)", &widthMm}, {18, "the luminous area's height at C0 (mm)", &heights[0]},
                                   {19, "the luminous area's height at C90 (mm)", &heights[1]}, {20, "the luminous area's height at C180 (mm)", &heights[2]},
                                   {21, "the luminous area's height at C270 (mm)", &heights[3]}, {22, "the downward flux fraction (%)", &dff},
                                   {23, "the light output ratio LORL (%)", &lor}, {24, "the conversion factor for luminous intensities", &conversion},
                                   {25, "the tilt during measurement", &tiltDuring}, {26, "the number of lamp sets", &sets}})
    if (std::string e = number(static_cast<std::size_t>(line), what, *value); !e.empty()) return Error{e};
  (void)dff, (void)tiltDuring;
  if (sets != std::floor(sets) || sets < 1 || sets > 20)
    return Error{path + ":26: the number of standard lamp sets must be a whole number from 1 to 20, found " + trim(lines[25])};
  out.round = widthMm == 0;
  out.openingLength = std::fabs(lengthMm) / 1000;
  out.openingWidth = out.round ? out.openingLength : std::fabs(widthMm) / 1000;
  out.openingHeight = std::fabs(std::max({heights[0], heights[1], heights[2], heights[3]})) / 1000;
  // Each lamp set: number of lamps, type, total flux (lm), colour temperature, CRI, wattage.
  // Intensities are per 1000 lm of the first (standard) set.
  double lampCount = 0, flux = 0, watts = 0;
  if (std::string e = number(27, "the first lamp set's number of lamps", lampCount); !e.empty()) return Error{e};
  if (std::string e = number(29, "the first lamp set's total luminous flux (lm)", flux); !e.empty()) return Error{e};
  if (std::string e = number(32, "the first lamp set's wattage including ballast (W)", watts); !e.empty()) return Error{e};
  if (!(flux > 0))
    return Error{path + ":29: the first lamp set's luminous flux must be positive (the intensities are in cd per 1000 lm of it), found " +
                 trim(lines[28])};
  if (!(conversion > 0)) {
    warning(path + ":24: conversion factor " + trim(lines[23]) + " is not positive; taken as 1");
    conversion = 1;
  }
  out.lampLumens = flux;
  out.inputWatts = std::fmax(watts, 0.0);
  if (lor > 0 && lor <= 100) {
    out.statedLuminaireLumens = flux * lor / 100;
  } else {
    warning(path + ":23: light output ratio " + trim(lines[22]) + "% lies outside (0, 100]; the luminaire's flux is not stated");
  }
  // After the sets: 10 direct ratios, then the Mc C angles, Ng γ angles and the intensities.
  const std::size_t anglesFrom = 26 + 6 * static_cast<std::size_t>(sets) + 10;
  std::vector<std::string> rest(lines.begin() + static_cast<std::ptrdiff_t>(std::min(anglesFrom, lines.size())), lines.end());
  std::vector<Token> values = tokens(rest, 0);
  for (Token& t : values) {
    t.line += static_cast<int>(anglesFrom);
    if (t.text.find(',') != std::string::npos) std::replace(t.text.begin(), t.text.end(), ',', '.');
  }
  NumberReader in(values, path, static_cast<int>(lines.size()));
  if (in.remaining() < numC + nV + planes * nV)
    return Error{path + ":" + std::to_string(lines.size()) + ": the file holds " + std::to_string(in.remaining()) + " values after line " +
                 std::to_string(anglesFrom) + ", fewer than the " + std::to_string(numC) + " C angles, " + std::to_string(nV) +
                 " γ angles and " + std::to_string(planes * nV) + " intensities its header declares (it is truncated: get the complete file from its source)"};
  std::vector<double> cAngles(numC), vertical(nV), columns(planes * nV);
  for (std::size_t i = 0; i < numC; ++i)
    if (!in.next("C angle " + std::to_string(i + 1) + " of " + std::to_string(numC), cAngles[i])) return Error{in.error()};
  const int cLine = in.line();
  for (std::size_t i = 0; i < nV; ++i)
    if (!in.next("γ angle " + std::to_string(i + 1) + " of " + std::to_string(nV), vertical[i])) return Error{in.error()};
  const int gammaLine = in.line();
  const double scale = flux / 1000 * conversion;
  std::size_t negatives = 0;
  for (std::size_t p = 0; p < planes; ++p)
    for (std::size_t v = 0; v < nV; ++v) {
      double& c = columns[p * nV + v];
      if (!in.next("intensity " + std::to_string(p * nV + v + 1) + " of " + std::to_string(planes * nV) + " (cd/klm)", c)) return Error{in.error()};
      if (c < 0) ++negatives, c = 0;
      c *= scale;
    }
  if (negatives > 0) warning(path + ": " + std::to_string(negatives) + " negative intensities set to 0");
  if (in.remaining() > 0)
    warning(path + ":" + std::to_string(in.nextLine()) + ": " + std::to_string(in.remaining()) + " value(s) after the intensity table ignored");
  if (std::string bad = checkAscending(cAngles, 0, 360, "C angle"); !bad.empty()) return Error{path + ":" + std::to_string(cLine) + ": " + bad};
  if (std::string bad = checkAscending(vertical, 0, 180, "γ angle"); !bad.empty()) return Error{path + ":" + std::to_string(gammaLine) + ": " + bad};
  std::vector<double> given(cAngles.begin() + static_cast<std::ptrdiff_t>(firstPlane),
                            cAngles.begin() + static_cast<std::ptrdiff_t>(firstPlane + planes));
  out.verticalDegrees = vertical;
  expandSymmetry(symmetry, given, columns, nV, out);
  out.integrateFlux();
  if (out.statedLuminaireLumens > 0 && std::fabs(out.luminousFlux() - out.statedLuminaireLumens) > 0.05 * out.statedLuminaireLumens)
    warning(path + ": the intensities integrate to " + std::to_string(std::lround(out.luminousFlux())) + " lm, not the lamps' flux × LOR = " +
            std::to_string(std::lround(out.statedLuminaireLumens)) + " lm the file states; the intensities are used as they are");
  return out;
}

Result<Photometry> readEulumdat(const std::string& path) {
  Result<std::string> text = readWholeFile(path);
  if (!text) return text.error();
  return parseEulumdat(*text, path);
}

}  // namespace lambert
