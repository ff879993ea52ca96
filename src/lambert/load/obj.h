#pragma once
// Wavefront OBJ with its MTL materials (tinyobjloader), as lambert surfaces. What is read:
//   v, f (any polygon; non-convex ones are triangulated, degenerate ones dropped and counted),
//   o / g (each object or group is a named set of smooth regions: scene/regions.h),
//   usemtl with the MTL's Kd → albedo ρ, map_Kd → an albedo texture it multiplies (through the
//   faces' vt, v counted up from the image's bottom row as OBJ does; a missing or unreadable
//   texture file is a warning, the material drawn with its Kd alone, as Blender's importer
//   does), Ke → emitted radiance L_e (W/(m²·sr)), map_Ke → an emission texture it multiplies
//   (sRGB decoded, through the same vt; missing or unreadable: a warning, Ke alone).
// What is not: vn (lambert shades from its own mesh), curves and surfaces. OBJ has no sidedness:
// faces are one-sided, counter-clockwise in front (a scene file's "twoSided" can make them two-sided). Units: OBJ has none; metresPerUnit says what the numbers are
// (metres unless told). A missing MTL is a warning and its materials a default grey. Kd of 1 or
// more (many files say Kd 1 1 1) is lowered to 0.999 with a warning (boundedAlbedo); negative Kd
// or Ke is an error.
#include <string>

#include "lambert/core/error.h"
#include "lambert/scene/regions.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct ObjOptions {
  double metresPerUnit = 1;
  RegionOptions regions;
};

// The scene is named after the file, lit by its emissive materials; it gives no camera
// (cameraGiven is false: render/scene_camera.h chooses the view).
// Warnings (missing MTL, dropped faces, textures, clamped albedo) go through warning().
Result<Scene> readObj(const std::string& path, const ObjOptions& options = {});

// Writes the scene's surfaces as OBJ (one `o` per surface, its faces over its own vertices) with
// an MTL beside it (NAME.mtl: Kd, and Ke where a surface emits), both atomically, numbers in
// their shortest round-trip form. Two-sided surfaces are written once (OBJ has no sidedness: a
// scene file's "twoSided" restores it); textured materials are refused (a bug in the caller).
Status writeObj(const std::string& path, const Scene& scene);

}  // namespace lambert
