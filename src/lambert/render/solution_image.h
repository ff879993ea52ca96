#pragma once
// An image of a solution (method/solution.h) from a camera, the way every command draws one.
//
// Hybrid lighting: the point, spot and directional lights' direct light computed
// per pixel sample with a shadow ray per light (crisp spot edges, hard shadows), over the
// indirect light interpolated from the radiosity solution (B less the injected ρ·E_direct).
// Emissive surfaces stay in the radiosity, since their light is part of B. Radiosity lighting
// draws everything from the solution. Gouraud shading interpolates the view's continuous vertex
// values over its vertex mesh; flat shading shows each element in its own value.
#include <optional>

#include "lambert/core/image.h"
#include "lambert/method/solution.h"
#include "lambert/render/rasterizer.h"

namespace lambert {

enum class Lighting {
  Hybrid,     // lights' direct light per pixel over interpolated indirect radiosity
  Radiosity,  // everything from the interpolated radiosity solution
};

struct SolutionImageOptions {
  int width = 512, height = 512;
  Shading shading = Shading::Gouraud;
  int supersample = 2;  // samples per pixel per axis, box-filtered
  Lighting lighting = Lighting::Hybrid;
  std::optional<Camera> camera;  // the scene's camera when empty
};

// Radiance L in W/(m²·sr) per pixel.
Image renderSolution(const SolutionView& solution, const SolutionImageOptions& options);

// Whether renderSolution draws lights per pixel: hybrid lighting of a solution with a light that
// is not a sky (every one but the skies is drawn per pixel; a sky from the solution: see
// solution_image.cpp).
bool drawsLightsPerPixel(const SolutionView& solution, const SolutionImageOptions& options);

}  // namespace lambert
