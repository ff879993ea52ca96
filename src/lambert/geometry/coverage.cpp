#include "lambert/geometry/coverage.h"

#include "lambert/core/error.h"
#include "lambert/core/parallel.h"
#include "lambert/core/rng.h"
#include "lambert/core/sampling.h"

namespace lambert {

void measureOpenFractions(Mesh& mesh, const RayCaster& caster, int samplesPerPatch) {
  const std::vector<std::uint8_t> all(mesh.numPatches(), 1);
  measureOpenFractions(mesh, caster, all, samplesPerPatch);
}

void measureOpenFractions(Mesh& mesh, const RayCaster& caster, std::span<const std::uint8_t> measure, int samplesPerPatch) {
  LAMBERT_CHECK(measure.size() == mesh.numPatches());
  const double epsilon = rayEpsilon(mesh);
  parallelFor(0, mesh.numPatches(), [&](std::size_t i) {
    if (!measure[i]) return;
    Patch& patch = mesh.patches[i];
    const PatchCorners corners = mesh.corners(i);
    Pcg32 rng(0x0c0ffee, i);
    const std::uint32_t su = rng.nextUint(), sv = rng.nextUint();
    int open = 0;
    for (int k = 0; k < samplesPerPatch; ++k) {
      auto [u, v] = scrambledZeroTwo(static_cast<std::uint32_t>(k), su, sv);
      open += !isCovered(caster, sampleConvexPolygon(corners, u, v), patch.normal, epsilon);
    }
    patch.openFraction = static_cast<double>(open) / samplesPerPatch;
  }, 16);
}

bool isCovered(const RayCaster& caster, const Vec3& x, const Vec3& n, double epsilon) {
  auto hit = caster.intersect(Ray{x + n * epsilon, n, 0, INFINITY});
  return hit && !hit->frontFace;
}

bool isInsideClosedObject(const RayCaster& caster, const Vec3& x, const Vec3& n, double epsilon) {
  if (!caster.hasClosedObjects()) return false;
  auto hit = caster.intersect(Ray{x + n * epsilon, n, 0, INFINITY});
  return hit && caster.insideClosedObject(hit->patch);
}

}  // namespace lambert
