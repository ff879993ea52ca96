#include "lambert/design/points_file.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "lambert/core/atomic_file.h"
#include "lambert/core/photometric.h"
#include "lambert/core/text.h"
#include "lambert/core/warning.h"

namespace lambert {
namespace {

std::string trimmed(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  std::string out(s.substr(a, b - a));
  if (out.size() >= 2 && out.front() == '"' && out.back() == '"') out = out.substr(1, out.size() - 2);
  return out;
}

// A row's fields: split at commas, semicolons or tabs where the line has any, else at runs of spaces.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  const bool delimited = line.find_first_of(",;\t") != std::string::npos;
  if (delimited) {
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',' || line[i] == ';' || line[i] == '\t') {
        out.push_back(trimmed(std::string_view(line).substr(start, i - start)));
        start = i + 1;
      }
  } else {
    std::istringstream in(line);
    for (std::string field; in >> field;) out.push_back(field);
  }
  return out;
}

bool number(const std::string& text, double& value) {
  const char* end = text.data() + text.size();
  const char* start = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
  auto [ptr, ec] = std::from_chars(start, end, value);
  return ec == std::errc() && ptr == end && std::isfinite(value);
}

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

Result<PointsTable> readPointsCsv(const std::string& path, const FileFrame& frame) {
  Result<std::string> text = readWholeFile(path);
  if (!text) return text.error();
  PointsTable table;
  std::array<int, 6> column{0, 1, 2, 3, 4, 5};  // x, y, z, nx, ny, nz
  bool normals = true, first = true;
  std::istringstream in(*text);
  int lineNumber = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineNumber == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);  // a UTF-8 byte-order mark
    const std::string content = trimmed(line);
    if (content.empty() || content[0] == '#') continue;
    const std::vector<std::string> f = fields(line);
    const std::string where = path + ":" + std::to_string(lineNumber);
    if (first) {
      first = false;
      double ignored;
      // A header names columns: most of its fields are not numbers (a data row with a damaged
      // field is a data row, refused below with the field).
      const auto words = std::count_if(f.begin(), f.end(), [&](const std::string& s) { return !number(s, ignored); });
      const bool header = 2 * words >= static_cast<std::ptrdiff_t>(f.size());
      if (header) {
        table.header = f;
        const std::array<const char*, 6> names{"x", "y", "z", "nx", "ny", "nz"};
        for (int k = 0; k < 6; ++k) {
          column[k] = -1;
          for (std::size_t c = 0; c < f.size(); ++c)
            if (lowercase(f[c]) == names[k]) column[k] = static_cast<int>(c);
        }
        for (int k = 0; k < 3; ++k)
          if (column[k] < 0)
            return Error{where + ": the header names no column \"" + names[k] +
                         "\" (a points file has columns x, y, z, nx, ny, nz; its first row names them or is the first point)"};
        normals = column[3] >= 0 && column[4] >= 0 && column[5] >= 0;
        if (!normals) {
          if (column[3] >= 0 || column[4] >= 0 || column[5] >= 0)
            return Error{where + ": the header names some of nx, ny, nz but not all three"};
          warning(where + ": no nx, ny, nz columns; every point faces the file's up direction");
        }
        continue;
      }
      table.header = {"x", "y", "z", "nx", "ny", "nz"};
      for (std::size_t c = 6; c < f.size(); ++c) table.header.push_back("column " + std::to_string(c + 1));
    }
    const int needed = 1 + *std::max_element(column.begin(), column.begin() + (normals ? 6 : 3));
    if (static_cast<int>(f.size()) < needed)
      return Error{where + ": " + std::to_string(f.size()) + " fields, " + std::to_string(needed) + " needed (x, y, z, nx, ny, nz)"};
    std::array<double, 6> v{0, 0, 0, frame.up.x, frame.up.y, frame.up.z};
    for (int k = 0; k < (normals ? 6 : 3); ++k)
      if (!number(f[column[k]], v[k]))
        return Error{where + ": field " + std::to_string(column[k] + 1) + " (\"" + f[column[k]] + "\") is not a finite number"};
    const Vec3 n = frame.sceneDirection({v[3], v[4], v[5]});
    if (!(length(n) > 0)) return Error{where + ": the normal (nx, ny, nz) is zero; give the direction the point faces"};
    table.points.push_back({frame.scenePoint({v[0], v[1], v[2]}), normalize(n)});
    table.rows.push_back(f);
  }
  if (table.points.empty()) return Error{path + ": no points (one per row: x, y, z, nx, ny, nz)"};
  return table;
}

Status writePointsCsvColumns(const std::string& path, const PointsTable& table, std::span<const std::string> columns,
                             std::span<const double> values) {
  if (values.size() != table.rows.size() * columns.size()) return Error{"writePointsCsvColumns: one value per row and column needed"};
  std::string out;
  const std::size_t given = table.header.size();
  // Appended piece by piece (GCC 12 warns, wrongly, of overlap in csvField(...) + ",").
  for (std::size_t c = 0; c < given; ++c) out.append(csvField(table.header[c])).push_back(',');
  for (std::size_t c = 0; c < columns.size(); ++c) out.append(csvField(columns[c])).push_back(c + 1 < columns.size() ? ',' : '\n');
  char number[64];
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    for (std::size_t c = 0; c < given; ++c) out.append(c < table.rows[i].size() ? csvField(table.rows[i][c]) : std::string()).push_back(',');
    for (std::size_t c = 0; c < columns.size(); ++c) {
      std::snprintf(number, sizeof number, c + 1 < columns.size() ? "%.6g," : "%.6g", values[i * columns.size() + c]);
      out += number;
    }
    out += "\n";
  }
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(out.data()), out.size()));
}

Status writePointsCsv(const std::string& path, const PointsTable& table, std::span<const PointIrradiance> irradiance,
                      std::span<const double> daylightFactorPercent) {
  if (irradiance.size() != table.rows.size()) return Error{"writePointsCsv: one irradiance per row needed"};
  const bool daylight = !daylightFactorPercent.empty();
  std::vector<std::string> columns{"E_direct", "E_sky", "E_sun", "E_indirect", "E"};
  if (daylight) columns.push_back("DF");
  std::vector<double> values;
  values.reserve(table.rows.size() * columns.size());
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const PointIrradiance& e = irradiance[i];
    values.insert(values.end(), {illuminanceLux(e.direct), illuminanceLux(e.sky), illuminanceLux(e.sun), illuminanceLux(e.indirect), illuminanceLux(e.total())});
    if (daylight) values.push_back(daylightFactorPercent[i]);
  }
  return writePointsCsvColumns(path, table, columns, values);
}

}  // namespace lambert
