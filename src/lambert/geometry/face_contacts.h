#pragma once
// Faces in contact: a point of one face that lies on another face turned toward it, as the floor
// under a block standing on it lies on the block's bottom, or a frame's back on its wall. Lifted
// off its face by a ray epsilon, such a point is already inside the other object, so a ray from
// it sees that object's inside. Enclosure detection (geometry/enclosures.h) leaves such points
// out: from the floor under a two-sided block resting on it (every Blender export), they joined
// the block's inner shell to the lit room, which then lit the block's inside and, through its
// bottom, the floor under it (the add-on's test: 13% of the lit floor's light there).
//
// The faces are bucketed by plane (the normal to 10⁻⁴, the offset to the tolerance), and each
// plane's faces indexed in a uniform grid of its own; a query looks in the plane facing the
// other way at the same offset, and in the buckets beside it across the offset's rounding.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lambert/core/vec2.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

class FaceContacts {
 public:
  // planeTolerance: how far apart (scene units) two parallel faces may be and still touch. The
  // mesh must outlive this.
  FaceContacts(const Mesh& mesh, const Scene& scene, double planeTolerance);

  // Whether x, a point of patch `self`, lies on a patch of another surface (not self's twin) in
  // self's plane and facing the other way. Only the faces the file gives touch, not the twins
  // made for two-sided ones (Surface::twin, the later of the two): a file's faces face out of
  // their objects, a twin into it, and the floor lying on a slab's top is not inside the slab,
  // though the slab's inner top faces it.
  bool inContact(const Vec3& x, std::uint32_t self) const;

 private:
  struct PlaneKey {
    std::int32_t nx, ny, nz;
    std::int64_t offset;
    bool operator==(const PlaneKey&) const = default;
  };
  struct PlaneKeyHash {
    std::size_t operator()(const PlaneKey& k) const;
  };
  // One bucket's faces, in its plane's frame (u, v), and a uniform grid over them.
  struct Plane {
    Vec3 u, v;
    Vec2 lo;
    double cell = 1;
    std::vector<std::uint32_t> patches;
    std::vector<std::array<Vec2, 4>> corners;  // per entry of patches
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;  // cell → entries
  };
  PlaneKey keyOf(const Vec3& normal, const Vec3& point) const;

  const Mesh& mesh_;
  std::vector<int> twinOf_;  // per surface: Surface::twin
  double tolerance_;
  std::unordered_map<PlaneKey, Plane, PlaneKeyHash> planes_;
};

}  // namespace lambert
