#pragma once
// The least-squares conformal map of a chart (Lévy, Petitjean, Ray & Maillot 2002, "Least squares
// conformal maps for automatic texture atlas generation"), for mesh/uv_charts. Internal to
// mesh/lightmap_uvs.
#include "lambert/mesh/uv_charts.h"

namespace lambert {

// The least-squares conformal map of the chart's faces (their fan triangles), two far vertices
// pinned. False where the system is singular.
bool conformalMap(const SurfaceGeometry& g, Chart& chart);

}  // namespace lambert
