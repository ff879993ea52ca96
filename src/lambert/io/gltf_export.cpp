#include "lambert/io/gltf_export.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "lambert/core/atomic_file.h"

namespace lambert {
namespace {

// Appends values to the one buffer as a new, 4-byte aligned buffer view; returns its index.
int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int addVec3(tinygltf::Model& model, const std::vector<float>& xyz, bool bounds) {
  tinygltf::Accessor a;
  a.bufferView = addView(model, xyz.data(), xyz.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = TINYGLTF_TYPE_VEC3;
  a.count = xyz.size() / 3;
  if (bounds) {  // required for POSITION
    a.minValues = {INFINITY, INFINITY, INFINITY};
    a.maxValues = {-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t k = 0; k < xyz.size(); ++k) {
      a.minValues[k % 3] = std::fmin(a.minValues[k % 3], xyz[k]);
      a.maxValues[k % 3] = std::fmax(a.maxValues[k % 3], xyz[k]);
    }
  }
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
}

}  // namespace

Status writeGlb(const std::string& path, const SolutionView& solution, const GltfExportOptions& options) {
  const Scene& scene = solution.scene();
  const Mesh& mesh = solution.vertexMesh();
  const double scale = std::exp2(options.exposureStops);

  // Irradiance H = (B − E)/ρ per element, and both quantities at the vertices.
  std::vector<Rgb> irradiance(solution.radiosity().size());
  for (std::size_t i = 0; i < irradiance.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double rho = solution.albedo()[i][c];
      irradiance[i][c] = rho > 0 ? std::fmax(0.0, solution.radiosity()[i][c] - solution.emitted()[i][c]) / rho : 0;
    }
  const std::vector<Rgb> vertexIrradiance = solution.vertexValues(irradiance);
  const std::vector<Rgb> vertexRadiance = solution.vertexRadiance();
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

  // One primitive per (material, emitting) pair, each with its own vertices.
  std::map<std::pair<int, bool>, std::vector<std::uint32_t>> groups;
  for (std::uint32_t p = 0; p < mesh.numPatches(); ++p) {
    const Surface& surface = scene.surfaces[mesh.patches[p].surface];
    groups[{surface.material, surface.emittedRadiance.maxComponent() > 0}].push_back(p);
  }
  for (const auto& [key, patches] : groups) {
    const auto [materialIndex, emitting] = key;
    const bool radiance = emitting || options.bake == GltfBake::Radiance;
    const Material& material = scene.materials[static_cast<std::size_t>(materialIndex)];

    tinygltf::Material m;
    m.name = material.name + (emitting ? " (emitting)" : "");
    const Rgb base = radiance ? Rgb{1, 1, 1} : material.albedo;
    m.pbrMetallicRoughness.baseColorFactor = {base.r, base.g, base.b, 1};
    m.pbrMetallicRoughness.metallicFactor = 0;
    m.pbrMetallicRoughness.roughnessFactor = 1;
    m.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
    model.materials.push_back(m);

    std::map<std::uint32_t, std::uint32_t> local;
    std::vector<float> position, normal, colour, linear;
    std::vector<std::uint32_t> indices;
    auto vertex = [&](std::uint32_t v) {
      auto [it, inserted] = local.try_emplace(v, static_cast<std::uint32_t>(local.size()));
      if (inserted) {
        const Vec3 p = mesh.positions[v] * scene.metresPerUnit;
        const Vec3 n = normalize(normals[v]);
        const Rgb c = (radiance ? vertexRadiance[v] : vertexIrradiance[v] / kPi) * scale;
        for (double x : {p.x, p.y, p.z}) position.push_back(static_cast<float>(x));
        for (double x : {n.x, n.y, n.z}) normal.push_back(static_cast<float>(x));
        for (double x : {c.r, c.g, c.b}) colour.push_back(static_cast<float>(x));
        for (double x : {vertexRadiance[v].r, vertexRadiance[v].g, vertexRadiance[v].b}) linear.push_back(static_cast<float>(x));
      }
      return it->second;
    };
    for (std::uint32_t p : patches) {
      std::span<const std::uint32_t> corners = mesh.cornerIndices(p);
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        for (std::uint32_t v : {corners[0], corners[k], corners[k + 1]}) indices.push_back(vertex(v));
    }
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = static_cast<int>(model.materials.size() - 1);
    primitive.attributes["POSITION"] = addVec3(model, position, true);
    primitive.attributes["NORMAL"] = addVec3(model, normal, false);
    primitive.attributes["COLOR_0"] = addVec3(model, colour, false);
    primitive.attributes["_RADIANCE"] = addVec3(model, linear, false);
    tinygltf::Accessor index;
    index.bufferView = addView(model, indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    index.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    index.type = TINYGLTF_TYPE_SCALAR;
    index.count = indices.size();
    model.accessors.push_back(index);
    primitive.indices = static_cast<int>(model.accessors.size() - 1);
    out.primitives.push_back(primitive);
  }
  model.meshes.push_back(out);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = scene.name;
  model.nodes.push_back(node);
  tinygltf::Scene root;
  root.nodes = {0};
  model.scenes.push_back(root);
  model.defaultScene = 0;

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true)) return Error{path + ": cannot encode glTF"};
  const std::string bytes = stream.str();
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
}

}  // namespace lambert
