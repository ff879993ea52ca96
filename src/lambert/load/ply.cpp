#include "lambert/load/ply.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"

namespace lambert {
namespace {

enum class Format { Ascii, LittleEndian, BigEndian };

// Sizes of PLY's scalar types, by both of their names.
int typeSize(const std::string& type) {
  static const std::map<std::string, int> sizes = {
      {"char", 1},   {"int8", 1},   {"uchar", 1},  {"uint8", 1},  {"short", 2},  {"int16", 2},   {"ushort", 2},  {"uint16", 2},
      {"int", 4},    {"int32", 4},  {"uint", 4},   {"uint32", 4}, {"float", 4},  {"float32", 4}, {"double", 8}, {"float64", 8}};
  auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

struct Property {
  std::string name, type;
  bool list = false;
  std::string countType;  // list only
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

class PlyReader {
 public:
  PlyReader(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}

  Result<Scene> read(double metresPerUnit, const RegionOptions& regions) {
    if (Status s = readHeader(); !s) return s.error();
    PolygonMesh mesh;
    mesh.name = std::filesystem::path(path_).stem().string();
    for (const Element& element : elements_) {
      for (std::size_t e = 0; e < element.count; ++e) {
        if (element.name == "vertex") {
          Vec3 p;
          for (const Property& property : element.properties) {
            Result<std::vector<double>> values = readProperty(property);
            if (!values) return values.error();
            if (!values->empty()) {
              const bool coordinate = property.name == "x" || property.name == "y" || property.name == "z";
              if (coordinate && !std::isfinite((*values)[0]))
                return error("vertex " + std::to_string(e) + ": " + property.name + " is not finite (NaN or infinite)");
              if (property.name == "x") p.x = (*values)[0];
              if (property.name == "y") p.y = (*values)[0];
              if (property.name == "z") p.z = (*values)[0];
            }
          }
          mesh.positions.push_back(p);
        } else {
          PolygonMesh::Face face;
          for (const Property& property : element.properties) {
            Result<std::vector<double>> values = readProperty(property);
            if (!values) return values.error();
            if (element.name == "face" && property.list && (property.name == "vertex_indices" || property.name == "vertex_index"))
              for (double v : *values) face.vertices.push_back(v >= 0 && v < 4294967295.0 ? static_cast<std::uint32_t>(v) : 0xFFFFFFFFu);
          }
          if (element.name == "face") mesh.faces.push_back(std::move(face));
        }
      }
    }
    if (mesh.faces.empty()) return Error{path_ + ": no faces (lambert needs an `element face` with vertex_indices)"};
    Scene scene;
    scene.name = mesh.name;
    scene.metresPerUnit = metresPerUnit;
    scene.materials.push_back({"default", Rgb::gray(0.5)});
    DroppedFaces dropped = addSmoothRegions(scene, mesh, {Rgb{}}, regions);
    if (dropped.total() > 0) warning(path_ + ": " + dropped.describe());
    if (scene.surfaces.empty()) return Error{path_ + ": every face is degenerate (" + dropped.describe() + ")"};
    scene.camera = cameraViewingScene(scene);
    return scene;
  }

 private:
  Error error(const std::string& what) const {
    if (format_ == Format::Ascii) return Error{path_ + ":" + std::to_string(line_) + ": " + what};
    return Error{path_ + ": byte " + std::to_string(offset_) + ": " + what};
  }

  Status readHeader() {
    std::size_t end = bytes_.find("end_header");
    if (bytes_.rfind("ply", 0) != 0 || end == std::string::npos) return Error{path_ + ": not a PLY file (no \"ply\" … \"end_header\")"};
    std::istringstream header(bytes_.substr(0, end));
    std::string text;
    int lineNumber = 0;
    while (std::getline(header, text)) {
      ++lineNumber;
      std::istringstream words(text);
      std::string keyword;
      words >> keyword;
      if (keyword == "format") {
        std::string format;
        words >> format;
        if (format == "ascii") format_ = Format::Ascii;
        else if (format == "binary_little_endian") format_ = Format::LittleEndian;
        else if (format == "binary_big_endian") format_ = Format::BigEndian;
        else return Error{path_ + ":" + std::to_string(lineNumber) + ": unknown format '" + format + "'"};
      } else if (keyword == "element") {
        Element element;
        long long count = -1;
        // A count past long long fails the stream (and leaves LLONG_MAX in count): an error too.
        if (!(words >> element.name >> count) || count < 0)
          return Error{path_ + ":" + std::to_string(lineNumber) + ": an element needs a count (a whole number below 2^63)"};
        element.count = static_cast<std::size_t>(count);
        elements_.push_back(element);
      } else if (keyword == "property") {
        if (elements_.empty()) return Error{path_ + ":" + std::to_string(lineNumber) + ": a property before any element"};
        Property property;
        words >> property.type;
        if (property.type == "list") {
          property.list = true;
          words >> property.countType >> property.type;
          if (!typeSize(property.countType)) return Error{path_ + ":" + std::to_string(lineNumber) + ": unknown type '" + property.countType + "'"};
          // A list's length is a count: a float type there (which the PLY format does not allow) could hold
          // lengths no integer can.
          if (property.countType == "float" || property.countType == "float32" || property.countType == "double" ||
              property.countType == "float64")
            return Error{path_ + ":" + std::to_string(lineNumber) + ": a list's count type must be an integer type, not '" +
                         property.countType + "'"};
        }
        words >> property.name;
        if (!typeSize(property.type)) return Error{path_ + ":" + std::to_string(lineNumber) + ": unknown type '" + property.type + "'"};
        elements_.back().properties.push_back(property);
      } else if (keyword != "comment" && keyword != "obj_info" && keyword != "ply" && !keyword.empty()) {
        return Error{path_ + ":" + std::to_string(lineNumber) + ": unknown header line '" + keyword + "'"};
      }
    }
    line_ = lineNumber + 2;  // the header's lines, then end_header's
    offset_ = bytes_.find('\n', end);
    offset_ = offset_ == std::string::npos ? bytes_.size() : offset_ + 1;
    // Each element needs at least a byte (binary: its fixed-size properties, a list's count) or
    // two characters (ascii: a number and a separator) per property: refuse counts the file
    // cannot hold before reading, let alone allocating, anything.
    for (const Element& element : elements_) {
      std::size_t perElement = 0;
      for (const Property& property : element.properties)
        perElement += format_ == Format::Ascii ? 2 : static_cast<std::size_t>(typeSize(property.list ? property.countType : property.type));
      // An element without properties takes no bytes, so no file size bounds its count: reading 2^62 of
      // them would hang (found by fuzz/ply_fuzz).
      if (perElement == 0 && element.count > 0)
        return Error{path_ + ": the header declares " + std::to_string(element.count) + " " + element.name +
                     " elements without any property"};
      if (perElement > 0 && element.count > (bytes_.size() - offset_) / perElement)
        return Error{path_ + ": the header declares " + std::to_string(element.count) + " " + element.name + " elements, more than the file's " +
                     std::to_string(bytes_.size() - offset_) + " bytes of data can hold"};
    }
    return Ok{};
  }

  // One property's value(s): a scalar, or a list's entries.
  Result<std::vector<double>> readProperty(const Property& property) {
    std::vector<double> values;
    if (!property.list) {
      Result<double> v = scalar(property.type);
      if (!v) return v.error();
      values.push_back(*v);
      return values;
    }
    Result<double> count = scalar(property.countType);
    if (!count) return count.error();
    const int entrySize = format_ == Format::Ascii ? 2 : typeSize(property.type);
    // Checked, and printed, as a double before any conversion to an integer: an ascii count may be any
    // number strtod reads, a binary one any value of its type (1e29 has no long long).
    auto number = [](double v) {
      std::ostringstream text;
      text << v;
      return text.str();
    };
    if (*count != std::floor(*count)) return error("a list's count " + number(*count) + " is not a whole number");
    if (!(*count >= 0) || *count > static_cast<double>((bytes_.size() - offset_) / static_cast<std::size_t>(entrySize) + 1))
      return error("a list of " + number(*count) + " entries does not fit in the file");
    for (long long k = 0; k < static_cast<long long>(*count); ++k) {
      Result<double> v = scalar(property.type);
      if (!v) return v.error();
      values.push_back(*v);
    }
    return values;
  }

  Result<double> scalar(const std::string& type) {
    if (format_ == Format::Ascii) {
      while (offset_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[offset_]))) {
        if (bytes_[offset_] == '\n') ++line_;
        ++offset_;
      }
      if (offset_ >= bytes_.size()) return Error{path_ + ": the file ends early, after line " + std::to_string(lastLine_) + " (truncated?)"};
      lastLine_ = line_;
      const char* start = bytes_.data() + offset_;
      char* stop = nullptr;
      const double v = std::strtod(start, &stop);
      if (stop == start) return error("expected a number");
      offset_ += static_cast<std::size_t>(stop - start);
      return v;
    }
    const int size = typeSize(type);
    if (offset_ + static_cast<std::size_t>(size) > bytes_.size()) return error("the file ends early (truncated?)");
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + offset_, static_cast<std::size_t>(size));
    offset_ += static_cast<std::size_t>(size);
    const bool swap = (format_ == Format::BigEndian) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(raw, raw + size);
    auto as = [&](auto value) {
      std::memcpy(&value, raw, sizeof value);
      return static_cast<double>(value);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
  }

  std::string path_;
  std::string bytes_;
  Format format_ = Format::Ascii;
  std::vector<Element> elements_;
  std::size_t offset_ = 0;
  int line_ = 1;      // ascii: the line being read
  int lastLine_ = 1;  // ascii: the line of the last number read
};

}  // namespace

Result<Scene> readPly(const std::string& path, double metresPerUnit, const RegionOptions& regions) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such PLY file"};
  Result<std::string> bytes = readWholeFile(path);
  if (!bytes) return bytes.error();
  return PlyReader(path, *bytes).read(metresPerUnit, regions);
}

}  // namespace lambert
