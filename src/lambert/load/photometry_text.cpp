#include "lambert/load/photometry_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace lambert::photometry_text {

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

bool parseNumber(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

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

}  // namespace lambert::photometry_text
