#include "lambert/load/photometry_file.h"

// IES LM-63 (ANSI/IES LM-63-1995, -2002, -2019, and the 1986 and 1991 forms before them): the
// header line, keyword lines up to TILT=, a tilt table inline or in a file beside it, the
// luminaire and electrical lines, the angles and the candela table (LM-63-2002 §5.9–5.13), its
// symmetry said by the first and last horizontal angles.
#include <cmath>
#include <filesystem>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/load/photometry_text.h"

namespace lambert {

using namespace photometry_text;

namespace {

// An IES tilt block: lamp-to-luminaire geometry, the number of pairs, the angles, the factors.
bool readTiltBlock(NumberReader& in, TiltTable& tilt, std::string& error) {
  double geometry = 0;
  std::size_t n = 0;
  if (!in.next("the tilt table's lamp-to-luminaire geometry", geometry) || !in.nextCount("the number of tilt angles", 1, kMaxAngles, n)) {
    error = in.error();
    return false;
  }
  tilt.lampGeometry = static_cast<int>(geometry);
  tilt.degrees.resize(n);
  tilt.factors.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!in.next("tilt angle " + std::to_string(i + 1), tilt.degrees[i])) return error = in.error(), false;
  for (std::size_t i = 0; i < n; ++i)
    if (!in.next("tilt factor " + std::to_string(i + 1), tilt.factors[i])) return error = in.error(), false;
  if (std::string bad = checkAscending(tilt.degrees, 0, 180, "tilt angle"); !bad.empty()) {
    error = "line " + std::to_string(in.line()) + ": " + bad;
    return false;
  }
  for (double& f : tilt.factors) f = std::fmax(f, 0.0);
  return true;
}

}  // namespace

