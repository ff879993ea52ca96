#pragma once
// The inside of closed two-sided objects: faces no light can reach.
//
// A Blender export is two-sided throughout, so every closed object (a sphere, a table top, a
// cabinet) carries a second, inner shell: its faces' twins, facing inward (Surface::twin). No
// light reaches them, but a method that gathers through clusters holding both shells (Smits,
// Arvo & Greenberg 1994: a receiving cluster hands every face in it the same mean) hands them
// half of what the outer faces gather, and the light then goes round inside: a UV sphere's inside
// showed 22% of the room's mean radiance, and its outside only half the indirect light it gets.
//
// Enclosures are found as a connected set: faces are joined by the rays they cast, and a set is
// dark when none of its faces sees a light, an emitter, the outside where a sky or a sun lights it
// (a ray that escapes) or a one-sided face (ordinary geometry, taken as lit). Without a sky or a
// sun, the outer shell of a closed two-sided room is dark too. Only twinned faces are asked, so
// one-sided scenes are untouched; a set is lit if any of its faces is, so one ray from anywhere
// inside a room that finds its lamp lights the whole room. Points of a face lying on another
// face turned toward it cast no ray (geometry/face_contacts.h): lifted, they are inside it.
#include <cstdint>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"
#include "lambert/scene/scene.h"

namespace lambert {

struct Enclosures {
  std::vector<std::uint8_t> enclosed;  // per patch: 1 where a twinned face of a dark enclosure, else 0
  // Per patch, 1 on the outer side of two-sided walls lit on both sides, else 0. A cluster that
  // holds faces of both sides of such walls (a room's inner faces and its outer twins) hands what
  // it gathers to both by their areas, though its links' light reached one side
  // (hierarchical/transport.h, the directional push): with a sky or a sun lighting the outer
  // twins, a closed room lit inside came out 25% dark. The hierarchy keeps the sides apart
  // (hierarchical/element_hierarchy.h). A wall is lit on both sides where a face and its twin
  // are both lit and in different sets; its outer side is the set a ray of which escapes the
  // scene. Faces of no such wall (a two-sided sphere in the open, whose inside is dark) are 0.
  std::vector<std::uint32_t> outerSide;
  bool wallsLitOnBothSides = false;
};

// Per patch of `mesh` (the caster's mesh, one patch per face or finer). `raysPerPatch`
// cosine-distributed rays from stratified points of each twinned patch join it to what they
// meet; the lights are tested by shadow rays from a patch's centroid (point-like lights:
// position; directional: toward the light). The lights are scene.lights: a light moved into a
// closed object later does not light its inside.
Enclosures findEnclosures(const Mesh& mesh, const RayCaster& caster, const Scene& scene, int raysPerPatch = 16);

}  // namespace lambert
