#include "lambert/geometry/enclosures.h"

#include <cmath>
#include <map>
#include <utility>

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"
#include "lambert/core/union_find.h"
#include "lambert/geometry/face_contacts.h"

namespace lambert {
namespace {

// Whether a light of the scene reaches the front of x (normal n) unoccluded.
bool seesALight(const Scene& scene, const RayCaster& caster, const Vec3& x, const Vec3& n, double epsilon) {
  const Vec3 origin = x + n * epsilon;
  for (const Light& light : scene.lights) {
    if (light.kind == LightKind::Directional) {
      const Vec3 toward = -normalize(light.direction);
      if (dot(toward, n) > 0 && !caster.occluded(Ray{origin, toward, 0, INFINITY})) return true;
    } else if (light.kind != LightKind::Sky) {  // a sky's light comes through rays that escape
      const Vec3 d = light.position - origin;
      if (dot(d, n) > 0 && !caster.occluded(Ray{origin, d, 0, 1 - 1e-6})) return true;
    }
  }
  return false;
}

}  // namespace

Enclosures findEnclosures(const Mesh& mesh, const RayCaster& caster, const Scene& scene, int raysPerPatch) {
  const std::size_t n = mesh.numPatches();
  Enclosures out;
  out.enclosed.assign(n, 0);
  bool anyTwinned = false;
  for (const Patch& p : mesh.patches) anyTwinned |= p.twinned;
  if (!anyTwinned) return out;
  const double epsilon = rayEpsilon(mesh);
  // A ray that escapes meets light only where the sky or the sun is there to give it: without
  // either, the outside of a closed two-sided room is as dark as the inside of a sphere in it.
  bool lightOutside = false;
  for (const Light& light : scene.lights) lightOutside |= light.kind == LightKind::Sky || light.kind == LightKind::Directional;
  // Per patch: what its rays met (the twinned fronts that join it to their patches) and whether
  // any reached light.
  std::vector<std::vector<std::uint32_t>> met(n);
  std::vector<std::uint8_t> lit(n, 0), escaped(n, 0);
  const auto emits = [&](const Patch& p) { return scene.surfaces[p.surface].emittedRadiance.maxComponent() > 0; };
  const FaceContacts contacts(mesh, scene, epsilon);
  parallelFor(0, n, [&](std::size_t i) {
    const Patch& patch = mesh.patches[i];
    if (!patch.twinned) return;
    if (emits(patch)) {
      lit[i] = 1;
      return;
    }
    const PatchCorners corners = mesh.corners(i);
    Pcg32 rng(0x5eed5eed, i);
    const std::uint32_t su = rng.nextUint(), sv = rng.nextUint(), du = rng.nextUint(), dv = rng.nextUint();
    for (int k = 0; k < raysPerPatch && !lit[i]; ++k) {
      auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
      const Vec3 x = sampleConvexPolygon(corners, u, v);
      // On a face turned toward it (the floor under a block standing there), x lifted is inside
      // that face's object: its ray would join that inside to this face's side.
      if (contacts.inContact(x, static_cast<std::uint32_t>(i))) continue;
      const Vec3 d = cosineDirection(patch.normal, scrambledZeroTwo(static_cast<std::uint32_t>(k), du, dv));
      const Vec3 origin = x + patch.normal * epsilon;
      const std::optional<RayHit> hit = caster.intersect(Ray{origin, d, 0, INFINITY});
      // A ray that meets a face where another lies on it, turned toward it, has met the contact
      // (from inside a block standing on the floor, the floor lies on the block's bottom, and
      // which of the two a ray meets there is undecided): it joins nothing.
      if (hit && contacts.inContact(origin + d * hit->t, hit->patch)) continue;
      if (!hit) {
        lit[i] = lightOutside;
        escaped[i] = 1;
      } else if (hit->frontFace) {
        const Patch& other = mesh.patches[hit->patch];
        if (!other.twinned || emits(other)) lit[i] = 1;
        else met[i].push_back(hit->patch);
      }
      // A one-sided face's back is black and opaque: nothing comes through it.
    }
  }, 16);
  UnionFind sets(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t j : met[i]) sets.unite(static_cast<std::uint32_t>(i), j);
  std::vector<std::uint8_t> setLit(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (lit[i]) setLit[sets.find(static_cast<std::uint32_t>(i))] = 1;
  // The lights, asked of each set not yet lit, one patch at a time until one sees a light.
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.patches[i].twinned) continue;
    const std::uint32_t r = sets.find(static_cast<std::uint32_t>(i));
    if (setLit[r]) continue;
    if (seesALight(scene, caster, mesh.patches[i].centroid, mesh.patches[i].normal, epsilon)) setLit[r] = 1;
  }
  std::vector<std::uint8_t> setEscapes(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (escaped[i]) setEscapes[sets.find(static_cast<std::uint32_t>(i))] = 1;
  for (std::size_t i = 0; i < n; ++i)
    if (mesh.patches[i].twinned) out.enclosed[i] = !setLit[sets.find(static_cast<std::uint32_t>(i))];
  // Walls lit on both sides: a face and its twin (the same face of the twin surface) lit, in
  // different sets; the set of the two that escapes is their outer side.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> patchOfFace;
  for (std::size_t i = 0; i < n; ++i) patchOfFace.try_emplace({mesh.patches[i].surface, mesh.patches[i].face}, static_cast<std::uint32_t>(i));
  std::vector<std::uint8_t> outerSet(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Patch& p = mesh.patches[i];
    const int twin = scene.surfaces[p.surface].twin;
    if (!p.twinned || twin < 0 || emits(p)) continue;
    const auto other = patchOfFace.find({static_cast<std::uint32_t>(twin), p.face});
    if (other == patchOfFace.end() || emits(mesh.patches[other->second])) continue;
    const std::uint32_t here = sets.find(static_cast<std::uint32_t>(i)), there = sets.find(other->second);
    if (here == there || !setLit[here] || !setLit[there] || setEscapes[here] == setEscapes[there]) continue;
    outerSet[setEscapes[here] ? here : there] = 1;
    out.wallsLitOnBothSides = true;
  }
  out.outerSide.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (mesh.patches[i].twinned) out.outerSide[i] = outerSet[sets.find(static_cast<std::uint32_t>(i))];
  return out;
}

}  // namespace lambert
