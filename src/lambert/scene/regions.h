#pragma once
// From the polygon meshes that files hold (an OBJ group, a glTF primitive) to lambert's surfaces:
// smooth regions of faces (scene/scene.h). Every loader goes through here, so that every format
// gets the same rules:
//   - vertices at exactly the same position are welded (exporters split them for normals and UVs);
//   - degenerate faces (a non-finite coordinate, a repeated vertex, no area) are dropped and
//     counted by kind, and so are duplicates (an earlier face's corners, in the same turning
//     order: coincident patches would count their light twice). A face and its reverse are
//     both kept: that is a two-sided sheet;
//   - a convex face is kept whole (the mesher fans it, which also splits a non-planar quad); a
//     non-convex one is split into triangles by ear clipping in its plane;
//   - faces that share an edge, have the same material and normals within the crease angle
//     (coplanar ones always) are one region: one Surface, meshed conforming across the shared
//     edges and shaded smoothly across them; nothing is shared between regions.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lambert/core/vec3.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct PolygonMesh {
  std::string name;  // regions are named "<name>" (or "<name> N" when it falls into several)
  std::vector<Vec3> positions;
  struct Face {
    std::vector<std::uint32_t> vertices;  // indices into positions, counter-clockwise from the front
    int material = 0;                     // index into Scene::materials
    std::vector<Uv> uvs = {};             // texture coordinates per corner, or none
    std::vector<Uv> lightmapUvs = {};     // lightmap coordinates per corner (glTF TEXCOORD_1), or none
  };
  std::vector<Face> faces;
};

struct RegionOptions {
  double creaseAngleDegrees = 20;  // neighbours whose normals differ by more are not smoothed
};

struct DroppedFaces {
  std::size_t nonFinite = 0, repeatedVertex = 0, noArea = 0, outOfRange = 0;
  std::size_t duplicate = 0;  // the same corners in the same turning order as an earlier face
  std::size_t total() const { return nonFinite + repeatedVertex + noArea + outOfRange + duplicate; }
  void add(const DroppedFaces& other);
  // "3 degenerate faces dropped: 1 with a NaN or infinite coordinate, 2 with no area", or "".
  std::string describe() const;
};

// Appends the mesh's regions to scene.surfaces; emittedRadiance[m] is the radiance of material m's
// surfaces. Returns what was dropped.
DroppedFaces addSmoothRegions(Scene& scene, const PolygonMesh& mesh, const std::vector<Rgb>& emittedRadiance,
                              const RegionOptions& options = {});

// An albedo a file gives, made physical: one of 1 or more (many files say white) is lowered to
// 0.999 with a warning naming `where`, since a surface that reflects everything makes a closed
// room's radiosity infinite.
Rgb boundedAlbedo(Rgb albedo, const std::string& where);

// Ear clipping of a simple polygon (counter-clockwise about `normal`): triangles as index triples
// into the polygon. A convex polygon gives its fan; collinear slivers are left out.
std::vector<std::array<std::uint32_t, 3>> triangulatePolygon(const std::vector<Vec3>& polygon, const Vec3& normal);

}  // namespace lambert
