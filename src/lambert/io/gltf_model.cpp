#include "lambert/io/gltf_model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "lambert/core/srgb.h"
#include "lambert/io/png.h"
#include "lambert/render/scene_camera.h"

namespace lambert::gltf {

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

int addPngImage(tinygltf::Model& model, const std::vector<std::uint8_t>& png, const std::string& name) {
  tinygltf::Image image;
  image.name = name;
  image.mimeType = "image/png";
  image.bufferView = addView(model, png.data(), png.size(), 0);
  model.images.push_back(image);
  return static_cast<int>(model.images.size() - 1);
}

int addTexture(tinygltf::Model& model, int image, int wrap, int minFilter) {
  tinygltf::Sampler sampler;
  sampler.wrapS = sampler.wrapT = wrap;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = minFilter;
  model.samplers.push_back(sampler);
  tinygltf::Texture t;
  t.source = image;
  t.sampler = static_cast<int>(model.samplers.size() - 1);
  model.textures.push_back(t);
  return static_cast<int>(model.textures.size() - 1);
}

// The texture as an 8-bit sRGB PNG inside the buffer (its texels were 8-bit sRGB when read, so
// this gives them back exactly).
int addColourTexture(tinygltf::Model& model, const Texture& texture) {
  std::vector<std::uint8_t> rgb8;
  rgb8.reserve(texture.pixels.size() * 3);
  for (const Rgb& p : texture.pixels)
    for (int c = 0; c < 3; ++c) rgb8.push_back(static_cast<std::uint8_t>(std::lround(255 * srgbEncode(std::clamp(p[c], 0.0, 1.0)))));
  Result<std::vector<std::uint8_t>> png = encodePng(texture.width, texture.height, rgb8);
  LAMBERT_CHECK(png.ok());  // the sizes are the texture's own
  const int image = addPngImage(model, *png, std::filesystem::path(texture.path).filename().string());
  // lambert repeats textures, as glTF's default sampler does
  return addTexture(model, image, TINYGLTF_TEXTURE_WRAP_REPEAT, TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR);
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

int addIndices(tinygltf::Model& model, const std::vector<std::uint32_t>& indices) {
  tinygltf::Accessor a;
  a.bufferView = addView(model, indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  a.type = TINYGLTF_TYPE_SCALAR;
  a.count = indices.size();
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
}

tinygltf::Node cameraNode(tinygltf::Model& model, const Scene& scene) {
  // The scene's own camera, else the view `lambert render` draws (render/scene_camera.h): a
  // scene without one (an MGF building) has a default Camera{} that stands wherever it happens to,
  // outside the building (the glb opened in a viewer showed its outer wall, +9.8 stops).
  const Result<ChosenCamera> chosen = sceneCamera(scene, CameraRequest{});
  const Camera& view = chosen ? chosen->camera : scene.camera;
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.name = "camera";
  camera.perspective.yfov = view.verticalFovDegrees * kPi / 180;
  camera.perspective.aspectRatio = 1;
  const Bounds bounds = sceneBounds(scene);
  const double diagonal = length(bounds.hi - bounds.lo) * scene.metresPerUnit;
  camera.perspective.znear = 1e-3 * diagonal;
  camera.perspective.zfar = 10 * diagonal + length(view.eye - bounds.lo) * scene.metresPerUnit;
  model.cameras.push_back(camera);
  // Rotation from the camera's basis (right, up, back) as a quaternion.
  const Vec3 back = normalize(view.eye - view.target);
  const Vec3 right = normalize(cross(view.up, back));
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
  const Vec3 eye = view.eye * scene.metresPerUnit;
  node.translation = {eye.x, eye.y, eye.z};
  node.rotation = {x, y, z, w};
  return node;
}

Result<std::vector<std::uint8_t>> encodeGlb(tinygltf::Model& model) {
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true)) return Error{"cannot encode glTF"};
  const std::string bytes = stream.str();
  return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

void addSceneWithCamera(tinygltf::Model& model, const Scene& scene) {
  tinygltf::Node node;
  node.mesh = 0;
  node.name = scene.name;
  model.nodes.push_back(node);
  model.nodes.push_back(cameraNode(model, scene));
  tinygltf::Scene root;
  root.nodes = {static_cast<int>(model.nodes.size()) - 2, static_cast<int>(model.nodes.size()) - 1};
  model.scenes.push_back(root);
  model.defaultScene = static_cast<int>(model.scenes.size()) - 1;
}

}  // namespace lambert::gltf
