#include "lambert/load/gltf.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>
#include <map>

#include "lambert/core/text.h"
#include "lambert/core/transform.h"
#include "lambert/core/warning.h"
#include "lambert/load/gltf_types.h"
#include "lambert/scene/texture.h"

namespace lambert {
namespace {

Transform localTransform(const tinygltf::Node& node) {
  Transform t;
  if (node.matrix.size() == 16) {
    for (int k = 0; k < 16; ++k) t.m[k] = node.matrix[k];
    return t;
  }
  Transform translate, rotate, scale;
  if (node.translation.size() == 3)
    for (int k = 0; k < 3; ++k) translate.m[12 + k] = node.translation[k];
  if (node.rotation.size() == 4) {
    const double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
    rotate.m = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
                2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
                2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
                0,                       0,                       0,                       1};
  }
  if (node.scale.size() == 3)
    for (int k = 0; k < 3; ++k) scale.m[k * 5] = node.scale[k];
  return translate * rotate * scale;
}

class Reader {
 public:
  Reader(const tinygltf::Model& model, const std::string& path, const RegionOptions& regions)
      : model_(model), path_(path), regions_(regions) {}

  Result<Scene> read() {
    scene_.name = std::filesystem::path(path_).stem().string();
    scene_.metresPerUnit = 1;
    if (Status s = readMaterials(); !s) return s.error();
    const int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (model_.scenes.empty() || sceneIndex >= static_cast<int>(model_.scenes.size()))
      return Error{path_ + ": no scene to read (the file has " + std::to_string(model_.scenes.size()) + ")"};
    for (int root : model_.scenes[static_cast<std::size_t>(sceneIndex)].nodes)
      if (Status s = visit(root, Transform{}, 0); !s) return s.error();
    if (!usesDefault_) scene_.materials.pop_back();
    if (dropped_.total() > 0) warning(path_ + ": " + dropped_.describe());
    if (skippedPrimitives_ > 0)
      warning(path_ + ": " + std::to_string(skippedPrimitives_) + " point or line primitives skipped (lambert solves surfaces)");
    if (scene_.surfaces.empty()) return Error{path_ + ": no triangles in the default scene"};
    if (!haveCamera_) scene_.camera = cameraViewingScene(scene_);
    scene_.cameraGiven = haveCamera_;
    return std::move(scene_);  // read() is called once; a copy would duplicate every face
  }

 private:
  Status readMaterials() {
    for (const tinygltf::Material& m : model_.materials) {
      const auto& factor = m.pbrMetallicRoughness.baseColorFactor;
      Rgb albedo = factor.size() >= 3 ? Rgb{factor[0], factor[1], factor[2]} : Rgb{1, 1, 1};
      Material material{m.name, {}, m.doubleSided};
      const tinygltf::TextureInfo& base = m.pbrMetallicRoughness.baseColorTexture;
      const std::string where = path_ + ": material '" + m.name + "'";
      if (base.index >= 0) {
        Result<std::shared_ptr<const Texture>> texture = colourTexture(base.index);
        if (!texture) return texture.error();
        material.texture = *texture;
        if (base.extensions.count("KHR_texture_transform"))
          warning(where + ": KHR_texture_transform is not read; the base colour texture is placed by its UVs as they are");
      }
      Rgb emitted = m.emissiveFactor.size() == 3 ? Rgb{m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]} : Rgb{};
      if (auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end() && it->second.Has("emissiveStrength"))
        emitted = emitted * it->second.Get("emissiveStrength").GetNumberAsDouble();
      // L_e = emissiveFactor × strength × emissiveTexture (sRGB, as the base colour); a texture
      // under a black factor (glTF's default) changes nothing and is not read.
      const tinygltf::TextureInfo& emissive = m.emissiveTexture;
      const bool emissiveTextured = emissive.index >= 0 && emitted.maxComponent() > 0;
      if (emissiveTextured) {
        Result<std::shared_ptr<const Texture>> texture = colourTexture(emissive.index);
        if (!texture) return texture.error();
        material.emissionTexture = *texture;
        if (emissive.extensions.count("KHR_texture_transform"))
          warning(where + ": KHR_texture_transform is not read; the emissive texture is placed by its UVs as they are");
      }
      // A surface carries one set of texture coordinates: the base colour's where there is one.
      const int set = base.index >= 0 ? base.texCoord : emissiveTextured ? emissive.texCoord : 0;
      if (base.index >= 0 && emissiveTextured && base.texCoord != emissive.texCoord)
        warning(where + ": its emissive texture reads TEXCOORD_" + std::to_string(emissive.texCoord) + " and its base colour TEXCOORD_" +
                std::to_string(base.texCoord) + "; lambert reads one set per material: TEXCOORD_" + std::to_string(set) + " places both");
      texCoordSet_.push_back(set);
      for (int c = 0; c < 3; ++c)
        if (!(albedo[c] >= 0) || !(emitted[c] >= 0))
          return Error{path_ + ": material '" + m.name + "': base colour and emission must not be negative"};
      material.albedo = material.texture ? boundedAlbedo(albedo, *material.texture, where) : boundedAlbedo(albedo, where);
      scene_.materials.push_back(std::move(material));
      emission_.push_back(emitted);
    }
    defaultMaterial_ = static_cast<int>(scene_.materials.size());
    scene_.materials.push_back({"default", Rgb::gray(0.5)});  // glTF's default is white: kept physical
    emission_.push_back({});
    texCoordSet_.push_back(0);
    return Ok{};
  }

