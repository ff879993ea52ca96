#pragma once
// A software z-buffer rasterizer that turns a solved mesh into an image of radiance.
#include <cstdint>
#include <functional>
#include <vector>

#include "lambert/core/image.h"
#include "lambert/core/rgb.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

enum class Shading {
  Gouraud,  // radiosity interpolated from the vertices (area-weighted averages of their patches)
  Flat,     // each patch in its own radiosity: shows the mesh the solution lives on
};

// Radiance (W/(m²·sr)) a light-shading callback adds at a visible, front-facing surface point:
// the direct light of point, spot and directional lights, shaded per sample with shadow rays,
// on top of the interpolated radiosity (which then carries the indirect light only).
// position: the world point seen through the sample centre, on the patch's plane (to rounding);
// patch: index into the mesh rendered (a quad's two fan triangles both give the quad's index).
// Called concurrently from several threads, once per covered front-facing sample.
using DirectRadianceFn = std::function<Rgb(const Vec3& position, std::uint32_t patch)>;

struct RenderOptions {
  int width = 512, height = 512;
  Shading shading = Shading::Gouraud;
  int supersample = 2;                   // samples per pixel per axis, box-filtered down
  DirectRadianceFn directRadiance = {};  // empty: radiosity only
};

// Renders every patch of the mesh as seen by the camera, in radiance L = B/π. Back faces are
// culled (not drawn: the camera sees through the back of a one-sided face, as with back-face
// culling in RenderPark, engines and Blender); the background is black.
// patchRadiosity holds B in W/m², one per patch. With options.directRadiance, every sample that
// sees the front of a patch adds what it returns there before the samples are box-filtered.
Image renderRadiance(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& patchRadiosity,
                     const RenderOptions& options);

// As renderRadiance, but Gouraud-shaded from the given radiosity B (W/m²) at every vertex, one per
// Mesh::positions entry, for meshes whose vertex values are computed elsewhere (an adaptive
// quad-tree renders its finest level with values interpolated from the active level). With
// vertexRadiosity(mesh, patchRadiosity) it gives renderRadiance's Gouraud image exactly.
// Shading::Flat shows each patch in the mean of its corners' values.
Image renderVertexRadiosity(const Camera& camera, const Mesh& mesh, const std::vector<Rgb>& vertexRadiosity,
                            const RenderOptions& options);

// Per patch of the mesh, 1 where renderRadiance and renderVertexRadiosity with these options
// (size, supersampling) would show its front at one sample or more, else 0: the patches whose
// values a picture reads (a Gouraud picture reads their corners' vertex values).
std::vector<std::uint8_t> visiblePatches(const Camera& camera, const Mesh& mesh, const RenderOptions& options);

}  // namespace lambert
