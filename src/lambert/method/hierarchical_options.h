#pragma once
// The hierarchical method's options: the link refinement (hierarchical/links.h) and the
// refine-then-solve passes (hierarchical/method.h). Collected by method/options.h.
#include <cstdint>

namespace lambert {

struct LinkOptions {
  double linkError = 2e-4;     // relative power a link may carry unrefined
  double minElementArea = 0;   // scene units²; 0: the scene's area × 1e-5
  int visibilityRays = 8;      // per link
  bool clusters = true;        // false: start from every pair of faces (no cluster links)
  std::uint64_t seed = 1;
  bool showProgress = false;
  double memoryLimitBytes = 0;  // core/memory.h: refinement stops when its links would not fit
};

struct HierarchicalOptions {
  LinkOptions links;         // link error, minimum element area, visibility rays, clustering
  int refinePasses = 2;      // refine-then-solve cycles in the first solve()
  bool refineAtLights = true;  // split elements at spot-cone and shadow edges first
};

}  // namespace lambert
