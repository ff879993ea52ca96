#include "lambert/light/photometry.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <tuple>
#include <utility>

#include "lambert/core/rgb.h"
#include "lambert/core/text.h"
#include "lambert/core/vec3.h"
#include "lambert/core/warning.h"

namespace lambert {
namespace {

// Limits a file may not exceed: beyond them it is garbled, not large (real files have at most a
// few hundred angles per axis).
constexpr std::size_t kMaxAngles = 3600;

// Steffen's slope at the middle of three points (M. Steffen, "A simple method for monotonic
// interpolation in one dimension", Astron. Astrophys. 239, 1990, eqs. 11 and 13): zero at a local
// extremum, else the parabola's slope limited to twice the smaller secant, so that the cubic
// Hermite interpolant never overshoots its data (and so never goes negative between positive
// candela values).
double steffenSlope(double xa, double ya, double xb, double yb, double xc, double yc) {
  const double ha = xb - xa, hb = xc - xb;
  const double sa = (yb - ya) / ha, sb = (yc - yb) / hb;
  if (!(sa * sb > 0)) return 0;
  const double p = (sa * hb + sb * ha) / (ha + hb);
  const double limited = std::min({std::fabs(sa), std::fabs(sb), 0.5 * std::fabs(p)});
  return (sa > 0 ? 2 : -2) * limited;
}

// The cubic Hermite interpolant on [x1, x2] with end slopes d1, d2.
double hermite(double x, double x1, double y1, double d1, double x2, double y2, double d2) {
  const double h = x2 - x1, t = (x - x1) / h, t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * y1 + (t3 - 2 * t2 + t) * h * d1 + (-2 * t3 + 3 * t2) * y2 + (t3 - t2) * h * d2;
}

// A monotone cubic through (x0..x3, y0..y3) evaluated on [x1, x2]; a missing outer point
// (hasLeft/hasRight false) gives its end the interval's secant, which keeps it monotone.
double monotoneCubic(double x, bool hasLeft, double x0, double y0, double x1, double y1, double x2, double y2, bool hasRight,
                     double x3, double y3) {
  const double secant = (y2 - y1) / (x2 - x1);
  const double d1 = hasLeft ? steffenSlope(x0, y0, x1, y1, x2, y2) : secant;
  const double d2 = hasRight ? steffenSlope(x1, y1, x2, y2, x3, y3) : secant;
  return hermite(x, x1, y1, d1, x2, y2, d2);
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Lines of a text file with either line ending (\n, \r\n, or a lone \r).
std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\r' || c == '\n') {
      lines.push_back(line);
      line.clear();
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    } else {
      line += c;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// A number, the whole of `s`; false when it is not one (or not finite).
bool parseNumber(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

struct Token {
  std::string text;
  int line = 0;  // 1-based
};

// The whitespace- and comma-separated values of lines[first..], each with its line number (IES
// values may be split over lines anywhere, LM-63-2002 §5.10).
std::vector<Token> tokens(const std::vector<std::string>& lines, std::size_t first) {
  std::vector<Token> out;
  for (std::size_t l = first; l < lines.size(); ++l) {
    std::string word;
    for (char c : lines[l] + " ") {
      if (std::isspace(static_cast<unsigned char>(c)) || c == ',') {
        if (!word.empty()) out.push_back({word, static_cast<int>(l + 1)});
        word.clear();
      } else {
        word += c;
      }
    }
  }
  return out;
}

// Reads numbers off a token stream, failing with file:line and what was expected.
class NumberReader {
 public:
  NumberReader(const std::vector<Token>& tokens, std::string path, int lastLine)
      : tokens_(tokens), path_(std::move(path)), lastLine_(lastLine) {}
  bool next(const std::string& what, double& out) {
    if (at_ >= tokens_.size()) {
      error_ = path_ + ":" + std::to_string(lastLine_) + ": the file ends before " + what +
               " (it is truncated: get the complete file from its source)";
      return false;
    }
    const Token& t = tokens_[at_];
    if (!parseNumber(t.text, out)) {
      error_ = path_ + ":" + std::to_string(t.line) + ": expected a number for " + what + ", found \"" + t.text.substr(0, 40) +
               "\" (the file is damaged or not an IES LM-63 file)";
      return false;
    }
    line_ = t.line;
    ++at_;
    return true;
  }
  bool nextCount(const std::string& what, std::size_t min, std::size_t max, std::size_t& out) {
    double v = 0;
    if (!next(what, v)) return false;
    if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max)) {
      error_ = path_ + ":" + std::to_string(line_) + ": " + what + " must be a whole number from " + std::to_string(min) +
               " to " + std::to_string(max) + ", found " + tokens_[at_ - 1].text;
      return false;
    }
    out = static_cast<std::size_t>(v);
    return true;
  }
  const std::string& error() const { return error_; }
  int line() const { return line_; }
  std::size_t remaining() const { return tokens_.size() - at_; }
  int nextLine() const { return at_ < tokens_.size() ? tokens_[at_].line : lastLine_; }

 private:
  const std::vector<Token>& tokens_;
  std::string path_;
  int lastLine_;
  std::size_t at_ = 0;
  int line_ = 0;
  std::string error_;
};

// How a file's horizontal angles cover the C planes (LM-63-2002 §5.13; EULUMDAT Isym).
enum class Symmetry { Rotational, Quadrant, BilateralC0, BilateralC90, Full };

// The full set of C planes from the planes a file gives: each given plane mirrored as the symmetry
// says, reduced to [0, 360), sorted, and the duplicates (0 and 360, a mirror plane onto itself)
// dropped. Returns the columns' source indices beside their angles.
void expandSymmetry(Symmetry symmetry, const std::vector<double>& given, const std::vector<double>& columns, std::size_t nV,
                    Photometry& out) {
  std::vector<std::pair<double, std::size_t>> planes;
  auto add = [&](double c, std::size_t column) {
    c = std::fmod(c, 360.0);
    if (c < 0) c += 360;
    if (c > 360 - 1e-9) c = 0;
    planes.push_back({c, column});
  };
  for (std::size_t k = 0; k < given.size(); ++k) {
    const double c = given[k];
    switch (symmetry) {
      case Symmetry::Rotational: add(0, k); break;
      case Symmetry::Full: add(c, k); break;
      case Symmetry::BilateralC0: add(c, k), add(360 - c, k); break;       // mirror in the C0–C180 plane
      case Symmetry::BilateralC90: add(c, k), add(180 - c, k); break;      // mirror in the C90–C270 plane
      case Symmetry::Quadrant: add(c, k), add(180 - c, k), add(180 + c, k), add(360 - c, k); break;
    }
  }
  std::stable_sort(planes.begin(), planes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  out.horizontalDegrees.clear();
  out.candelaGrid.clear();
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (!out.horizontalDegrees.empty() && planes[i].first - out.horizontalDegrees.back() < 1e-9) continue;
    out.horizontalDegrees.push_back(planes[i].first);
    const std::size_t column = planes[i].second;
    out.candelaGrid.insert(out.candelaGrid.end(), columns.begin() + static_cast<std::ptrdiff_t>(column * nV),
                           columns.begin() + static_cast<std::ptrdiff_t>((column + 1) * nV));
  }
  if (symmetry == Symmetry::Rotational) {
    out.horizontalDegrees.assign(1, 0.0);
    out.candelaGrid.resize(nV);
  }
}

// Angles must rise; equal neighbours are a typing slip the reader cannot resolve.
std::string checkAscending(const std::vector<double>& angles, double lo, double hi, const std::string& what) {
  for (std::size_t i = 0; i < angles.size(); ++i) {
    if (angles[i] < lo - 1e-9 || angles[i] > hi + 1e-9)
      return what + " " + std::to_string(angles[i]) + "° lies outside " + std::to_string(static_cast<int>(lo)) + "–" +
             std::to_string(static_cast<int>(hi)) + "°";
    if (i > 0 && !(angles[i] > angles[i - 1]))
      return what + "s must rise, but " + std::to_string(angles[i]) + "° follows " + std::to_string(angles[i - 1]) + "°";
  }
  return {};
}

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

double TiltTable::factor(double tiltDegrees) const {
  if (degrees.empty()) return 1;
  if (tiltDegrees <= degrees.front()) return factors.front();
  if (tiltDegrees >= degrees.back()) return factors.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(degrees.begin(), degrees.end(), tiltDegrees) - degrees.begin());
  const double t = (tiltDegrees - degrees[k - 1]) / (degrees[k] - degrees[k - 1]);
  return factors[k - 1] + t * (factors[k] - factors[k - 1]);
}

double Photometry::rowValue(std::size_t row, double c) const {
  const std::size_t nV = verticalDegrees.size(), nC = horizontalDegrees.size();
  if (nC == 1) return candelaGrid[row];
  c = std::fmod(c, 360.0);
  if (c < 0) c += 360;
  const auto n = static_cast<long>(nC);
  // Plane k of the periodic sequence: horizontalDegrees[k mod n] + 360·floor(k / n).
  auto wrap = [&](long k) { return static_cast<std::size_t>(((k % n) + n) % n); };
  auto angle = [&](long k) { return horizontalDegrees[wrap(k)] + 360.0 * static_cast<double>(k >= 0 ? k / n : -((-k + n - 1) / n)); };
  auto value = [&](long k) { return candelaGrid[wrap(k) * nV + row]; };
  long j = static_cast<long>(std::upper_bound(horizontalDegrees.begin(), horizontalDegrees.end(), c) - horizontalDegrees.begin()) - 1;
  return std::fmax(0.0, monotoneCubic(c, true, angle(j - 1), value(j - 1), angle(j), value(j), angle(j + 1), value(j + 1), true,
                                      angle(j + 2), value(j + 2)));
}

double Photometry::candela(double cDegrees, double gammaDegrees) const {
  const std::size_t nV = verticalDegrees.size();
  if (nV < 2 || horizontalDegrees.empty() || !std::isfinite(cDegrees) || !std::isfinite(gammaDegrees)) return 0;
  const std::vector<double>& v = verticalDegrees;
  if (gammaDegrees < v.front() - 1e-9 || gammaDegrees > v.back() + 1e-9) return 0;
  std::size_t k = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), gammaDegrees) - v.begin());
  k = std::min(std::max<std::size_t>(k, 1), nV - 1) - 1;
  // Beyond a pole the neighbour lies in the opposite half plane, C + 180°: I(C, −γ) = I(C + 180°, γ).
  bool hasLeft = true, hasRight = true;
  double x0 = 0, y0 = 0, x3 = 0, y3 = 0;
  if (k >= 1) {
    x0 = v[k - 1], y0 = rowValue(k - 1, cDegrees);
  } else if (v[0] == 0) {
    x0 = -v[1], y0 = rowValue(1, cDegrees + 180);
  } else {
    hasLeft = false;
  }
  if (k + 2 < nV) {
    x3 = v[k + 2], y3 = rowValue(k + 2, cDegrees);
  } else if (v[nV - 1] == 180) {
    x3 = 360 - v[nV - 2], y3 = rowValue(nV - 2, cDegrees + 180);
  } else {
    hasRight = false;
  }
  const double value = monotoneCubic(gammaDegrees, hasLeft, x0, y0, v[k], rowValue(k, cDegrees), v[k + 1], rowValue(k + 1, cDegrees),
                                     hasRight, x3, y3);
  return std::fmax(0.0, value);
}