  // A base colour or emissive texture, sRGB decoded to linear (glTF's colour textures are sRGB);
  // one Texture per image, however many materials use it.
  Result<std::shared_ptr<const Texture>> colourTexture(int textureIndex) {
    if (textureIndex >= static_cast<int>(model_.textures.size())) return Error{path_ + ": texture " + std::to_string(textureIndex) + " does not exist"};
    const tinygltf::Texture& texture = model_.textures[static_cast<std::size_t>(textureIndex)];
    const int source = texture.source;
    if (source < 0 || source >= static_cast<int>(model_.images.size()))
      return Error{path_ + ": texture " + std::to_string(textureIndex) + " has no image"};
    if (texture.sampler >= 0 && texture.sampler < static_cast<int>(model_.samplers.size())) {
      const tinygltf::Sampler& sampler = model_.samplers[static_cast<std::size_t>(texture.sampler)];
      if (sampler.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT || sampler.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT)
        warning(path_ + ": texture " + std::to_string(textureIndex) + ": lambert repeats textures; its clamp or mirror wrap mode is not read");
    }
    if (auto it = textures_.find(source); it != textures_.end()) return it->second;
    const tinygltf::Image& image = model_.images[static_cast<std::size_t>(source)];
    const std::string name = image.uri.empty() ? "image " + std::to_string(source) : image.uri;
    // tinygltf leaves an image it could not load empty (and says why in a warning).
    if (image.image.empty()) return Error{path_ + ": " + name + ": the image could not be loaded (a missing or unreadable file?)"};
    if (image.bits != 8) return Error{path_ + ": " + name + ": only 8-bit images are read as colour textures"};
    Result<std::shared_ptr<const Texture>> read =
        textureFromSrgb8(image.image, image.width, image.height, image.component, path_ + ": " + name);
    if (read) textures_[source] = *read;
    return read;
  }

