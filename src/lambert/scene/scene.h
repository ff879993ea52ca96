#pragma once
// A scene as plain data: what is there, what it is made of, what emits, and where the eye is.
// Geometry is in scene units (metresPerUnit converts them to metres, for power in watts).
#include <string>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"

namespace lambert {

struct Material {
  std::string name;
  Rgb albedo;  // diffuse reflectance ρ per channel, dimensionless, in [0, 1)
};

// A planar convex polygon. Vertices run counter-clockwise seen from the front, so the normal
// cross(v1 - v0, v2 - v0) points to the side that emits and reflects (the back is black and
// opaque). Quads need not be exactly planar: they are split into a triangle fan.
struct Surface {
  std::string name;
  std::vector<Vec3> vertices;
  int material = 0;
  Rgb emittedRadiance;  // L_e in W/(m²·sr); emitted radiosity E = π·L_e in W/m²
};

struct Camera {
  Vec3 eye;
  Vec3 target;           // a point the camera looks at
  Vec3 up{0, 1, 0};
  double verticalFovDegrees = 40;
};

struct Scene {
  std::string name;
  std::vector<Material> materials;
  std::vector<Surface> surfaces;
  Camera camera;
  double metresPerUnit = 1;  // 0.001 for a scene in millimetres
};

// Unit normal of a surface's plane (from its first three vertices' winding).
Vec3 surfaceNormal(const Surface& surface);
// Area of a surface in scene units², as the sum of its fan triangles.
double surfaceArea(const Surface& surface);

}  // namespace lambert
