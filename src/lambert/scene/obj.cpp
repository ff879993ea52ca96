#include "lambert/scene/obj.h"

#include <tiny_obj_loader.h>

#include <filesystem>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/scene/texture.h"

namespace lambert {

Result<Scene> readObj(const std::string& path, const ObjOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such OBJ file"};
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // lambert triangulates (ear clipping) only what is not convex
  config.vertex_color = false;
  config.mtl_search_path = std::filesystem::path(path).parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) return Error{path + ": " + singleLine(reader.Error())};
  if (!reader.Warning().empty()) warning(path + ": " + singleLine(reader.Warning()));

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.metresPerUnit = options.metresPerUnit;
  std::vector<Rgb> emission;
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    Rgb albedo{m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    Rgb emitted{m.emission[0], m.emission[1], m.emission[2]};
    for (int c = 0; c < 3; ++c) {
      if (!(albedo[c] >= 0)) return Error{path + ": material '" + m.name + "': Kd must not be negative"};
      if (!(emitted[c] >= 0)) return Error{path + ": material '" + m.name + "': Ke must not be negative"};
    }
    Material material{m.name, albedo};
    if (!m.diffuse_texname.empty()) {
      Result<std::shared_ptr<const Texture>> texture = readTexture((std::filesystem::path(config.mtl_search_path) / m.diffuse_texname).string());
      if (!texture) return Error{path + ": material '" + m.name + "': map_Kd: " + texture.error().message};
      material.texture = *texture;
    }
    const std::string where = path + ": material '" + m.name + "': Kd";
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
  mesh.positions.resize(attrib.vertices.size() / 3);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    mesh.positions[v] = {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]};
  DroppedFaces dropped;
  std::size_t numFaces = 0, facesWithoutVt = 0;
  const auto& shapes = reader.GetShapes();
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const tinyobj::mesh_t& m = shapes[s].mesh;
    mesh.name = shapes[s].name.empty() ? "object " + std::to_string(s + 1) : shapes[s].name;
    mesh.faces.clear();
    std::size_t index = 0;
    for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      PolygonMesh::Face face;
      const int material = f < m.material_ids.size() ? m.material_ids[f] : -1;
      face.material = material >= 0 && material < defaultMaterial ? material : defaultMaterial;
      const bool textured = scene.materials[static_cast<std::size_t>(face.material)].texture != nullptr;
      bool missingVt = false;
      for (unsigned k = 0; k < m.num_face_vertices[f]; ++k, ++index) {
        face.vertices.push_back(static_cast<std::uint32_t>(m.indices[index].vertex_index));
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

}  // namespace lambert
