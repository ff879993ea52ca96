#pragma once
// An image of baked lightmaps (bake/lightmaps.h) on the scene's own faces, drawn as a client of
// the exported glb (io/lightmap_export.h) draws it, so that a browser's or an engine's picture of
// the glb can be compared with lambert's, pixel by pixel (tests/real_clients_test.cpp).
//
// Per pixel sample that sees the front of a face: the lightmap coordinates (TEXCOORD_1) and the
// texture coordinates interpolated over the face's fan triangle at the point seen (perspective
// correct), the atlas's irradiance E read there with a GPU's LINEAR filter and CLAMP_TO_EDGE
// (sampleLightmap), and the outgoing radiance of the diffuse surface
//   L = L_e + ρ/π · E,
// ρ the material's albedo times its texture (read through the texture coordinates where the face
// has them, else its mean, as the glb's base colour is) and L_e the surface's emission (times its
// emission texture likewise). Back faces are culled and the background is black, as in
// render/rasterizer.h; nothing else is lit (the lights' direct light is in the lightmaps).
#include "lambert/bake/lightmaps.h"
#include "lambert/core/image.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct LightmapImageOptions {
  int width = 512, height = 512;
  int supersample = 2;  // samples per pixel per axis, box-filtered
};

// The atlas's value at lightmap coordinate uv (glTF's convention: (0, 0) the top-left corner of
// the first texel row; texel (x, y) covers [x, x + 1] × [y, y + 1] / size, its centre at
// (x + ½, y + ½) / size): bilinear between the four nearest texel centres, coordinates past the
// outermost centres reading the edge texels (OpenGL's LINEAR filter with CLAMP_TO_EDGE, what the
// glb's lightmap samplers ask for). A non-finite coordinate reads texel (0, 0).
Rgb sampleLightmap(const Image& atlas, const Uv& uv);

// Radiance L in W/(m²·sr) per pixel of the scene's faces lit by `baked` (which must have been
// baked for this scene: its coordinates parallel to surfaceFaces of every surface), seen by camera.
Image renderLightmapped(const Scene& scene, const BakedLightmaps& baked, const Camera& camera, const LightmapImageOptions& options = {});

}  // namespace lambert
