#include "viewer/mesh_renderer.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include <epoxy/gl.h>

#include "lambert/light/lights.h"

namespace lambert::viewer {
namespace {

// Corner attributes, in DrawVertex's order; the visibility of up to 16 lights as four vec4s, of
// which the program for LIGHT_COUNT lights interpolates only the ones it reads. (Each light
// count gets its own program with the loop unrolled: Mesa's software rasterizer draws the scene
// 2–3 times faster than with one program indexing its varyings by a uniform loop.)
const char* kMeshVertexShader = R"(
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 albedo;
layout(location = 3) in vec3 indirect;
layout(location = 4) in vec3 emitted;
layout(location = 5) in float twinned;
layout(location = 6) in vec4 visibility0;
layout(location = 7) in vec4 visibility1;
layout(location = 8) in vec4 visibility2;
layout(location = 9) in vec4 visibility3;
uniform mat4 viewProjection;
out vec3 vPosition;
flat out vec3 vNormal;
flat out vec3 vAlbedo;
out vec3 vIndirect;
out vec3 vEmitted;
flat out float vTwinned;
out vec4 vVisibility[VISIBILITY_VECTORS];
void main() {
  vPosition = position;
  vNormal = normal;
  vAlbedo = albedo;
  vIndirect = indirect;
  vEmitted = emitted;
  vTwinned = twinned;
  vec4 visibility[4] = vec4[4](visibility0, visibility1, visibility2, visibility3);
  for (int k = 0; k < VISIBILITY_VECTORS; ++k) vVisibility[k] = visibility[k];
  gl_Position = viewProjection * vec4(position, 1.0);
}
)";

// The direct light of lights.cpp (unshadowedIrradiance) per pixel, times the visibility
// interpolated from the corners; B = E + ρ·E_lights; L = B/π; exposure and sRGB as toSrgb8.
const char* kMeshFragmentShader = R"(
const float PI = 3.14159265358979;
in vec3 vPosition;
flat in vec3 vNormal;
flat in vec3 vAlbedo;
in vec3 vIndirect;
in vec3 vEmitted;
flat in float vTwinned;
in vec4 vVisibility[VISIBILITY_VECTORS];
uniform int lightKind[16];        // 0 point, 1 spot, 2 directional, 3 luminaire
uniform vec3 lightPosition[16];
uniform vec3 lightDirection[16];  // unit
uniform vec3 lightPower[16];      // I in W/sr, or E⊥ in W/m² (directional), or a luminaire's colour × multiplier
uniform vec2 lightCone[16];       // cos(outer), cos(inner)
uniform vec3 lightC0[16];         // luminaire: the direction of its C = 0 half plane (unit); lightDirection: its nadir
// Luminaire i's candela × tilt factor / 683 (lights.cpp: luminaireIntensity), resampled every 5°: rows
// i·37 + γ/5, columns C/5 (0..72, the last repeating C = 0), filtered bilinearly.
uniform sampler2D candelaTable;
uniform float metresPerUnit;
uniform int mode;                 // 0 both, 1 direct, 2 indirect
uniform vec3 ambient;             // W/m²
uniform float exposureScale;
uniform bool encodeSrgb;
uniform bool falseColour;
uniform float falseColourMax;     // W/m²
uniform bool preview;
uniform vec3 eye;
out vec4 colour;

vec3 irradiance(int i, vec3 x, vec3 n) {
  if (lightKind[i] == 2) return lightPower[i] * max(-dot(n, lightDirection[i]), 0.0);
  vec3 toLight = lightPosition[i] - x;
  float distanceSquared = dot(toLight, toLight);
  float cosine = dot(n, toLight) * inversesqrt(distanceSquared);
  if (cosine <= 0.0 || distanceSquared <= 0.0) return vec3(0.0);
  float falloff = 1.0;
  if (lightKind[i] == 1) falloff = smoothstep(lightCone[i].x, lightCone[i].y, dot(lightDirection[i], -toLight) * inversesqrt(distanceSquared));
  if (lightKind[i] == 3) {
    vec3 outward = -toLight * inversesqrt(distanceSquared);
    float gamma = degrees(acos(clamp(dot(outward, lightDirection[i]), -1.0, 1.0)));
    vec3 c90 = cross(lightC0[i], lightDirection[i]);
    float c = degrees(atan(dot(outward, c90), dot(outward, lightC0[i])));
    if (c < 0.0) c += 360.0;
    falloff = texture(candelaTable, vec2((c / 5.0 + 0.5) / 73.0, (float(i * 37) + gamma / 5.0 + 0.5) / float(37 * 16))).r;
  }
  return lightPower[i] * (falloff * cosine / (distanceSquared * metresPerUnit * metresPerUnit));
}

// A perceptual ramp from dark blue through green and yellow to red (after matplotlib's turbo).
vec3 ramp(float t) {
  t = clamp(t, 0.0, 1.0);
  vec3 c = vec3(0.19, 0.07, 0.23);
  c = mix(c, vec3(0.16, 0.47, 0.97), smoothstep(0.0, 0.25, t));
  c = mix(c, vec3(0.15, 0.93, 0.56), smoothstep(0.25, 0.5, t));
  c = mix(c, vec3(0.96, 0.82, 0.17), smoothstep(0.5, 0.75, t));
  c = mix(c, vec3(0.48, 0.02, 0.01), smoothstep(0.75, 1.0, t));
  return c;
}

vec3 srgb(vec3 c) {
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  // Back faces are culled, as the software renderer draws (render/rasterizer.h): the camera
  // sees through the back of a one-sided face, and a two-sided face's twin is drawn there.
  if (!gl_FrontFacing) discard;
  vec3 n = normalize(vNormal);
  if (preview) {
    float facing = abs(dot(n, normalize(eye - vPosition)));
    colour = vec4(max(vAlbedo * (0.2 + 0.6 * facing), vEmitted / PI), 1.0);
    return;
  }
  vec3 lights = vec3(0.0);
  for (int i = 0; i < LIGHT_COUNT; ++i) lights += irradiance(i, vPosition, n) * vVisibility[i / 4][i % 4];
  vec3 reflectedDirect = vAlbedo * lights;
  vec3 ambientTerm = vAlbedo * ambient;
  vec3 b = mode == 1 ? vEmitted + reflectedDirect
         : mode == 2 ? vIndirect - vEmitted + ambientTerm
                     : vIndirect + ambientTerm + reflectedDirect;
  if (falseColour) {
    // log scale over three decades below the scene's 99th percentile.
    float luminance = dot(b, vec3(0.2126, 0.7152, 0.0722));
    float t = luminance > 0.0 ? 1.0 + log(luminance / falseColourMax) / log(1000.0) : 0.0;
    colour = vec4(ramp(t), 1.0);
    return;
  }
  vec3 c = clamp(b / PI * exposureScale, 0.0, 1.0);
  colour = vec4(encodeSrgb ? srgb(c) : c, 1.0);
}
)";

