#include "lambert/load/obj.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <span>
#include <sstream>
#include <string_view>

#include "lambert/core/atomic_file.h"
#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/scene/texture.h"

namespace lambert {
namespace {

// tinyobjloader reads a coordinate it cannot parse ("nan", "abc", one left out) as 0 and says
// nothing, so a broken vertex would become a wrong one. Each v and vt line is checked here first:
// its numbers must be finite, and a v needs x, y and z.
Status checkCoordinates(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Words are separated as istream's >> separates them in the C locale.
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; };
  const char* p = text.data();
  const char* const fileEnd = text.data() + text.size();
  for (int number = 1; p < fileEnd; ++number) {
    const char* lineEnd = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(fileEnd - p)));
    if (!lineEnd) lineEnd = fileEnd;
    const auto nextWord = [&](const char*& at) {
      while (at < lineEnd && space(*at)) ++at;
      const char* begin = at;
      while (at < lineEnd && !space(*at)) ++at;
      return std::string_view(begin, static_cast<std::size_t>(at - begin));
    };
    const char* at = p;
    p = lineEnd + (lineEnd < fileEnd ? 1 : 0);
    const std::string_view keyword = nextWord(at);
    if (keyword != "v" && keyword != "vt") continue;
    int count = 0;
    for (std::string_view word = nextWord(at); !word.empty(); word = nextWord(at)) {
      ++count;
      double value = 0;
      const char* begin = word.data() + (word[0] == '+' ? 1 : 0);
      const char* end = word.data() + word.size();
      const auto [stop, ec] = std::from_chars(begin, end, value);
      if (ec == std::errc() && stop == end && std::isfinite(value)) continue;
      const std::string where = path + ":" + std::to_string(number) + ": " + std::string(keyword) + ": ";
      if (ec == std::errc() && stop == end) return Error{where + "'" + std::string(word) + "' is not a finite number"};
      if (ec == std::errc::result_out_of_range) return Error{where + "'" + std::string(word) + "' is not a finite number (out of range)"};
      return Error{where + "expected a number, found '" + std::string(word) + "'"};
    }
    if (keyword == "v" && count < 3) return Error{path + ":" + std::to_string(number) + ": v needs three coordinates x y z, found " + std::to_string(count)};
  }
  return Ok{};
}

// The folder an OBJ's material libraries are read from. OBJ says nothing of what `mtllib` paths
// are relative to; Blender and tinyobjloader take the OBJ's folder. Files written by programs that
// ran from a project's root name their libraries from there (`mtllib scenes/box.mtl` inside
// scenes/), so where the first library is not beside the OBJ, the same path is tried from each
// folder above it; the folder that holds it is used, with a warning naming the line. With none
// found, the OBJ's folder (tinyobjloader then warns that the library is missing).
std::filesystem::path materialFolder(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path objFolder = fs::path(path).parent_path();
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string keyword, library;
    words >> keyword >> library;
    if (keyword != "mtllib" || library.empty()) continue;
    std::error_code ec;
    if (fs::is_regular_file(objFolder / library, ec)) return objFolder;
    const std::string where = path + ":" + std::to_string(number) + ": mtllib '" + library + "' is not beside the OBJ; ";
    for (fs::path folder = fs::absolute(objFolder, ec).parent_path(); !folder.empty(); folder = folder.parent_path()) {
      if (fs::is_regular_file(folder / library, ec)) {
        warning(where + "read " + (folder / library).string() + " (a path from a folder above it, as the program that wrote it ran)");
        return folder;
      }
      if (folder == folder.parent_path()) break;
    }
    return objFolder;
  }
  return objFolder;
}

// Where each material's Kd is written (MTL path:line), for warnings that name the place the
// value came from: OBJs that share one MTL then report its problems alike (and a scene file that
// loads several reports each once). Materials not found in a library keep the OBJ's path.
std::map<std::string, std::string> kdPlaces(const std::string& objPath, const std::filesystem::path& folder) {
  std::map<std::string, std::string> places;
  std::ifstream obj(objPath, std::ios::binary);
  std::string line;
  while (std::getline(obj, line)) {
    std::istringstream words(line);
    std::string keyword, library;
    words >> keyword;
    if (keyword != "mtllib") continue;
    while (words >> library) {
      const std::string mtl = (folder / library).string();
      std::ifstream in(mtl, std::ios::binary);
      std::string material, text;
      for (int number = 1; std::getline(in, text); ++number) {
        std::istringstream mtlWords(text);
        std::string key;
        mtlWords >> key;
        if (key == "newmtl") {
          std::getline(mtlWords >> std::ws, material);
          while (!material.empty() && (material.back() == '\r' || material.back() == ' ')) material.pop_back();
          places.try_emplace(material, mtl + ":" + std::to_string(number));
        } else if (key == "Kd" && !material.empty()) {
          places[material] = mtl + ":" + std::to_string(number);
        }
      }
    }
  }
  return places;
}

}  // namespace

