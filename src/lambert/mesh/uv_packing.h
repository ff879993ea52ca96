#pragma once
// The packing of lightmap_uvs' charts (mesh/uv_charts.h) into square atlases of texels, and the
// smallest texel size at which they fit one. mesh/uv_packing.cpp says how; internal to
// mesh/lightmap_uvs.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lambert/mesh/uv_charts.h"

namespace lambert {

// Where a chart's rectangle went.
struct Placement {
  std::uint32_t atlas = 0;
  int x = 0, y = 0;  // the rectangle's corner (its padding starts here)
  bool rotated = false;
  double scale = 1;  // below 1 for a chart scaled down to fit an atlas
};

// A chart's footprint in whole texels at a texel size: at least one.
int footprint(double extent, double texelSize);

// The orders rectangles are placed in (largest first, by one measure each): the packing that
// fits at the smallest texel size is kept.
enum class PackOrder { ShortSide, Area, LongSide };
constexpr PackOrder kPackOrders[] = {PackOrder::ShortSide, PackOrder::Area, PackOrder::LongSide};

// Packs every chart at `texelSize` into atlases of `size` texels (at most maxAtlases); the
// placements, or false where they do not fit.
bool pack(const std::vector<Chart>& charts, double texelSize, int size, int padding, std::size_t maxAtlases,
          std::vector<Placement>& placements, std::size_t& numAtlases, PackOrder order = PackOrder::ShortSide, bool scaleDown = true);

// The smallest texel size at which the charts fit one atlas of `size` in one of the packing
// orders (bisection on its logarithm, to 0.2%), and that order; 0 when they fit none (too many
// charts for one atlas at any size).
double fittingTexelSize(const std::vector<Chart>& charts, double area, int size, int padding, PackOrder* fittingOrder = nullptr);

}  // namespace lambert