  Status visit(int nodeIndex, const Transform& parent, int depth) {
    if (nodeIndex < 0 || nodeIndex >= static_cast<int>(model_.nodes.size()))
      return Error{path_ + ": node " + std::to_string(nodeIndex) + " does not exist"};
    if (depth > 256) return Error{path_ + ": the node hierarchy is deeper than 256 (a cycle?)"};
    const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(nodeIndex)];
    const Transform world = parent * localTransform(node);
    if (node.mesh >= 0)
      if (Status s = readMesh(node, world); !s) return s;
    if (node.camera >= 0 && !haveCamera_)
      if (Status s = readCamera(node, world); !s) return s;
    if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end() && it->second.Has("light"))
      if (Status s = readLight(it->second.Get("light").GetNumberAsInt(), node, world); !s) return s;
    for (int child : node.children)
      if (Status s = visit(child, world, depth + 1); !s) return s;
    return Ok{};
  }

  // A typed view of an accessor's elements, bounds-checked against its buffer.
  Result<std::vector<double>> readAccessor(int index, int components) {
    if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
      return Error{path_ + ": accessor " + std::to_string(index) + " does not exist"};
    const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(index)];
    const std::string name = "accessor " + std::to_string(index);
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model_.bufferViews.size()))
      return Error{path_ + ": " + name + " has no buffer view (sparse accessors are not read)"};
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) return Error{path_ + ": " + name + ": no buffer"};
    const std::vector<unsigned char>& data = model_.buffers[static_cast<std::size_t>(view.buffer)].data;
    const int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (componentSize <= 0) return Error{path_ + ": " + name + ": unknown component type " + std::to_string(a.componentType)};
    const std::size_t elementSize = static_cast<std::size_t>(componentSize) * components;
    const std::size_t stride = view.byteStride ? view.byteStride : elementSize;
    const std::size_t start = view.byteOffset + a.byteOffset;
    if (a.count > 0 && (stride < elementSize || start + (a.count - 1) * stride + elementSize > view.byteOffset + view.byteLength ||
                        view.byteOffset + view.byteLength > data.size()))
      return Error{path_ + ": " + name + " reaches past the end of its buffer"};
    std::vector<double> values(a.count * components);
    for (std::size_t e = 0; e < a.count; ++e)
      for (int c = 0; c < components; ++c) {
        const unsigned char* p = data.data() + start + e * stride + static_cast<std::size_t>(c) * componentSize;
        double v = 0;
        switch (a.componentType) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); v = f; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t u; std::memcpy(&u, p, 2); v = u; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; break;
          default: return Error{path_ + ": " + name + ": component type " + std::to_string(a.componentType) + " is not read here"};
        }
        values[e * components + c] = v;
      }
    return values;
  }

  Status readMesh(const tinygltf::Node& node, const Transform& world) {
    // tinygltf does not check a node's indices; .at() would throw out of the reader.
    if (node.mesh >= static_cast<int>(model_.meshes.size()))
      return Error{path_ + ": node '" + node.name + "' refers to mesh " + std::to_string(node.mesh) + ", which does not exist"};
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(node.mesh)];
    const bool mirrored = world.determinant() < 0;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& primitive = mesh.primitives[p];
      const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        ++skippedPrimitives_;
        continue;
      }
      auto position = primitive.attributes.find("POSITION");
      if (position == primitive.attributes.end()) return Error{path_ + ": mesh '" + mesh.name + "' has a primitive without POSITION"};
      if (position->second < 0 || position->second >= static_cast<int>(model_.accessors.size()))
        return Error{path_ + ": mesh '" + mesh.name + "': POSITION accessor " + std::to_string(position->second) + " does not exist"};
      if (model_.accessors[static_cast<std::size_t>(position->second)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        return Error{path_ + ": mesh '" + mesh.name + "': quantised positions (KHR_mesh_quantization) are not read"};
      Result<std::vector<double>> xyz = readAccessor(position->second, 3);
      if (!xyz) return xyz.error();
      PolygonMesh polygons;
      // (Appended piecewise: GCC 12 warns falsely, -Wrestrict, about "literal" + std::string.)
      polygons.name = !node.name.empty() ? node.name : !mesh.name.empty() ? mesh.name : std::string("mesh ").append(std::to_string(node.mesh));
      if (mesh.primitives.size() > 1) polygons.name.append(" ").append(std::to_string(p + 1));
      // A NaN or infinite position is a broken file, not a degenerate face: refused, saying where.
      for (std::size_t k = 0; k < xyz->size(); ++k)
        if (!std::isfinite((*xyz)[k]))
          return Error{path_ + ": mesh '" + mesh.name + "': POSITION (accessor " + std::to_string(position->second) + ") vertex " +
                       std::to_string(k / 3) + " is not finite (NaN or infinite)"};
      for (std::size_t v = 0; v < xyz->size() / 3; ++v)
        polygons.positions.push_back(world.point({(*xyz)[3 * v], (*xyz)[3 * v + 1], (*xyz)[3 * v + 2]}));
      std::vector<std::uint32_t> indices;
      if (primitive.indices >= 0) {
        Result<std::vector<double>> read = readAccessor(primitive.indices, 1);
        if (!read) return read.error();
        // The spec allows unsigned byte, short and int indices only; a float one (a fuzzed file
        // held −1185.98) has no vertex to name.
        const int type = model_.accessors[static_cast<std::size_t>(primitive.indices)].componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
          return Error{path_ + ": mesh '" + mesh.name + "': indices (accessor " + std::to_string(primitive.indices) +
                       ") must be unsigned integers (componentType 5121, 5123 or 5125), not componentType " + std::to_string(type)};
        for (double i : *read) indices.push_back(static_cast<std::uint32_t>(i));
      } else {
        for (std::uint32_t i = 0; i < polygons.positions.size(); ++i) indices.push_back(i);
      }
      int material = primitive.material;
      if (material < 0 || material >= defaultMaterial_) {
        material = defaultMaterial_;
        usesDefault_ = true;
      }
      std::vector<Uv> uvs;
      if (const Material& m = scene_.materials[static_cast<std::size_t>(material)]; m.texture || m.emissionTexture) {
        Result<std::vector<Uv>> read = readUvs(primitive, texCoordSet_[static_cast<std::size_t>(material)], polygons.positions.size(), mesh.name);
        if (!read) return read.error();
        uvs = std::move(*read);
      }
      // The lightmap set (TEXCOORD_1, as MOZ_lightmap and engines' second UV channel use it),
      // wherever the primitive has one: mesh/lightmap_uvs.h decides whether it is usable.
      std::vector<Uv> lightmapUvs;
      if (primitive.attributes.count("TEXCOORD_1")) {
        Result<std::vector<Uv>> read = readUvs(primitive, 1, polygons.positions.size(), mesh.name);
        if (!read) return read.error();
        lightmapUvs = std::move(*read);
      }
      auto addTriangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (mirrored) std::swap(b, c);
        PolygonMesh::Face face{{a, b, c}, material};
        if (!uvs.empty() && a < uvs.size() && b < uvs.size() && c < uvs.size()) face.uvs = {uvs[a], uvs[b], uvs[c]};
        if (!lightmapUvs.empty() && a < lightmapUvs.size() && b < lightmapUvs.size() && c < lightmapUvs.size())
          face.lightmapUvs = {lightmapUvs[a], lightmapUvs[b], lightmapUvs[c]};
        polygons.faces.push_back(std::move(face));
      };
      if (mode == TINYGLTF_MODE_TRIANGLES)
        for (std::size_t t = 0; t + 2 < indices.size(); t += 3) addTriangle(indices[t], indices[t + 1], indices[t + 2]);
      else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
        for (std::size_t t = 0; t + 2 < indices.size(); ++t)
          t % 2 ? addTriangle(indices[t + 1], indices[t], indices[t + 2]) : addTriangle(indices[t], indices[t + 1], indices[t + 2]);
      else
        for (std::size_t t = 1; t + 1 < indices.size(); ++t) addTriangle(indices[0], indices[t], indices[t + 1]);
      dropped_.add(addSmoothRegions(scene_, polygons, emission_, regions_));
    }
    return Ok{};
  }

  // TEXCOORD_<set> of a primitive: floats, or normalised unsigned bytes or shorts.
  Result<std::vector<Uv>> readUvs(const tinygltf::Primitive& primitive, int set, std::size_t vertices, const std::string& meshName) {
    const std::string attribute = "TEXCOORD_" + std::to_string(set);
    auto found = primitive.attributes.find(attribute);
    if (found == primitive.attributes.end())
      return Error{path_ + ": mesh '" + meshName + "': its material has a texture but the primitive has no " + attribute};
    Result<std::vector<double>> read = readAccessor(found->second, 2);
    if (!read) return read.error();
    const tinygltf::Accessor& accessor = model_.accessors[static_cast<std::size_t>(found->second)];
    double scale = 1;
    if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) scale = 1 / 255.0;
    if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) scale = 1 / 65535.0;
    if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !accessor.normalized)
      return Error{path_ + ": mesh '" + meshName + "': " + attribute + " must be floats or normalised integers"};
    if (read->size() / 2 != vertices)
      return Error{path_ + ": mesh '" + meshName + "': " + attribute + " has " + std::to_string(read->size() / 2) + " elements, POSITION " + std::to_string(vertices)};
    std::vector<Uv> uvs(vertices);
    for (std::size_t v = 0; v < vertices; ++v) uvs[v] = {(*read)[2 * v] * scale, (*read)[2 * v + 1] * scale};
    return uvs;
  }

  Status readCamera(const tinygltf::Node& node, const Transform& world) {
    if (node.camera >= static_cast<int>(model_.cameras.size()))
      return Error{path_ + ": node '" + node.name + "' refers to camera " + std::to_string(node.camera) + ", which does not exist"};
    const tinygltf::Camera& camera = model_.cameras[static_cast<std::size_t>(node.camera)];
    if (camera.type != "perspective") return Ok{};
    haveCamera_ = true;
    scene_.camera.eye = world.point({0, 0, 0});
    scene_.camera.target = scene_.camera.eye + normalize(world.direction({0, 0, -1}));
    scene_.camera.up = normalize(world.direction({0, 1, 0}));
    scene_.camera.verticalFovDegrees = camera.perspective.yfov * 180 / kPi;
    return Ok{};
  }

  Status readLight(int index, const tinygltf::Node& node, const Transform& world) {
    if (index < 0 || index >= static_cast<int>(model_.lights.size()))
      return Error{path_ + ": node '" + node.name + "' refers to light " + std::to_string(index) + ", which does not exist"};
    const tinygltf::Light& l = model_.lights[static_cast<std::size_t>(index)];
    const Rgb colour = l.color.size() == 3 ? Rgb{l.color[0], l.color[1], l.color[2]} : Rgb{1, 1, 1};
    if (!(l.intensity >= 0)) return Error{path_ + ": light '" + l.name + "': negative intensity"};
    Light light;
    light.name = !l.name.empty() ? l.name : node.name;
    light.position = world.point({0, 0, 0});
    light.direction = normalize(world.direction({0, 0, -1}));  // lights shine along their local −z
    const Rgb radiometric = colour * (l.intensity / kLumensPerWatt);
    if (l.type == "point") {
      light.kind = LightKind::Point;
      light.intensity = radiometric;
    } else if (l.type == "spot") {
      light.kind = LightKind::Spot;
      light.intensity = radiometric;
      light.coneAngleDegrees = l.spot.outerConeAngle * 180 / kPi;
      light.falloffDegrees = std::fmax(0.0, (l.spot.outerConeAngle - l.spot.innerConeAngle) * 180 / kPi);
    } else if (l.type == "directional") {
      light.kind = LightKind::Directional;
      light.irradiance = radiometric;
    } else {
      return Error{path_ + ": light '" + l.name + "': unknown type '" + l.type + "' (KHR_lights_punctual: point, spot, directional)"};
    }
    scene_.lights.push_back(light);
    return Ok{};
  }

  const tinygltf::Model& model_;
  std::string path_;
  RegionOptions regions_;
  Scene scene_;
  std::vector<Rgb> emission_;
  std::vector<int> texCoordSet_;  // per material: the TEXCOORD set its textures read
  std::map<int, std::shared_ptr<const Texture>> textures_;  // by image
  int defaultMaterial_ = 0;
  bool usesDefault_ = false;
  bool haveCamera_ = false;
  DroppedFaces dropped_;
  int skippedPrimitives_ = 0;
};

