#pragma once
// Every ray query in lambert goes through RayCaster. The Embree backend is the one used for real
// work; the brute-force backend is a plain loop over triangles that tests compare against.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "lambert/core/vec3.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

struct Ray {
  Vec3 origin;
  Vec3 direction;  // need not be unit length; t is measured in multiples of it
  double tMin = 0;
  double tMax = INFINITY;
};

struct RayHit {
  double t = 0;
  std::uint32_t patch = 0;  // index into the Mesh the caster was built from
  bool frontFace = false;   // the ray hit the patch's front (its normal faces the ray origin)
};

class RayCaster {
 public:
  virtual ~RayCaster() = default;

  // Whether anything lies on the ray between tMin and tMax.
  virtual bool occluded(const Ray& ray) const = 0;
  // occluded() for many rays at once; out[i] is set for rays[i].
  virtual void occluded(std::span<const Ray> rays, std::span<bool> out) const;
  // The nearest hit between tMin and tMax, if any.
  virtual std::optional<RayHit> intersect(const Ray& ray) const = 0;
  // intersect() for many rays at once; out[i] is set for rays[i]. Embree traces them as a stream:
  // a point's 256 hemisphere rays took 25% less time than one by one (illuminance_bench), where
  // its coherent-stream mode, for rays of one origin, took 23% more.
  virtual void intersect(std::span<const Ray> rays, std::span<std::optional<RayHit>> out) const;

  // Rays traced since construction (occlusion and intersection together).
  std::uint64_t raysCast() const;

  // The patches that lie inside closed objects (geometry/enclosures.h), one entry per patch: a
  // point whose first surface along its normal is one of these, from either side, is inside such
  // an object, hence covered (isCovered in geometry/coverage.h). Unset, none is.
  void setInsideClosedObjects(std::vector<std::uint8_t> perPatch) { insideClosed_ = std::move(perPatch); }
  bool insideClosedObject(std::uint32_t patch) const { return patch < insideClosed_.size() && insideClosed_[patch] != 0; }
  bool hasClosedObjects() const { return !insideClosed_.empty(); }

 protected:
  // Each thread counts in its own cache line: one shared counter bounced between the cores on
  // every ray cost 8% of a point-illuminance run (perf, illuminance_bench).
  void countRays(std::uint64_t n) const { raysCast_[counterSlot()].rays.fetch_add(n, std::memory_order_relaxed); }

 private:
  struct alignas(64) Counter {
    std::atomic<std::uint64_t> rays{0};
  };
  static constexpr std::size_t kCounterSlots = 16;
  static std::size_t counterSlot();
  mutable std::array<Counter, kCounterSlots> raysCast_;
  std::vector<std::uint8_t> insideClosed_;
};

// Embree 3 BVH over the mesh's patches. Casters copy what they need: the mesh may be moved or
// destroyed afterwards.
std::unique_ptr<RayCaster> makeEmbreeRayCaster(const Mesh& mesh);
// Tests every triangle for every ray; only for checking the fast backend.
std::unique_ptr<RayCaster> makeBruteForceRayCaster(const Mesh& mesh);

// Scene-scale offset for ray endpoints on surfaces, so a ray neither hits the surface it starts
// on nor the one it ends on: a small fraction of the scene's size, well above float precision.
double rayEpsilon(const Mesh& mesh);

}  // namespace lambert
