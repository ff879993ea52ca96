#include "lambert/io/gltf_export.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

#include "lambert/core/atomic_file.h"
#include "lambert/core/srgb.h"
#include "lambert/core/warning.h"
#include "lambert/io/png.h"
#include "lambert/light/emission.h"

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

// The texture as an 8-bit sRGB PNG inside the buffer (its texels were 8-bit sRGB when read, so
// this gives them back exactly).
int addTexture(tinygltf::Model& model, const Texture& texture) {
  std::vector<std::uint8_t> rgb8;
  rgb8.reserve(texture.pixels.size() * 3);
  for (const Rgb& p : texture.pixels)
    for (int c = 0; c < 3; ++c) rgb8.push_back(static_cast<std::uint8_t>(std::lround(255 * srgbEncode(std::clamp(p[c], 0.0, 1.0)))));
  Result<std::vector<std::uint8_t>> png = encodePng(texture.width, texture.height, rgb8);
  LAMBERT_CHECK(png.ok());  // the sizes are the texture's own
  tinygltf::Image image;
  image.name = std::filesystem::path(texture.path).filename().string();
  image.mimeType = "image/png";
  image.bufferView = addView(model, png->data(), png->size(), 0);
  model.images.push_back(image);
  tinygltf::Sampler sampler;  // lambert repeats textures, as glTF's default sampler does
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  model.samplers.push_back(sampler);
  tinygltf::Texture t;
  t.source = static_cast<int>(model.images.size() - 1);
  t.sampler = static_cast<int>(model.samplers.size() - 1);
  model.textures.push_back(t);
  return static_cast<int>(model.textures.size() - 1);
}

int addVec2(tinygltf::Model& model, const std::vector<float>& uv) {
  tinygltf::Accessor a;
  a.bufferView = addView(model, uv.data(), uv.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = TINYGLTF_TYPE_VEC2;
  a.count = uv.size() / 2;
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
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

// The scene's camera, so that a viewer opens at lambert's view: a node at the eye whose −z looks
// at the target, in metres.
tinygltf::Node cameraNode(tinygltf::Model& model, const Scene& scene) {
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.name = "camera";
  camera.perspective.yfov = scene.camera.verticalFovDegrees * kPi / 180;
  camera.perspective.aspectRatio = 1;
  const Bounds bounds = sceneBounds(scene);
  const double diagonal = length(bounds.hi - bounds.lo) * scene.metresPerUnit;
  camera.perspective.znear = 1e-3 * diagonal;
  camera.perspective.zfar = 10 * diagonal + length(scene.camera.eye - bounds.lo) * scene.metresPerUnit;
  model.cameras.push_back(camera);
  // Rotation from the camera's basis (right, up, back) as a quaternion.
  const Vec3 back = normalize(scene.camera.eye - scene.camera.target);
  const Vec3 right = normalize(cross(scene.camera.up, back));
  const Vec3 up = cross(back, right);
  const double m[3][3] = {{right.x, up.x, back.x}, {right.y, up.y, back.y}, {right.z, up.z, back.z}};
  double w, x, y, z;
  const double trace = m[0][0] + m[1][1] + m[2][2];
  if (trace > 0) {
    const double s = 2 * std::sqrt(1 + trace);
    w = s / 4, x = (m[2][1] - m[1][2]) / s, y = (m[0][2] - m[2][0]) / s, z = (m[1][0] - m[0][1]) / s;
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = 2 * std::sqrt(1 + m[0][0] - m[1][1] - m[2][2]);
    w = (m[2][1] - m[1][2]) / s, x = s / 4, y = (m[0][1] + m[1][0]) / s, z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] > m[2][2]) {
    const double s = 2 * std::sqrt(1 + m[1][1] - m[0][0] - m[2][2]);
    w = (m[0][2] - m[2][0]) / s, x = (m[0][1] + m[1][0]) / s, y = s / 4, z = (m[1][2] + m[2][1]) / s;
  } else {
    const double s = 2 * std::sqrt(1 + m[2][2] - m[0][0] - m[1][1]);
    w = (m[1][0] - m[0][1]) / s, x = (m[0][2] + m[2][0]) / s, y = (m[1][2] + m[2][1]) / s, z = s / 4;
  }
  tinygltf::Node node;
  node.name = "camera";
  node.camera = static_cast<int>(model.cameras.size() - 1);
  const Vec3 eye = scene.camera.eye * scene.metresPerUnit;
  node.translation = {eye.x, eye.y, eye.z};
  node.rotation = {x, y, z, w};
  return node;
}

}  // namespace

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
      if (inserted) it->second = addTexture(model, *material.texture);
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
    primitive.attributes["POSITION"] = addVec3(model, position, true);
    primitive.attributes["NORMAL"] = addVec3(model, normal, false);
    primitive.attributes["COLOR_0"] = addVec3(model, colour, false);
    values += colour.size();
    primitive.attributes["_RADIANCE"] = addVec3(model, linear, false);
    if (textured) primitive.attributes["TEXCOORD_0"] = addVec2(model, texcoord);
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
  model.nodes.push_back(cameraNode(model, scene));
  tinygltf::Scene root;
  root.nodes = {0, 1};
  model.scenes.push_back(root);
  model.defaultScene = 0;

  if (clipped > 0) {
    char share[32];
    std::snprintf(share, sizeof share, "%.3g%%", 100.0 * static_cast<double>(clipped) / static_cast<double>(values));
    warning(path + ": " + share + " of the COLOR_0 values were above 1 and are clipped (glTF colours are in [0, 1]); " +
            "a lower --exposure keeps them, and _RADIANCE holds the unclipped radiance");
  }
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true)) return Error{path + ": cannot encode glTF"};
  const std::string bytes = stream.str();
  return writeFileAtomically(path, std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
}

}  // namespace lambert
