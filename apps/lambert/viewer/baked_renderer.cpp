#include "viewer/baked_renderer.h"

#include <chrono>
#include <cmath>
#include <cstddef>
#include <string>

#include <epoxy/gl.h>

namespace lambert::viewer {
namespace {

struct FaceVertex {
  float position[3];
  float lightmapUv[2];  // glTF's convention: (0, 0) the top-left corner of the atlas's first row
  float albedo[3];      // ρ
  float emitted[3];     // L_e, W/(m²·sr)
};

const char* kLightmapVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 lightmapUv;
layout(location = 2) in vec3 albedo;
layout(location = 3) in vec3 emitted;
uniform mat4 viewProjection;
out vec2 vUv;
flat out vec3 vAlbedo;
flat out vec3 vEmitted;
void main() {
  vUv = lightmapUv;
  vAlbedo = albedo;
  vEmitted = emitted;
  gl_Position = viewProjection * vec4(position, 1.0);
}
)";

// The atlas's first row is the texture's first row (t = 0), so glTF's lightmap coordinates are
// the texture's coordinates as they are.
const char* kLightmapFragmentShader = R"(#version 330 core
const float PI = 3.14159265358979;
in vec2 vUv;
flat in vec3 vAlbedo;
flat in vec3 vEmitted;
uniform sampler2D irradiance;  // E, W/m²
uniform float exposureScale;
uniform bool encodeSrgb;
out vec4 colour;
vec3 srgb(vec3 c) { return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c)); }
void main() {
  if (!gl_FrontFacing) discard;  // as the software renderer and render/lightmap_image.h cull
  vec3 radiance = vEmitted + vAlbedo / PI * texture(irradiance, vUv).rgb;
  vec3 c = clamp(radiance * exposureScale, 0.0, 1.0);
  colour = vec4(encodeSrgb ? srgb(c) : c, 1.0);
}
)";

const char* kSphereVertexShader = R"(#version 330 core
layout(location = 0) in vec3 direction;  // unit: the sphere's normal there
uniform mat4 viewProjection;
uniform vec3 centre;
uniform float radius;
out vec3 vNormal;
void main() {
  vNormal = direction;
  gl_Position = viewProjection * vec4(centre + radius * direction, 1.0);
}
)";

// bake/probes.h's basis (shBasis), in its order k = l² + l + m.
const char* kSphereFragmentShader = R"(#version 330 core
const float PI = 3.14159265358979;
in vec3 vNormal;
uniform vec3 sh[9];  // irradiance SH, W/m²
uniform vec3 albedo;
uniform float exposureScale;
uniform bool encodeSrgb;
out vec4 colour;
vec3 srgb(vec3 c) { return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c)); }
void main() {
  vec3 n = normalize(vNormal);
  float x = n.x, y = n.y, z = n.z;
  vec3 e = sh[0] * 0.282094792
         + 0.488602512 * (sh[1] * y + sh[2] * z + sh[3] * x)
         + 1.092548431 * (sh[4] * x * y + sh[5] * y * z + sh[7] * x * z)
         + sh[6] * (0.315391565 * (3.0 * z * z - 1.0))
         + sh[8] * (0.546274215 * (x * x - y * y));
  // L2 irradiance rings below zero facing a dark region opposite a bright one: no light is negative.
  vec3 radiance = albedo / PI * max(e, vec3(0.0));
  vec3 c = clamp(radiance * exposureScale, 0.0, 1.0);
  colour = vec4(encodeSrgb ? srgb(c) : c, 1.0);
}
)";

constexpr int kSphereStacks = 48, kSphereSlices = 96;

void put(float (&out)[3], const Vec3& v) {
  out[0] = static_cast<float>(v.x), out[1] = static_cast<float>(v.y), out[2] = static_cast<float>(v.z);
}
void put(float (&out)[3], const Rgb& c) {
  out[0] = static_cast<float>(c.r), out[1] = static_cast<float>(c.g), out[2] = static_cast<float>(c.b);
}

void faceAttribute(GLuint location, int size, std::size_t offset) {
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, sizeof(FaceVertex), reinterpret_cast<const void*>(offset));
}

