#include "lambert/io/gltf_export.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "lambert/core/atomic_file.h"
#include "lambert/core/warning.h"
#include "lambert/io/gltf_model.h"
#include "lambert/light/emission.h"

namespace lambert {

Status writeGlb(const std::string& path, const SolutionView& solution, const GltfExportOptions& options) {
  const Scene& scene = solution.scene();
  const Mesh& mesh = solution.vertexMesh();
  const double scale = std::exp2(options.exposureStops);

  // Irradiance H = (B − E)/ρ and radiance L = B/π at the vertices (one final gather for both).
  constexpr VertexQuantity kQuantities[] = {VertexQuantity::Irradiance, VertexQuantity::Radiosity};
  std::vector<std::vector<Rgb>> atVertices = solution.vertexValues(kQuantities);
  const std::vector<Rgb>& vertexIrradiance = atVertices[0];
  std::vector<Rgb>& vertexRadiance = atVertices[1];
  for (Rgb& l : vertexRadiance) l = l / kPi;
  // Vertex normals: the area-weighted normals of the vertex's patches (all on one surface).
  std::vector<Vec3> normals(mesh.numVertices());
  for (const Patch& patch : mesh.patches)
    for (std::uint32_t k = 0; k < patch.numCorners; ++k) normals[patch.vertices[k]] += patch.normal * patch.area;

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "lambert";
  model.buffers.resize(1);
  model.extensionsUsed = {"KHR_materials_unlit"};
  tinygltf::Mesh out;
  out.name = scene.name;

  std::map<const Texture*, int> textureIndex;
  std::size_t clipped = 0, values = 0;
  // One primitive per (material, emitting) pair, each with its own vertices. Whether a patch
  // emits is its own emission's (an emission texture dark over most of a material leaves the
  // rest of it reflecting, under its base colour texture).
  const std::vector<Rgb> emitted = emittedRadiosity(scene, mesh);
  std::map<std::pair<int, bool>, std::vector<std::uint32_t>> groups;
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p)
    groups[{scene.surfaces[mesh.patches[p].surface].material, emitted[p].maxComponent() > 0}].push_back(p);
  for (const auto& [key, patches] : groups) {
    const auto [materialIndex, emitting] = key;
    const bool radiance = emitting || options.bake == GltfBake::Radiance;
    const Material& material = scene.materials[static_cast<std::size_t>(materialIndex)];

    tinygltf::Material m;
    m.name = material.name + (emitting ? " (emitting)" : "");
    const Rgb base = radiance ? Rgb{1, 1, 1} : material.albedo;
    m.pbrMetallicRoughness.baseColorFactor = {base.r, base.g, base.b, 1};
    // A texture stays a texture: sharp over the smooth light in COLOR_0. Its UVs are per patch
    // corner, so each patch has vertices of its own (a UV seam can run through a vertex).
    const bool textured = !radiance && material.texture;
    if (textured) {
      auto [it, inserted] = textureIndex.try_emplace(material.texture.get(), 0);
      if (inserted) it->second = gltf::addColourTexture(model, *material.texture);
      m.pbrMetallicRoughness.baseColorTexture.index = it->second;
    }
    m.pbrMetallicRoughness.metallicFactor = 0;
    m.pbrMetallicRoughness.roughnessFactor = 1;
    m.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
    model.materials.push_back(m);

    std::map<std::uint64_t, std::uint32_t> local;
    std::vector<float> position, normal, colour, linear, texcoord;
    std::vector<std::uint32_t> indices;
    // A vertex of the mesh, or (textured) of one patch corner with its UV.
    auto vertex = [&](std::uint32_t v, std::uint32_t patch, const Uv* uv) {
      const std::uint64_t key = uv ? (std::uint64_t{patch} << 32 | v) : v;
      auto [it, inserted] = local.try_emplace(key, static_cast<std::uint32_t>(local.size()));
      if (inserted) {
        if (uv)
          for (double x : {uv->u, uv->v}) texcoord.push_back(static_cast<float>(x));
        const Vec3 p = mesh.positions[v] * scene.metresPerUnit;
        const Vec3 n = normalize(normals[v]);
        const Rgb c = (radiance ? vertexRadiance[v] : vertexIrradiance[v] / kPi) * scale;
        for (double x : {p.x, p.y, p.z}) position.push_back(static_cast<float>(x));
        for (double x : {n.x, n.y, n.z}) normal.push_back(static_cast<float>(x));
        // glTF colours are in [0, 1]: brighter light is clipped (and counted), _RADIANCE keeps it.
        for (double x : {c.r, c.g, c.b}) {
          clipped += x > 1;
          colour.push_back(static_cast<float>(std::fmin(x, 1.0)));
        }
        for (double x : {vertexRadiance[v].r, vertexRadiance[v].g, vertexRadiance[v].b}) linear.push_back(static_cast<float>(x));
      }
      return it->second;
    };
    for (std::uint32_t p : patches) {
      std::span<const std::uint32_t> corners = mesh.cornerIndices(p);
      std::array<Uv, 4> uvs{};
      if (textured) uvs = patchCornerUvs(scene, mesh, p);
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        for (std::size_t c : {std::size_t{0}, k, k + 1}) indices.push_back(vertex(corners[c], p, textured ? &uvs[c] : nullptr));
    }
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = static_cast<int>(model.materials.size() - 1);
    primitive.attributes["POSITION"] = gltf::addVec3(model, position, true);
    primitive.attributes["NORMAL"] = gltf::addVec3(model, normal, false);
    primitive.attributes["COLOR_0"] = gltf::addVec3(model, colour, false);
    values += colour.size();
    primitive.attributes["_RADIANCE"] = gltf::addVec3(model, linear, false);
    if (textured) primitive.attributes["TEXCOORD_0"] = gltf::addVec2(model, texcoord);
    primitive.indices = gltf::addIndices(model, indices);
    out.primitives.push_back(primitive);
  }
  model.meshes.push_back(out);
  gltf::addSceneWithCamera(model, scene);

  if (clipped > 0) {
    char share[32];
    std::snprintf(share, sizeof share, "%.3g%%", 100.0 * static_cast<double>(clipped) / static_cast<double>(values));
    warning(path + ": " + share + " of the COLOR_0 values were above 1 and are clipped (glTF colours are in [0, 1]); " +
            "a lower --exposure keeps them, and _RADIANCE holds the unclipped radiance");
  }
  Result<std::vector<std::uint8_t>> bytes = gltf::encodeGlb(model);
  if (!bytes) return Error{path + ": " + bytes.error().message};
  return writeFileAtomically(path, *bytes);
}

}  // namespace lambert