// A .glb's container (glTF 2.0 spec, "Binary glTF Layout"): a 12-byte header (magic 'glTF',
// version 2, the file's length), then chunks of (length, type, data): JSON first, then an
// optional BIN. Checked here, before tinygltf, so that a damaged file is named for what is
// wrong with it ("truncated") rather than tinygltf's "Invalid glTF binary". Returns the JSON
// chunk; bytes after the header's length are not glTF, and are dropped from `file` (a warning).
Result<std::string_view> glbJsonChunk(std::string& file, const std::string& path) {
  auto word = [&](std::size_t offset) {  // little-endian, whatever the machine
    std::uint32_t value = 0;
    for (int b = 3; b >= 0; --b) value = (value << 8) | static_cast<unsigned char>(file[offset + static_cast<std::size_t>(b)]);
    return value;
  };
  const std::string again = ": export it again";
  if (file.size() < 12)
    return Error{path + ": truncated: a .glb starts with a 12-byte header, and this file has " + std::to_string(file.size()) + " bytes" + again};
  if (word(0) != 0x46546C67u) return Error{path + ": not a binary glTF file (a .glb starts with 'glTF')"};
  if (word(4) != 2) return Error{path + ": binary glTF version " + std::to_string(word(4)) + "; lambert reads glTF 2.0 (export it as glTF 2.0)"};
  const std::size_t length = word(8);
  if (length > file.size())
    return Error{path + ": the header says the file has " + std::to_string(length) + " bytes, but it has " + std::to_string(file.size()) +
                 " (truncated)" + again};
  if (length < file.size()) {
    warning(path + ": " + std::to_string(file.size() - length) + " bytes after the length the header gives (" + std::to_string(length) + ") are ignored");
    file.resize(length);
  }
  std::string_view json;
  std::size_t offset = 12;
  for (int chunk = 0; offset < file.size() && chunk < 2; ++chunk) {
    const char* name = chunk == 0 ? "JSON" : "BIN";
    if (file.size() - offset < 8) return Error{path + ": the " + name + " chunk's 8-byte header is cut off at byte " + std::to_string(offset) + again};
    const std::size_t chunkLength = word(offset);
    const std::uint32_t expectedType = chunk == 0 ? 0x4E4F534Au : 0x004E4942u;  // "JSON", "BIN\0"
    if (word(offset + 4) != expectedType)
      return Error{path + ": chunk " + std::to_string(chunk) + " at byte " + std::to_string(offset) + " is not the " + name +
                   " chunk a .glb must have there" + again};
    if (chunkLength > file.size() - offset - 8)
      return Error{path + ": the " + name + " chunk at byte " + std::to_string(offset) + " claims " + std::to_string(chunkLength) +
                   " bytes, but only " + std::to_string(file.size() - offset - 8) + " follow its header" + again};
    if (chunk == 0) json = std::string_view(file).substr(offset + 8, chunkLength);
    offset += 8 + chunkLength;
  }
  if (offset == 12) return Error{path + ": the file has a header but no JSON chunk" + again};
  return json;
}

