#include "lambert/io/vertices.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "lambert/core/atomic_file.h"
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

// Nine significant digits round-trip a float and are plenty for radiance. to_chars with a
// precision writes what printf's %.9g does, without its locale and format parsing: a 10⁶-vertex
// file took seconds through snprintf.
constexpr std::size_t kMaxRow = 9 * 32 + 3 * 4 + 2;  // nine numbers and separators, three bytes, a newline

char* appendNumber(char* at, double value) {
  return std::to_chars(at, at + 32, value, std::chars_format::general, 9).ptr;
}

char* appendRow(char* at, const VertexSample& v, char separator) {
  const double values[9] = {v.position.x, v.position.y, v.position.z, v.normal.x, v.normal.y,
                            v.normal.z,   v.radiance.r, v.radiance.g, v.radiance.b};
  for (int k = 0; k < 9; ++k) {
    if (k > 0) *at++ = separator;
    at = appendNumber(at, values[k]);
  }
  return at;
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
  const bool ply = endsWith(path, ".ply");
  if (!ply && !endsWith(path, ".csv")) return Error{path + ": unknown vertex file type (use .csv or .ply)"};
  std::string text;
  if (ply) {
    text = "ply\nformat ascii 1.0\ncomment lambert vertices: radiance_* is outgoing radiance L in W/(m^2 sr)\n";
    text += "element vertex " + std::to_string(vertices.size()) + "\n";
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "radiance_r", "radiance_g", "radiance_b"})
      text += std::string("property float ") + name + "\n";
    text += "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  } else {
    text = std::string(kCsvHeader) + "\n";
  }
  // Rows are formatted in blocks in parallel and written one after another.
  constexpr std::size_t kBlock = 4096;
  std::vector<std::string> blocks((vertices.size() + kBlock - 1) / kBlock);
  parallelFor(0, blocks.size(), [&](std::size_t b) {
    const std::size_t begin = b * kBlock, end = std::min(vertices.size(), begin + kBlock);
    std::vector<char> rows((end - begin) * kMaxRow);
    char* at = rows.data();
    for (std::size_t i = begin; i < end; ++i) {
      const VertexSample& v = vertices[i];
      at = appendRow(at, v, ply ? ' ' : ',');
      if (ply)
        for (double channel : {v.radiance.r, v.radiance.g, v.radiance.b}) {
          *at++ = ' ';
          at = std::to_chars(at, at + 4, toSrgbByte(channel)).ptr;
        }
      *at++ = '\n';
    }
    blocks[b].assign(rows.data(), at);
  });
  const auto bytesOf = [](const std::string& s) { return std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()); };
  std::vector<std::span<const std::uint8_t>> parts{bytesOf(text)};
  for (const std::string& block : blocks) parts.push_back(bytesOf(block));
  return writeFileAtomically(path, parts);
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