Result<Scene> readObj(const std::string& path, const ObjOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such OBJ file"};
  if (Status s = checkCoordinates(path); !s) return s.error();
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // lambert triangulates (ear clipping) only what is not convex
  config.vertex_color = false;
  config.mtl_search_path = materialFolder(path).string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) return Error{path + ": " + singleLine(reader.Error())};
  if (!reader.Warning().empty()) warning(path + ": " + singleLine(reader.Warning()));

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.metresPerUnit = options.metresPerUnit;
  std::vector<Rgb> emission;
  const std::map<std::string, std::string> kdPlace = kdPlaces(path, config.mtl_search_path);
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    Rgb albedo{m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    Rgb emitted{m.emission[0], m.emission[1], m.emission[2]};
    for (int c = 0; c < 3; ++c) {
      if (!(albedo[c] >= 0)) return Error{path + ": material '" + m.name + "': Kd must not be negative; give each channel between 0 and 1 in its MTL"};
      if (!(emitted[c] >= 0)) return Error{path + ": material '" + m.name + "': Ke must not be negative; give each channel 0 or more in its MTL"};
    }
    Material material{m.name, albedo};
    if (!m.diffuse_texname.empty()) {
      Result<std::shared_ptr<const Texture>> texture = readTexture((std::filesystem::path(config.mtl_search_path) / m.diffuse_texname).string());
      // As a missing MTL is, and as Blender's importer does: the material without its texture.
      if (texture)
        material.texture = *texture;
      else
        warning(path + ": material '" + m.name + "': map_Kd: " + texture.error().message + "; the material is drawn with its Kd alone");
    }
    // map_Ke multiplies Ke (sRGB decoded, as Blender's OBJ exporter and importer take it); under a
    // black Ke it changes nothing and is not read.
    if (!m.emissive_texname.empty() && emitted.maxComponent() > 0) {
      Result<std::shared_ptr<const Texture>> texture = readTexture((std::filesystem::path(config.mtl_search_path) / m.emissive_texname).string());
      if (texture)
        material.emissionTexture = *texture;
      else
        warning(path + ": material '" + m.name + "': map_Ke: " + texture.error().message + "; the material emits its Ke alone");
    }
    const auto place = kdPlace.find(m.name);
    const std::string where = (place != kdPlace.end() ? place->second : path) + ": material '" + m.name + "': Kd";
    material.albedo = material.texture ? boundedAlbedo(albedo, *material.texture, where) : boundedAlbedo(albedo, where);
    scene.materials.push_back(std::move(material));
    emission.push_back(emitted);
  }
  // Faces without a material (or naming one the MTL lacks) get a default grey, kept if used.
  const int defaultMaterial = static_cast<int>(scene.materials.size());
  scene.materials.push_back({"default", Rgb::gray(0.5)});
  emission.push_back({});
  bool usesDefault = false;

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  PolygonMesh mesh;
  // Each object gets only the vertices its faces use (OBJ numbers them file-wide), so that a
  // file of many objects costs each object its own size, not the whole file's.
  const std::size_t fileVertices = attrib.vertices.size() / 3;
  constexpr std::uint32_t kUnused = UINT32_MAX;
  std::vector<std::uint32_t> localOf(fileVertices, kUnused), used;
  auto localVertex = [&](int global) -> std::uint32_t {
    if (global < 0 || static_cast<std::size_t>(global) >= fileVertices) return kUnused;  // dropped as out of range
    std::uint32_t& local = localOf[static_cast<std::size_t>(global)];
    if (local == kUnused) {
      local = static_cast<std::uint32_t>(mesh.positions.size());
      used.push_back(static_cast<std::uint32_t>(global));
      const std::size_t g = static_cast<std::size_t>(global);
      mesh.positions.push_back({attrib.vertices[3 * g], attrib.vertices[3 * g + 1], attrib.vertices[3 * g + 2]});
    }
    return local;
  };
  DroppedFaces dropped;
  std::size_t numFaces = 0, facesWithoutVt = 0;
  const auto& shapes = reader.GetShapes();
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const tinyobj::mesh_t& m = shapes[s].mesh;
    mesh.name = shapes[s].name.empty() ? "object " + std::to_string(s + 1) : shapes[s].name;
    mesh.faces.clear();
    mesh.positions.clear();
    for (std::uint32_t global : used) localOf[global] = kUnused;
    used.clear();
    std::size_t index = 0;
    for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      PolygonMesh::Face face;
      const int material = f < m.material_ids.size() ? m.material_ids[f] : -1;
      face.material = material >= 0 && material < defaultMaterial ? material : defaultMaterial;
      const Material& faceMaterial = scene.materials[static_cast<std::size_t>(face.material)];
      const bool textured = faceMaterial.texture || faceMaterial.emissionTexture;
      bool missingVt = false;
      for (unsigned k = 0; k < m.num_face_vertices[f]; ++k, ++index) {
        face.vertices.push_back(localVertex(m.indices[index].vertex_index));
        if (!textured) continue;
        // OBJ's v runs up from the image's bottom row; lambert's (glTF's) down from its top row.
        const int vt = m.indices[index].texcoord_index;
        missingVt |= vt < 0 || static_cast<std::size_t>(2 * vt + 1) >= attrib.texcoords.size();
        face.uvs.push_back(missingVt ? Uv{} : Uv{attrib.texcoords[2 * vt], 1 - attrib.texcoords[2 * vt + 1]});
      }
      if (missingVt) {
        ++facesWithoutVt;
        face.uvs.assign(face.vertices.size(), Uv{});
      }
      usesDefault |= face.material == defaultMaterial;
      mesh.faces.push_back(std::move(face));
    }
    numFaces += mesh.faces.size();
    dropped.add(addSmoothRegions(scene, mesh, emission, options.regions));
  }
  if (!usesDefault) scene.materials.pop_back();
  if (numFaces == 0) return Error{path + ": no faces (lambert needs polygons: f lines)"};
  if (dropped.total() > 0) warning(path + ": " + dropped.describe());
  if (facesWithoutVt > 0)
    warning(path + ": " + std::to_string(facesWithoutVt) + " textured face" + (facesWithoutVt == 1 ? " has" : "s have") +
            " no vt texture coordinates; they take the texture's corner texel");
  if (scene.surfaces.empty()) return Error{path + ": every face is degenerate (" + dropped.describe() + ")"};
  scene.camera = cameraViewingScene(scene);
  return scene;
}