double Photometry::maxCandela() const {
  double m = 0;
  for (double c : candelaGrid) m = std::fmax(m, c);
  return m;
}

void Photometry::integrateFlux() {
  // Φ = ∫₀^{2π} ∫₀^{π} I(C, γ) sin γ dγ dC. Each 0.5° band of γ is weighted by its exact
  // ∫ sin γ dγ = cos γa − cos γb, so the only error is the interpolant's variation in the cell.
  constexpr int kBands = 360, kPlanes = 180;
  const bool rotational = horizontalDegrees.size() == 1;
  double sum = 0;
  for (int b = 0; b < kBands; ++b) {
    const double ga = 180.0 * b / kBands, gb = 180.0 * (b + 1) / kBands, gm = 0.5 * (ga + gb);
    if (verticalDegrees.empty() || gm < verticalDegrees.front() || gm > verticalDegrees.back()) continue;
    const double weight = std::cos(ga * kPi / 180) - std::cos(gb * kPi / 180);
    if (rotational) {
      sum += candela(0, gm) * weight * 2 * kPi;
      continue;
    }
    for (int p = 0; p < kPlanes; ++p) sum += candela(360.0 * (p + 0.5) / kPlanes, gm) * weight * (2 * kPi / kPlanes);
  }
  flux_ = sum;
}

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

Result<Photometry> readPhotometry(const std::string& path) {
  return lowercaseExtension(path) == ".ldt" ? readEulumdat(path) : readIes(path);
}

}  // namespace lambert
