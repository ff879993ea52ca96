#include "lambert/io/vertices.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "lambert/core/atomic_file.h"
#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/srgb.h"

namespace lambert {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::uint8_t toSrgbByte(double linear) {
  return static_cast<std::uint8_t>(std::lround(255 * srgbEncode(std::fmin(std::fmax(linear, 0.0), 1.0))));
}

// Nine significant digits round-trip a float and are plenty for radiance. std::to_chars with a
// precision writes what printf's %.9g writes (C++20 [charconv.to.chars]: "as if by printf in the
// C locale"), several times faster than snprintf: a 10^5-face building writes 1.4 × 10^5 rows.
// A subnormal is written by snprintf: threads that ran Embree's builder keep its
// denormals-are-zero mode, in which to_chars' tests of the value take a subnormal for 0 (and so
// would std::fpclassify: its bits decide here).
char* appendNumber(char* at, char* end, double value) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(value);
  if ((bits & 0x7ff0000000000000ull) == 0 && (bits & 0x000fffffffffffffull) != 0) {
    const int written = std::snprintf(at, static_cast<std::size_t>(end - at), "%.9g", value);
    LAMBERT_CHECK(written > 0 && written < end - at);
    return at + written;
  }
  const std::to_chars_result r = std::to_chars(at, end, value, std::chars_format::general, 9);
  LAMBERT_CHECK(r.ec == std::errc());
  return r.ptr;
}

// Appends one row (nine values, no line end) to out.
void appendRow(std::string& out, const VertexSample& v, char separator) {
  char line[320];
  char* at = line;
  char* const end = line + sizeof line;
  const double values[9] = {v.position.x, v.position.y, v.position.z, v.normal.x,   v.normal.y,
                            v.normal.z,   v.radiance.r, v.radiance.g, v.radiance.b};
  for (int k = 0; k < 9; ++k) {
    if (k > 0) *at++ = separator;
    at = appendNumber(at, end, values[k]);
  }
  out.append(line, static_cast<std::size_t>(at - line));
}

// Rows 0 to count − 1, each appended by row(text, i), formatted in parallel blocks and joined
// in order.
template <class Row>
std::string formatRows(std::size_t count, Row&& row) {
  constexpr std::size_t kRowsPerBlock = 4096;
  std::vector<std::string> blocks((count + kRowsPerBlock - 1) / kRowsPerBlock);
  parallelFor(0, blocks.size(), [&](std::size_t b) {
    std::string& text = blocks[b];
    text.reserve(kRowsPerBlock * 120);
    for (std::size_t i = b * kRowsPerBlock; i < std::min(count, (b + 1) * kRowsPerBlock); ++i) row(text, i);
  });
  std::size_t bytes = 0;
  for (const std::string& text : blocks) bytes += text.size();
  std::string out;
  out.reserve(bytes);
  for (const std::string& text : blocks) out += text;
  return out;
}

bool parseRow(const std::string& line, char separator, double (&values)[9]) {
  const char* p = line.data();
  const char* end = line.data() + line.size();
  for (int k = 0; k < 9; ++k) {
    while (p < end && *p == ' ') ++p;
    auto [next, ec] = std::from_chars(p, end, values[k]);
    if (ec != std::errc() || !std::isfinite(values[k])) return false;
    p = next;
    while (p < end && *p == ' ' && separator != ' ') ++p;
    if (k < 8) {
      if (p >= end || *p != separator) return false;
      ++p;
    }
  }
  while (p < end && (*p == ' ' || *p == '\r')) ++p;
  return p == end || separator == ' ';  // PLY rows carry colour bytes after the nine values
}

constexpr const char* kCsvHeader = "x,y,z,nx,ny,nz,r,g,b";

}  // namespace

std::vector<VertexSample> vertexSamples(const SolutionView& solution) {
  return vertexSamples(solution.vertexMesh(), solution.vertexRadiance());
}