// The glTF JSON's types, where it parses (where it does not, tinygltf's message says where).
Status checkJsonTypes(std::string_view json, const std::string& path) {
  const nlohmann::json document = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return Ok{};
  return checkGltfTypes(document, path);
}

}  // namespace

Result<Scene> readGltf(const std::string& path, const RegionOptions& regions) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such glTF file"};
  const bool binary = lowercaseExtension(path) == ".glb";
  // Read once: checked here, then handed to tinygltf from memory.
  Result<std::string> file = readWholeFile(path);
  if (!file) return file.error();
  if (file->size() > std::numeric_limits<unsigned>::max()) return Error{path + ": larger than 4 GiB, which tinygltf cannot read"};
  Result<std::string_view> json = binary ? glbJsonChunk(*file, path) : Result<std::string_view>(std::string_view(*file));
  if (!json) return json.error();
  if (Status types = checkJsonTypes(*json, path); !types) return types.error();
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warn;
  // Relative buffer and image URIs are resolved against the file's folder, as LoadASCIIFromFile would.
  const std::string folder = std::filesystem::path(path).parent_path().string();
  const auto size = static_cast<unsigned>(file->size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warn, reinterpret_cast<const unsigned char*>(file->data()), size, folder)
                         : loader.LoadASCIIFromString(&model, &error, &warn, file->data(), size, folder);
  if (!warn.empty()) warning(path + ": " + singleLine(warn));
  if (!ok) return Error{path + ": " + (error.empty() ? std::string("not a glTF file") : singleLine(error))};
  return Reader(model, path, regions).read();
}

}  // namespace lambert