Result<Photometry> parseIes(const std::string& text, const std::string& path) {
  const std::vector<std::string> lines = splitLines(text);
  if (lines.empty()) return Error{path + ": the file is empty (an IES LM-63 file starts with IESNA:LM-63-…, keywords and TILT=)"};
  Photometry out;
  out.path = path;
  const std::string first = upper(trim(lines[0]));
  bool lm63_1995OrOlder = true;
  if (first.rfind("IESNA:LM-63-1995", 0) == 0) {
    out.format = "IES LM-63-1995";
  } else if (first.rfind("IESNA:LM-63-2002", 0) == 0) {
    out.format = "IES LM-63-2002", lm63_1995OrOlder = false;
  } else if (first.rfind("IES:LM-63-2019", 0) == 0 || first.rfind("IESNA:LM-63-2019", 0) == 0) {
    out.format = "IES LM-63-2019", lm63_1995OrOlder = false;
  } else if (first.rfind("IESNA91", 0) == 0) {
    out.format = "IES LM-63-1991";
  } else if (first.rfind("IES", 0) == 0 && first.find("LM-63") != std::string::npos) {
    warning(path + ":1: unknown LM-63 version \"" + trim(lines[0]).substr(0, 40) + "\"; read as LM-63-2002");
    out.format = "IES LM-63 (" + trim(lines[0]).substr(0, 40) + ")", lm63_1995OrOlder = false;
  } else {
    out.format = "IES LM-63-1986";  // the first version had no header line
  }
  // Keyword lines ([TEST], [LUMINAIRE], ...) up to the TILT= line.
  std::size_t tiltLine = lines.size();
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const std::string t = trim(lines[l]);
    if (upper(t).rfind("TILT", 0) == 0 && t.find('=') != std::string::npos) {
      tiltLine = l;
      break;
    }
    if (t.size() > 1 && t[0] == '[') {
      const std::size_t close = t.find(']');
      const std::string key = upper(t.substr(1, close == std::string::npos ? 0 : close - 1));
      const std::string value = close == std::string::npos ? std::string() : trim(t.substr(close + 1));
      if ((key == "LUMINAIRE" || (key == "LUMCAT" && out.name.empty())) && !value.empty()) out.name = value;
    }
  }
  if (tiltLine == lines.size())
    return Error{path + ": no TILT= line: an IES LM-63 file has one after its keyword lines (is this an IES file? EULUMDAT files end in .ldt)"};
  const std::string tiltValue = trim(trim(lines[tiltLine]).substr(trim(lines[tiltLine]).find('=') + 1));
  const int tiltLineNumber = static_cast<int>(tiltLine + 1);
  const std::vector<Token> values = tokens(lines, tiltLine + 1);
  NumberReader in(values, path, static_cast<int>(lines.size()));
  const std::string tiltUpper = upper(tiltValue);
  if (tiltUpper == "INCLUDE") {
    std::string error;
    if (!readTiltBlock(in, out.tilt, error)) return Error{error.rfind(path, 0) == 0 ? error : path + ": " + error};
  } else if (tiltUpper != "NONE") {
    if (tiltValue.empty()) return Error{path + ":" + std::to_string(tiltLineNumber) + ": TILT= names nothing (write TILT=NONE, TILT=INCLUDE or TILT=<file>)"};
    const std::string tiltPath = (std::filesystem::path(path).parent_path() / tiltValue).string();
    Result<std::string> tiltText = readWholeFile(tiltPath);
    if (!tiltText)
      return Error{path + ":" + std::to_string(tiltLineNumber) + ": TILT=" + tiltValue + ": the tilt file " + tiltPath +
                   " cannot be read (put it beside the IES file, write its table inline after TILT=INCLUDE, or write TILT=NONE)"};
    const std::vector<std::string> tiltLines = splitLines(*tiltText);
    const std::vector<Token> tiltTokens = tokens(tiltLines, 0);
    NumberReader tiltIn(tiltTokens, tiltPath, static_cast<int>(tiltLines.size()));
    std::string error;
    if (!readTiltBlock(tiltIn, out.tilt, error)) return Error{error.rfind(tiltPath, 0) == 0 ? error : tiltPath + ": " + error};
  }

  // LM-63-2002 §5.9–5.13: the luminaire line, the electrical line, the angles, the candela values.
  double lamps = 0, lumensPerLamp = 0, multiplier = 0, photometricType = 0, units = 0, width = 0, length = 0, height = 0;
  std::size_t nV = 0, nH = 0;
  if (!in.next("the number of lamps", lamps) || !in.next("the lumens per lamp", lumensPerLamp) ||
      !in.next("the candela multiplier", multiplier) || !in.nextCount("the number of vertical angles", 2, kMaxAngles, nV) ||
      !in.nextCount("the number of horizontal angles", 1, kMaxAngles, nH) || !in.next("the photometric type", photometricType))
    return Error{in.error()};
  const int typeLine = in.line();
  if (!in.next("the units type", units) || !in.next("the width of the luminous opening", width) ||
      !in.next("the length of the luminous opening", length) || !in.next("the height of the luminous opening", height))
    return Error{in.error()};
  const int unitsLine = in.line();
  double ballastFactor = 0, ballastLampFactor = 0, watts = 0;
  if (!in.next("the ballast factor", ballastFactor) || !in.next(lm63_1995OrOlder ? "the ballast-lamp photometric factor" : "the future-use value", ballastLampFactor) ||
      !in.next("the input watts", watts))
    return Error{in.error()};
  const int ballastLine = in.line();
  const std::string here = path + ":" + std::to_string(typeLine) + ": ";
  if (photometricType == 2 || photometricType == 3)
    return Error{here + "photometric type " + std::string(photometricType == 2 ? "B (2, floodlight)" : "A (3, automotive)") +
                 " is not supported: lambert reads type C (1), the goniometry of building luminaires; convert the file to type C "
                 "with the photometric software that made it"};
  if (photometricType != 1)
    return Error{here + "photometric type " + std::to_string(photometricType) + " is not one of 1 (C), 2 (B), 3 (A)"};
  if (!(multiplier > 0)) return Error{here + "the candela multiplier must be positive, found " + std::to_string(multiplier)};
  if (!(lamps >= 1)) {
    warning(here + "number of lamps " + std::to_string(lamps) + " is not positive; taken as 1");
    lamps = 1;
  }
  if (lumensPerLamp == -1) {
    out.lampLumens = 0;  // absolute photometry (LM-63-2002 §5.9: −1 for luminaires measured without separate lamps)
  } else if (lumensPerLamp > 0) {
    out.lampLumens = lamps * lumensPerLamp;
  } else {
    warning(here + "lumens per lamp " + std::to_string(lumensPerLamp) + " is neither positive nor −1; read as absolute photometry (−1)");
  }
  double metresPerUnit = 0.3048;
  if (units == 2) {
    metresPerUnit = 1;
  } else if (units != 1) {
    warning(path + ":" + std::to_string(unitsLine) + ": units type " + std::to_string(units) +
            " is neither 1 (feet) nor 2 (metres); the opening's size is read in feet");
  }
  // LM-63-2002 §5.9: a negative width or length describes a round opening (its diameter).
  out.round = width < 0 || length < 0;
  out.openingWidth = std::fabs(width) * metresPerUnit;
  out.openingLength = std::fabs(length) * metresPerUnit;
  out.openingHeight = std::fabs(height) * metresPerUnit;
  if (out.round) out.openingWidth = out.openingLength = std::fmax(out.openingWidth, out.openingLength);
  if (!(ballastFactor > 0)) {
    warning(path + ":" + std::to_string(ballastLine) + ": ballast factor " + std::to_string(ballastFactor) + " is not positive; taken as 1");
    ballastFactor = 1;
  }
  // The second value of the line is a multiplier only in LM-63-1995 and before (the
  // ballast-lamp photometric factor); LM-63-2002 reserves it ("future use", 1) and LM-63-2019
  // gives the file generation type there, neither of which scales the candela values.
  double scale = multiplier * ballastFactor;
  if (lm63_1995OrOlder) {
    if (ballastLampFactor > 0) {
      scale *= ballastLampFactor;
    } else {
      warning(path + ":" + std::to_string(ballastLine) + ": ballast-lamp photometric factor " + std::to_string(ballastLampFactor) +
              " is not positive; taken as 1");
    }
  }
  out.inputWatts = std::fmax(watts, 0.0);
  // Before anything is allocated for them: a garbled count must not ask for gigabytes.
  if (in.remaining() < nV + nH + nV * nH)
    return Error{path + ":" + std::to_string(lines.size()) + ": the file holds " + std::to_string(in.remaining()) +
                 " values after line " + std::to_string(ballastLine) + ", fewer than the " + std::to_string(nV) + " vertical angles, " +
                 std::to_string(nH) + " horizontal angles and " + std::to_string(nV * nH) +
                 " candela values it declares (it is truncated or its counts are wrong: get the complete file from its source)"};

  std::vector<double> vertical(nV), horizontal(nH), columns(nV * nH);
  for (std::size_t i = 0; i < nV; ++i)
    if (!in.next("vertical angle " + std::to_string(i + 1) + " of " + std::to_string(nV), vertical[i])) return Error{in.error()};
  const int verticalLine = in.line();
  for (std::size_t i = 0; i < nH; ++i)
    if (!in.next("horizontal angle " + std::to_string(i + 1) + " of " + std::to_string(nH), horizontal[i])) return Error{in.error()};
  const int horizontalLine = in.line();
  int negativeLine = 0;
  std::size_t negatives = 0;
  for (std::size_t h = 0; h < nH; ++h)
    for (std::size_t v = 0; v < nV; ++v) {
      double& c = columns[h * nV + v];
      if (!in.next("candela value " + std::to_string(h * nV + v + 1) + " of " + std::to_string(nV * nH) + " (horizontal angle " +
                       std::to_string(horizontal[h]) + "°, vertical " + std::to_string(vertical[v]) + "°)",
                   c))
        return Error{in.error()};
      if (c < 0) {
        if (negatives++ == 0) negativeLine = in.line();
        c = 0;
      }
      c *= scale;
    }
  if (negatives > 0)
    warning(path + ":" + std::to_string(negativeLine) + ": " + std::to_string(negatives) + " negative candela value" +
            (negatives > 1 ? "s" : "") + " (the first here) set to 0");
  if (in.remaining() > 0)
    warning(path + ":" + std::to_string(in.nextLine()) + ": " + std::to_string(in.remaining()) +
            " value(s) after the candela table ignored (the table holds vertical × horizontal = " + std::to_string(nV * nH) + ")");
  if (std::string bad = checkAscending(vertical, 0, 180, "vertical angle"); !bad.empty())
    return Error{path + ":" + std::to_string(verticalLine) + ": " + bad + " (type C vertical angles run from 0° at nadir to 180°)"};
  if (std::string bad = checkAscending(horizontal, 0, 360, "horizontal angle"); !bad.empty())
    return Error{path + ":" + std::to_string(horizontalLine) + ": " + bad};
  // LM-63-2002 §5.13: the first and last horizontal angles say the symmetry.
  Symmetry symmetry = Symmetry::Full;
  const double firstC = horizontal.front(), lastC = horizontal.back();
  if (nH == 1) {
    symmetry = Symmetry::Rotational;
  } else if (firstC == 0 && lastC == 90) {
    symmetry = Symmetry::Quadrant;
  } else if (firstC == 0 && lastC == 180) {
    symmetry = Symmetry::BilateralC0;
  } else if (firstC == 90 && lastC == 270) {
    symmetry = Symmetry::BilateralC90;  // LM-63-1995 allowed a bilateral file about the 90–270° plane
  } else if (firstC == 0 && lastC > 180) {
    symmetry = Symmetry::Full;  // up to 360° (the 360° plane repeats 0°); short of it, the gap is interpolated across
  } else {
    return Error{path + ":" + std::to_string(horizontalLine) + ": horizontal angles from " + std::to_string(firstC) + "° to " +
                 std::to_string(lastC) + "° describe no LM-63 symmetry (0–0 rotational, 0–90 quadrant, 0–180 or 90–270 bilateral, "
                 "0–360 none)"};
  }
  if (nH == 1 && firstC != 0)
    warning(path + ":" + std::to_string(horizontalLine) + ": a single horizontal angle should be 0°, found " + std::to_string(firstC) +
            "°; read as rotationally symmetric");
  out.verticalDegrees = vertical;
  expandSymmetry(symmetry, horizontal, columns, nV, out);
  out.integrateFlux();
  return out;
}

Result<Photometry> readIes(const std::string& path) {
  Result<std::string> text = readWholeFile(path);
  if (!text) return text.error();
  return parseIes(*text, path);
}

}  // namespace lambert