std::vector<VertexSample> vertexSamples(const Mesh& mesh, const std::vector<Rgb>& vertexRadiance) {
  LAMBERT_CHECK(vertexRadiance.size() == mesh.numVertices());
  std::vector<VertexSample> samples(mesh.numVertices());
  std::vector<Vec3> normal(mesh.numVertices());
  for (const Patch& patch : mesh.patches)
    for (std::uint32_t k = 0; k < patch.numCorners; ++k) normal[patch.vertices[k]] += patch.normal * patch.area;
  for (std::size_t v = 0; v < samples.size(); ++v) {
    samples[v].position = mesh.positions[v];
    samples[v].normal = lengthSquared(normal[v]) > 0 ? normalize(normal[v]) : Vec3{};
    samples[v].radiance = vertexRadiance[v];
  }
  return samples;
}

Status writeVertices(const std::string& path, const std::vector<VertexSample>& vertices) {
  std::string text;
  if (endsWith(path, ".csv")) {
    text = std::string(kCsvHeader) + "\n";
    text += formatRows(vertices.size(), [&](std::string& out, std::size_t i) {
      appendRow(out, vertices[i], ',');
      out += '\n';
    });
  } else if (endsWith(path, ".ply")) {
    text = "ply\nformat ascii 1.0\ncomment lambert vertices: radiance_* is outgoing radiance L in W/(m^2 sr)\n";
    text += "element vertex " + std::to_string(vertices.size()) + "\n";
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "radiance_r", "radiance_g", "radiance_b"})
      text += std::string("property float ") + name + "\n";
    text += "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    text += formatRows(vertices.size(), [&](std::string& out, std::size_t i) {
      const VertexSample& v = vertices[i];
      appendRow(out, v, ' ');
      for (double channel : {v.radiance.r, v.radiance.g, v.radiance.b}) out.append(" ").append(std::to_string(toSrgbByte(channel)));
      out += '\n';
    });
  } else {
    return Error{path + ": unknown vertex file type (use .csv or .ply)"};
  }
  return writeFileAtomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

Result<std::vector<VertexSample>> readVertices(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  const bool ply = endsWith(path, ".ply");
  if (!ply && !endsWith(path, ".csv")) return Error{path + ": unknown vertex file type (use .csv or .ply)"};
  std::string line;
  int lineNumber = 0;
  std::size_t expected = 0;
  bool counted = false;
  if (ply) {
    while (std::getline(in, line)) {
      ++lineNumber;
      if (lineNumber == 1 && line != "ply") return Error{path + ":1: not a PLY file"};
      if (line.rfind("element vertex ", 0) == 0) {
        // from_chars, not stoull: a count that is not a number is the file's error, not a crash.
        const char* begin = line.data() + 15;
        const char* end = line.data() + line.size();
        while (end > begin && (end[-1] == ' ' || end[-1] == '\r')) --end;
        const auto [stop, ec] = std::from_chars(begin, end, expected);
        if (ec != std::errc() || stop != end || begin == end)
          return Error{path + ":" + std::to_string(lineNumber) + ": the vertex count '" + line.substr(15) + "' is not a whole number"};
        counted = true;
      }
      if (line == "end_header") break;
    }
    if (!counted) return Error{path + ": PLY header has no vertex count"};
  } else {
    ++lineNumber;
    if (!std::getline(in, line) || line.rfind(kCsvHeader, 0) != 0)
      return Error{path + ":1: expected the header '" + std::string(kCsvHeader) + "'"};
  }
  std::vector<VertexSample> vertices;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty() || line == "\r") continue;
    double v[9];
    if (!parseRow(line, ply ? ' ' : ',', v))
      return Error{path + ":" + std::to_string(lineNumber) + ": expected nine finite numbers (position, normal, radiance)"};
    vertices.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}});
  }
  if (vertices.empty()) return Error{path + ": no vertices (the file holds a header only)"};
  if (ply && vertices.size() != expected)
    return Error{path + ": header promises " + std::to_string(expected) + " vertices, file has " + std::to_string(vertices.size())};
  return vertices;
}

}  // namespace lambert
