#include "lambert/geometry/ray_caster.h"

#include <cmath>

namespace lambert {

std::size_t RayCaster::counterSlot() {
  static std::atomic<std::size_t> threads{0};
  thread_local const std::size_t slot = threads.fetch_add(1, std::memory_order_relaxed) % kCounterSlots;
  return slot;
}

std::uint64_t RayCaster::raysCast() const {
  std::uint64_t total = 0;
  for (const Counter& counter : raysCast_) total += counter.rays.load(std::memory_order_relaxed);
  return total;
}

void RayCaster::intersect(std::span<const Ray> rays, std::span<std::optional<RayHit>> out) const {
  for (std::size_t i = 0; i < rays.size(); ++i) out[i] = intersect(rays[i]);
}

void RayCaster::occluded(std::span<const Ray> rays, std::span<bool> out) const {
  for (std::size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]);
}

double rayEpsilon(const Mesh& mesh) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& p : mesh.positions) {
    lo = componentMin(lo, p);
    hi = componentMax(hi, p);
  }
  // Single-precision BVH coordinates carry ~1e-7 relative error; stay two orders above it.
  return 1e-5 * length(hi - lo);
}

}  // namespace lambert