void setTone(GLuint program, const DisplaySettings& settings) {
  glUniform1f(glGetUniformLocation(program, "exposureScale"), static_cast<float>(std::exp2(settings.exposure)));
  glUniform1i(glGetUniformLocation(program, "encodeSrgb"), settings.srgb);
}

}  // namespace

Result<std::unique_ptr<BakedRenderer>> BakedRenderer::create(const Scene& scene) {
  std::unique_ptr<BakedRenderer> r(new BakedRenderer(scene));
  Result<unsigned> lightmap = linkProgram(kLightmapVertexShader, kLightmapFragmentShader, "lightmap");
  if (!lightmap) return lightmap.error();
  r->lightmapProgram_ = *lightmap;
  Result<unsigned> sphere = linkProgram(kSphereVertexShader, kSphereFragmentShader, "probe sphere");
  if (!sphere) return sphere.error();
  r->sphereProgram_ = *sphere;

  glGenVertexArrays(1, &r->faceArray_);
  glGenBuffers(1, &r->faceBuffer_);
  glBindVertexArray(r->faceArray_);
  glBindBuffer(GL_ARRAY_BUFFER, r->faceBuffer_);
  faceAttribute(0, 3, offsetof(FaceVertex, position));
  faceAttribute(1, 2, offsetof(FaceVertex, lightmapUv));
  faceAttribute(2, 3, offsetof(FaceVertex, albedo));
  faceAttribute(3, 3, offsetof(FaceVertex, emitted));

  // A latitude-longitude sphere of unit directions (its normals), indexed.
  std::vector<float> directions;
  for (int i = 0; i <= kSphereStacks; ++i) {
    const double theta = kPi * i / kSphereStacks;
    for (int j = 0; j <= kSphereSlices; ++j) {
      const double phi = 2 * kPi * j / kSphereSlices;
      directions.insert(directions.end(), {static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                                           static_cast<float>(-std::sin(theta) * std::sin(phi))});
    }
  }
  std::vector<unsigned> indices;
  for (int i = 0; i < kSphereStacks; ++i)
    for (int j = 0; j < kSphereSlices; ++j) {
      const unsigned a = static_cast<unsigned>(i * (kSphereSlices + 1) + j), b = a + kSphereSlices + 1;
      indices.insert(indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  r->sphereIndexCount_ = static_cast<int>(indices.size());
  glGenVertexArrays(1, &r->sphereArray_);
  glGenBuffers(1, &r->sphereBuffer_);
  glGenBuffers(1, &r->sphereIndices_);
  glBindVertexArray(r->sphereArray_);
  glBindBuffer(GL_ARRAY_BUFFER, r->sphereBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(directions.size() * sizeof(float)), directions.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphereIndices_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)), indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  if (GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"OpenGL error " + std::to_string(error) + " while setting up the lightmap and probe renderer"};
  return r;
}

BakedRenderer::~BakedRenderer() {
  glDeleteProgram(lightmapProgram_);
  glDeleteProgram(sphereProgram_);
  for (GLuint array : {faceArray_, sphereArray_}) glDeleteVertexArrays(1, &array);
  for (GLuint buffer : {faceBuffer_, sphereBuffer_, sphereIndices_}) glDeleteBuffers(1, &buffer);
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
}

// The faces fanned from their first corners, as render/lightmap_image.h and the glb draw them,
// gathered by atlas so that each atlas is one draw call.
void BakedRenderer::buildFaces(const LightmapUvs& uvs) {
  std::vector<std::vector<FaceVertex>> byAtlas(static_cast<std::size_t>(uvs.numAtlases));
  for (std::size_t s = 0; s < scene_->surfaces.size(); ++s) {
    const Surface& surface = scene_->surfaces[s];
    const Material& material = scene_->materials.at(static_cast<std::size_t>(surface.material));
    const Rgb albedo = material.albedo * (material.texture ? material.texture->mean : Rgb::gray(1));
    const Rgb emitted = surface.emittedRadiance.maxComponent() > 0
                            ? surface.emittedRadiance * (material.emissionTexture ? material.emissionTexture->mean : Rgb::gray(1))
                            : Rgb{};
    for (std::size_t f = 0; f < uvs.uv[s].size(); ++f) {
      const std::vector<std::uint32_t> corners = surfaceFace(surface, f);
      std::vector<FaceVertex>& out = byAtlas[uvs.atlas[s][f]];
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        for (std::size_t c : {std::size_t{0}, k, k + 1}) {
          FaceVertex v{};
          put(v.position, surface.vertices[corners[c]]);
          v.lightmapUv[0] = static_cast<float>(uvs.uv[s][f][c].u);
          v.lightmapUv[1] = static_cast<float>(uvs.uv[s][f][c].v);
          put(v.albedo, albedo);
          put(v.emitted, emitted);
          out.push_back(v);
        }
    }
  }
  std::vector<FaceVertex> all;
  atlasRanges_.clear();
  for (const std::vector<FaceVertex>& atlas : byAtlas) {
    atlasRanges_.push_back({static_cast<int>(all.size()), static_cast<int>(atlas.size())});
    all.insert(all.end(), atlas.begin(), atlas.end());
  }
  glBindBuffer(GL_ARRAY_BUFFER, faceBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(all.size() * sizeof(FaceVertex)), all.data(), GL_STATIC_DRAW);
  facesFor_ = &uvs;
}

double BakedRenderer::upload(const LightmapFrame& frame) {
  if (frame.version == uploadedVersion_) return 0;
  const auto start = std::chrono::steady_clock::now();
  if (facesFor_ != frame.uvs.get()) buildFaces(*frame.uvs);
  if (textures_.size() != frame.irradiance.size()) {
    if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
    textures_.assign(frame.irradiance.size(), 0);
    glGenTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  }
  std::vector<float> texels;
  for (std::size_t a = 0; a < frame.irradiance.size(); ++a) {
    const Image& image = frame.irradiance[a];
    texels.resize(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) texels[3 * i + static_cast<std::size_t>(c)] = static_cast<float>(image.pixels[i][c]);
    glBindTexture(GL_TEXTURE_2D, textures_[a]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, image.width, image.height, 0, GL_RGB, GL_FLOAT, texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  uploadedVersion_ = frame.version;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void BakedRenderer::drawLightmapped(const LightmapFrame& frame, const Eigen::Matrix4f& viewProjection, const DisplaySettings& settings) {
  upload(frame);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // the fragment shader culls back faces
  glUseProgram(lightmapProgram_);
  glUniformMatrix4fv(glGetUniformLocation(lightmapProgram_, "viewProjection"), 1, GL_FALSE, viewProjection.data());
  glUniform1i(glGetUniformLocation(lightmapProgram_, "irradiance"), 0);
  setTone(lightmapProgram_, settings);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(faceArray_);
  for (std::size_t a = 0; a < atlasRanges_.size() && a < textures_.size(); ++a) {
    glBindTexture(GL_TEXTURE_2D, textures_[a]);
    glDrawArrays(GL_TRIANGLES, atlasRanges_[a].first, atlasRanges_[a].second);
  }
  glBindVertexArray(0);
}

void BakedRenderer::drawSphere(const ShRgb& irradianceSh, const Vec3& centre, double radius, const Rgb& albedo,
                               const Eigen::Matrix4f& viewProjection, const DisplaySettings& settings) {
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);  // its inside is never seen
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glUseProgram(sphereProgram_);
  glUniformMatrix4fv(glGetUniformLocation(sphereProgram_, "viewProjection"), 1, GL_FALSE, viewProjection.data());
  glUniform3f(glGetUniformLocation(sphereProgram_, "centre"), static_cast<float>(centre.x), static_cast<float>(centre.y), static_cast<float>(centre.z));
  glUniform1f(glGetUniformLocation(sphereProgram_, "radius"), static_cast<float>(radius));
  float sh[3 * kShCoefficients];
  for (int k = 0; k < kShCoefficients; ++k)
    for (int c = 0; c < 3; ++c) sh[3 * k + c] = static_cast<float>(irradianceSh[static_cast<std::size_t>(k)][c]);
  glUniform3fv(glGetUniformLocation(sphereProgram_, "sh"), kShCoefficients, sh);
  glUniform3f(glGetUniformLocation(sphereProgram_, "albedo"), static_cast<float>(albedo.r), static_cast<float>(albedo.g), static_cast<float>(albedo.b));
  setTone(sphereProgram_, settings);
  glBindVertexArray(sphereArray_);
  glDrawElements(GL_TRIANGLES, sphereIndexCount_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glDisable(GL_CULL_FACE);
}

}  // namespace lambert::viewer