const char* kLineVertexShader = R"(
layout(location = 0) in vec3 position;
uniform mat4 viewProjection;
uniform float pointSize;
void main() {
  gl_Position = viewProjection * vec4(position, 1.0);
  gl_PointSize = pointSize;
}
)";

const char* kLineFragmentShader = R"(#version 330 core
uniform vec4 lineColour;
out vec4 colour;
void main() { colour = lineColour; }
)";

Result<unsigned> compile(GLenum kind, const std::string& source, const char* name) {
  GLuint shader = glCreateShader(kind);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    return Error{std::string("OpenGL could not compile the ") + name + " shader: " + log};
  }
  return shader;
}

Result<unsigned> link(const std::string& vertex, const std::string& fragment, const char* name) {
  Result<unsigned> vs = compile(GL_VERTEX_SHADER, vertex, name);
  if (!vs) return vs.error();
  Result<unsigned> fs = compile(GL_FRAGMENT_SHADER, fragment, name);
  if (!fs) return fs.error();
  GLuint program = glCreateProgram();
  glAttachShader(program, *vs);
  glAttachShader(program, *fs);
  glLinkProgram(program);
  glDeleteShader(*vs);
  glDeleteShader(*fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    return Error{std::string("OpenGL could not link the ") + name + " program: " + log};
  }
  return program;
}

void floatAttribute(GLuint location, int size, std::size_t offset) {
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, sizeof(DrawVertex), reinterpret_cast<const void*>(offset));
}

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }


// The mesh program for a number of lights drawn per pixel.
Result<unsigned> meshProgram(int lightCount) {
  const std::string defines = "#version 330 core\n#define LIGHT_COUNT " + std::to_string(lightCount) + "\n#define VISIBILITY_VECTORS " +
                              std::to_string(std::max(1, (lightCount + 3) / 4)) + "\n";
  return link(defines + kMeshVertexShader, defines + kMeshFragmentShader, "mesh");
}

}  // namespace

Result<unsigned> linkProgram(const std::string& vertex, const std::string& fragment, const char* name) { return link(vertex, fragment, name); }

Result<std::unique_ptr<MeshRenderer>> MeshRenderer::create() {
  std::unique_ptr<MeshRenderer> r(new MeshRenderer());
  // Every program up front: a light switched on later must not stall a frame, or fail then.
  for (int lights = 0; lights <= kMaxPixelLights; ++lights) {
    Result<unsigned> mesh = meshProgram(lights);
    if (!mesh) return mesh.error();
    r->meshPrograms_[static_cast<std::size_t>(lights)] = *mesh;
  }
  Result<unsigned> line = link(std::string("#version 330 core\n") + kLineVertexShader, kLineFragmentShader, "line");
  if (!line) return line.error();
  r->lineProgram_ = *line;

  glGenVertexArrays(1, &r->meshArray_);
  glGenBuffers(1, &r->meshBuffer_);
  glBindVertexArray(r->meshArray_);
  glBindBuffer(GL_ARRAY_BUFFER, r->meshBuffer_);
  floatAttribute(0, 3, offsetof(DrawVertex, position));
  floatAttribute(1, 3, offsetof(DrawVertex, normal));
  floatAttribute(2, 3, offsetof(DrawVertex, albedo));
  floatAttribute(3, 3, offsetof(DrawVertex, indirect));
  floatAttribute(4, 3, offsetof(DrawVertex, emitted));
  floatAttribute(5, 1, offsetof(DrawVertex, twinned));
  for (GLuint k = 0; k < 4; ++k) floatAttribute(6 + k, 4, offsetof(DrawVertex, visibility) + k * 4 * sizeof(float));

  for (auto [array, buffer] : {std::pair{&r->edgeArray_, &r->edgeBuffer_}, std::pair{&r->markerArray_, &r->markerBuffer_}}) {
    glGenVertexArrays(1, array);
    glGenBuffers(1, buffer);
    glBindVertexArray(*array);
    glBindBuffer(GL_ARRAY_BUFFER, *buffer);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  }
  glBindVertexArray(0);
  if (GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"OpenGL error " + std::to_string(error) + " while setting up the mesh renderer"};
  return r;
}

MeshRenderer::~MeshRenderer() {
  for (GLuint program : meshPrograms_) glDeleteProgram(program);
  glDeleteProgram(lineProgram_);
  for (GLuint array : {meshArray_, edgeArray_, markerArray_}) glDeleteVertexArrays(1, &array);
  for (GLuint buffer : {meshBuffer_, edgeBuffer_, markerBuffer_}) glDeleteBuffers(1, &buffer);
  if (candelaTexture_ != 0) glDeleteTextures(1, &candelaTexture_);
}