Status writeObj(const std::string& path, const Scene& scene) {
  const std::filesystem::path objPath(path);
  const std::filesystem::path mtlPath = std::filesystem::path(path).replace_extension(".mtl");
  // One material per (material, emission) pair, as the MTL carries the emission.
  std::vector<std::pair<int, Rgb>> kinds;
  std::vector<std::size_t> kindOf;
  for (const Surface& s : scene.surfaces) {
    const std::pair<int, Rgb> kind{s.material, s.emittedRadiance};
    auto it = std::find(kinds.begin(), kinds.end(), kind);
    kindOf.push_back(static_cast<std::size_t>(it - kinds.begin()));
    if (it == kinds.end()) kinds.push_back(kind);
  }
  auto token = [](std::string name) {  // OBJ names are one token
    for (char& c : name)
      if (c == ' ' || c == '\t') c = '_';
    return name.empty() ? std::string("unnamed") : name;
  };
  std::string mtl = "# written by lambert\n";
  char line[160];
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    const Material& m = scene.materials[static_cast<std::size_t>(kinds[k].first)];
    LAMBERT_CHECK(!m.texture && !m.emissionTexture);  // a texture file is not written
    std::snprintf(line, sizeof line, "newmtl %s_%zu\nKd %.17g %.17g %.17g\n", token(m.name).c_str(), k, m.albedo.r, m.albedo.g, m.albedo.b);
    mtl += line;
    if (kinds[k].second.maxComponent() > 0) {
      std::snprintf(line, sizeof line, "Ke %.17g %.17g %.17g\n", kinds[k].second.r, kinds[k].second.g, kinds[k].second.b);
      mtl += line;
    }
  }
  std::string obj = "# written by lambert: " + scene.name + ", metres per unit " + std::to_string(scene.metresPerUnit) + "\nmtllib " +
                    mtlPath.filename().string() + "\n";
  std::size_t base = 1;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    if (surface.twin >= 0 && static_cast<std::size_t>(surface.twin) < s) continue;  // the loader makes twins again
    obj += "o " + token(surface.name) + "\nusemtl " + token(scene.materials[static_cast<std::size_t>(surface.material)].name) + "_" +
           std::to_string(kindOf[s]) + "\n";
    for (const Vec3& v : surface.vertices) {
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v.x, v.y, v.z);
      obj += line;
    }
    for (const auto& face : surfaceFaces(surface)) {
      obj += "f";
      for (std::uint32_t i : face) {
        obj += ' ';
        obj += std::to_string(base + i);
      }
      obj += "\n";
    }
    base += surface.vertices.size();
  }
  auto bytes = [](const std::string& text) {
    return std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  };
  if (Status written = writeFileAtomically(mtlPath.string(), bytes(mtl)); !written) return written;
  return writeFileAtomically(path, bytes(obj));
}

}  // namespace lambert
