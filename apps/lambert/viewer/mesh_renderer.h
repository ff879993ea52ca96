#pragma once
// Draws a Snapshot with OpenGL 3.3 core: the hybrid picture (the lights' direct light
// per pixel in the fragment shader, shadowed by the visibility traced at the corners, over the
// interpolated radiosity), flat or Gouraud, with patch edges, a false-colour view of B, light
// markers, and the same exposure and sRGB encoding as lambert's own images (render/tonemap.h).
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lambert/core/error.h"
#include "viewer/solve_worker.h"

namespace lambert::viewer {

enum class LightingMode { Both, Direct, Indirect };

struct DisplaySettings {
  LightingMode lighting = LightingMode::Both;
  bool flat = false;
  bool wireframe = false;
  bool falseColour = false;
  bool srgb = true;
  bool ambient = true;       // add progressive refinement's ambient term mid-solve
  double exposure = 0;       // stops: radiance × 2^exposure before encoding
  // Follow each solution's automatic exposure (Snapshot::autoExposureStops) until the user or a
  // script sets one: for scenes that set none, without --exposure.
  bool autoExposure = false;
  bool lightMarkers = true;  // not in screenshots
  // The scene's own faces lit by baked lightmaps (viewer/baked_renderer.h) instead of the
  // solution's elements, once the first lightmaps are baked.
  bool lightmaps = false;
  bool probes = false;       // the probe-lit sphere
};

// Compiles and links a vertex and a fragment shader (full sources, #version line included);
// the error names the program and gives OpenGL's log.
Result<unsigned> linkProgram(const std::string& vertex, const std::string& fragment, const char* name);

class MeshRenderer {
 public:
  // Compiles the shaders; needs a current OpenGL 3.3 core context.
  static Result<std::unique_ptr<MeshRenderer>> create();
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  // Uploads the snapshot's triangles and edges (when it is not the one already uploaded).
  void upload(const Snapshot& snapshot);
  // Draws the uploaded snapshot into the current framebuffer.
  void draw(const Snapshot& snapshot, const Eigen::Matrix4f& viewProjection, const Eigen::Vector3f& eye,
            const DisplaySettings& settings, double metresPerUnit, int selectedLight, double markerSize);
  // The light markers alone (draw() draws them where settings.lightMarkers says), over what is
  // in the framebuffer: for pictures drawn by another renderer.
  void drawLightMarkers(const std::vector<Light>& lights, const Eigen::Matrix4f& viewProjection, int selectedLight, double markerSize);

 private:
  MeshRenderer() = default;
  // The luminaires' candela tables (the shader's candelaTable), rebuilt when a drawn luminaire's
  // photometry or tilt changes.
  void uploadCandelaTable(const std::vector<Light>& lights, int lightCount);
  static constexpr int kCandelaUnit = 3;  // the texture unit the table is bound to
  unsigned candelaTexture_ = 0;
  std::vector<std::pair<const Photometry*, double>> candelaTableKey_;
  std::array<unsigned, kMaxPixelLights + 1> meshPrograms_{};  // by the number of lights drawn per pixel
  unsigned lineProgram_ = 0;
  unsigned meshArray_ = 0, meshBuffer_ = 0, edgeArray_ = 0, edgeBuffer_ = 0, markerArray_ = 0, markerBuffer_ = 0;
  const Snapshot* uploaded_ = nullptr;
  const std::vector<float>* uploadedEdges_ = nullptr;  // outlines change only with the mesh
  int triangleCorners_ = 0, edgeEnds_ = 0;
};

}  // namespace lambert::viewer