void MeshRenderer::uploadCandelaTable(const std::vector<Light>& lights, int lightCount) {
  // What the table holds: each drawn luminaire's photometry and tilt (the rest is in uniforms).
  std::vector<std::pair<const Photometry*, double>> key(static_cast<std::size_t>(lightCount), {nullptr, 0.0});
  for (int i = 0; i < lightCount; ++i) {
    const Light& light = lights[static_cast<std::size_t>(i)];
    if (light.kind == LightKind::Luminaire) key[static_cast<std::size_t>(i)] = {light.photometry.get(), normalize(light.direction).y};
  }
  if (candelaTexture_ != 0 && key == candelaTableKey_) return;
  candelaTableKey_ = key;
  constexpr int kColumns = 73, kRows = 37;
  std::vector<float> table(static_cast<std::size_t>(kColumns * kRows * kMaxPixelLights), 0.0f);
  for (int i = 0; i < lightCount; ++i) {
    Light light = lights[static_cast<std::size_t>(i)];
    if (light.kind != LightKind::Luminaire || !light.photometry) continue;
    // The candela × tilt / 683 along each (C, γ) of the grid: luminaireIntensity for a white light.
    light.intensity = Rgb::gray(1);
    light.rotationDegrees = 0;
    const LuminaireFrame frame = luminaireFrame(light);
    for (int row = 0; row < kRows; ++row)
      for (int column = 0; column < kColumns; ++column) {
        const double gamma = row * 5 * kPi / 180, c = column * 5 * kPi / 180;
        const Vec3 outward = frame.nadir * std::cos(gamma) + (frame.c0 * std::cos(c) + frame.c90 * std::sin(c)) * std::sin(gamma);
        table[static_cast<std::size_t>((i * kRows + row) * kColumns + column)] = static_cast<float>(luminaireIntensity(light, outward).g);
      }
  }
  if (candelaTexture_ == 0) glGenTextures(1, &candelaTexture_);
  glActiveTexture(GL_TEXTURE0 + kCandelaUnit);
  glBindTexture(GL_TEXTURE_2D, candelaTexture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kColumns, kRows * kMaxPixelLights, 0, GL_RED, GL_FLOAT, table.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glActiveTexture(GL_TEXTURE0);
}

void MeshRenderer::upload(const Snapshot& snapshot) {
  if (uploaded_ == &snapshot) return;
  glBindBuffer(GL_ARRAY_BUFFER, meshBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(snapshot.triangles.size() * sizeof(DrawVertex)), snapshot.triangles.data(),
               GL_STREAM_DRAW);
  if (snapshot.edges.get() != uploadedEdges_) {
    glBindBuffer(GL_ARRAY_BUFFER, edgeBuffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(snapshot.edges->size() * sizeof(float)), snapshot.edges->data(), GL_STATIC_DRAW);
    edgeEnds_ = static_cast<int>(snapshot.edges->size() / 3);
    uploadedEdges_ = snapshot.edges.get();
  }
  triangleCorners_ = static_cast<int>(snapshot.triangles.size());
  uploaded_ = &snapshot;
}

void MeshRenderer::draw(const Snapshot& snapshot, const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eye,
                        const DisplaySettings& settings, double metresPerUnit, int selectedLight, double markerSize) {
  upload(snapshot);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // the fragment shader culls back faces, as the software renderer does
  const int lightCount = static_cast<int>(std::min<std::size_t>(snapshot.lights.size(), kMaxPixelLights));
  const GLuint program = meshPrograms_[static_cast<std::size_t>(lightCount)];
  glUseProgram(program);
  glUniformMatrix4fv(uniform(program, "viewProjection"), 1, GL_FALSE, viewProjection.data());
  int kinds[kMaxPixelLights] = {};
  float positions[3 * kMaxPixelLights] = {}, directions[3 * kMaxPixelLights] = {}, powers[3 * kMaxPixelLights] = {},
        cones[2 * kMaxPixelLights] = {}, c0s[3 * kMaxPixelLights] = {};
  uploadCandelaTable(snapshot.lights, lightCount);
  for (int i = 0; i < lightCount; ++i) {
    const Light& light = snapshot.lights[static_cast<std::size_t>(i)];
    kinds[i] = light.kind == LightKind::Point ? 0 : light.kind == LightKind::Spot ? 1 : light.kind == LightKind::Directional ? 2 : 3;
    if (light.kind == LightKind::Luminaire) {
      const Vec3 c0 = luminaireFrame(light).c0;
      for (int c = 0; c < 3; ++c) c0s[3 * i + c] = static_cast<float>(c0[c]);
    }
    const Vec3 direction = normalize(light.direction);
    const Rgb power = light.kind == LightKind::Directional ? light.irradiance : light.intensity;
    const double outer = light.coneAngleDegrees * kPi / 180, inner = std::fmax(outer - light.falloffDegrees * kPi / 180, 0.0);
    for (int c = 0; c < 3; ++c) {
      positions[3 * i + c] = static_cast<float>(c == 0 ? light.position.x : c == 1 ? light.position.y : light.position.z);
      directions[3 * i + c] = static_cast<float>(c == 0 ? direction.x : c == 1 ? direction.y : direction.z);
      powers[3 * i + c] = static_cast<float>(power[c]);
    }
    cones[2 * i] = static_cast<float>(std::cos(outer));
    cones[2 * i + 1] = static_cast<float>(std::cos(inner));
  }
  glUniform1iv(uniform(program, "lightKind"), kMaxPixelLights, kinds);
  glUniform3fv(uniform(program, "lightPosition"), kMaxPixelLights, positions);
  glUniform3fv(uniform(program, "lightDirection"), kMaxPixelLights, directions);
  glUniform3fv(uniform(program, "lightPower"), kMaxPixelLights, powers);
  glUniform2fv(uniform(program, "lightCone"), kMaxPixelLights, cones);
  glUniform3fv(uniform(program, "lightC0"), kMaxPixelLights, c0s);
  glActiveTexture(GL_TEXTURE0 + kCandelaUnit);
  glBindTexture(GL_TEXTURE_2D, candelaTexture_);
  glUniform1i(uniform(program, "candelaTable"), kCandelaUnit);
  glActiveTexture(GL_TEXTURE0);
  glUniform1f(uniform(program, "metresPerUnit"), static_cast<float>(metresPerUnit));
  glUniform1i(uniform(program, "mode"), static_cast<int>(settings.lighting));
  const Rgb ambient = settings.ambient ? snapshot.ambient : Rgb{};
  glUniform3f(uniform(program, "ambient"), static_cast<float>(ambient.r), static_cast<float>(ambient.g), static_cast<float>(ambient.b));
  glUniform1f(uniform(program, "exposureScale"), static_cast<float>(std::exp2(settings.exposure)));
  glUniform1i(uniform(program, "encodeSrgb"), settings.srgb);
  glUniform1i(uniform(program, "falseColour"), settings.falseColour);
  glUniform1f(uniform(program, "falseColourMax"), static_cast<float>(snapshot.maxRadiosity > 0 ? snapshot.maxRadiosity : 1.0));
  glUniform1i(uniform(program, "preview"), snapshot.preview);
  glUniform3f(uniform(program, "eye"), eye.x(), eye.y(), eye.z());
  glBindVertexArray(meshArray_);
  if (settings.wireframe) {
    // Push the surfaces back a little so the edges drawn on them win the depth test.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
  }
  glDrawArrays(GL_TRIANGLES, 0, triangleCorners_);
  glDisable(GL_POLYGON_OFFSET_FILL);

  glUseProgram(lineProgram_);
  glUniformMatrix4fv(uniform(lineProgram_, "viewProjection"), 1, GL_FALSE, viewProjection.data());
  if (settings.wireframe || snapshot.preview) {
    glUniform4f(uniform(lineProgram_, "lineColour"), 0.05f, 0.05f, 0.05f, 1.0f);
    glBindVertexArray(edgeArray_);
    glDrawArrays(GL_LINES, 0, edgeEnds_);
  }
  if (settings.lightMarkers) drawLightMarkers(snapshot.lights, viewProjection, selectedLight, markerSize);
  glBindVertexArray(0);
}

void MeshRenderer::drawLightMarkers(const std::vector<Light>& lights, const Eigen::Matrix4f& viewProjection, int selectedLight,
                                    double markerSize) {
  if (lights.empty()) return;
  glUseProgram(lineProgram_);
  glUniformMatrix4fv(uniform(lineProgram_, "viewProjection"), 1, GL_FALSE, viewProjection.data());
  // Each point or spot light as a square, a spot also with its axis; the selected one in yellow.
  glEnable(GL_PROGRAM_POINT_SIZE);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(markerArray_);
  glBindBuffer(GL_ARRAY_BUFFER, markerBuffer_);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    if (light.kind == LightKind::Directional || light.kind == LightKind::Sky) continue;
    const Vec3 tip = light.position + normalize(light.direction) * markerSize * 8;
    const float points[6] = {static_cast<float>(light.position.x), static_cast<float>(light.position.y), static_cast<float>(light.position.z),
                             static_cast<float>(tip.x),            static_cast<float>(tip.y),            static_cast<float>(tip.z)};
    glBufferData(GL_ARRAY_BUFFER, sizeof points, points, GL_STREAM_DRAW);
    const bool selected = static_cast<int>(i) == selectedLight;
    glUniform4f(uniform(lineProgram_, "lineColour"), selected ? 1.0f : 0.9f, selected ? 0.85f : 0.9f, selected ? 0.1f : 0.9f, 1.0f);
    glUniform1f(uniform(lineProgram_, "pointSize"), selected ? 12.0f : 8.0f);
    glDrawArrays(GL_POINTS, 0, 1);
    if (light.kind == LightKind::Spot || light.kind == LightKind::Luminaire) glDrawArrays(GL_LINES, 0, 2);  // the axis, the aim
  }
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

}  // namespace lambert::viewer
