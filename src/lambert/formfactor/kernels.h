#pragma once
// Closed-form pieces of the form factor
//   F_ij = 1/A_i ∫_Ai ∫_Aj cosθ_i cosθ_j / (π r²) V(x, y) dA_j dA_i.
#include <array>
#include <span>

#include "lambert/core/sampling.h"
#include "lambert/core/vec3.h"

namespace lambert {

// Differential-to-differential kernel cosθ_x cosθ_y / (π r²), per unit area of y; zero when the
// two points do not face each other. Unbounded as r → 0: the seed-000 estimator's weakness.
double pointToPointKernel(const Vec3& x, const Vec3& xNormal, const Vec3& y, const Vec3& yNormal);

// Unoccluded form factor from a differential area at x (unit normal xNormal) to a planar polygon,
// by Lambert's contour integral (Lambert 1760; Baum, Rushmeier & Winget 1989):
//   F = 1/(2π) Σ_k θ_k (a_k × a_{k+1})/|a_k × a_{k+1}| · n_x,  a_k = unit(v_k − x).
// The polygon is first clipped to the hemisphere above x, and only its front side (counter-
// clockwise winding, polygonNormal) emits toward x. Finite for x arbitrarily close to the polygon,
// so it is exact for adjacent patches where the point kernel blows up.
double pointToPolygonFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon,
                                const Vec3& polygonNormal);

// pointToPolygonFormFactor to 0.13% (KernelTest.FarPolygonsByQuadrature), at a fifth of its cost
// where the polygon is far: wholly above x's tangent plane, x in front of it, and its bounding
// radius under kQuadratureRatio of its centre's distance, Gauss–Legendre quadrature of the point
// kernel (2 × 2 over a quad's parameters, Strang & Fix's 3 points on a triangle: the kernel is
// smooth there, and the error falls as the ratio's 4th power); the contour integral elsewhere.
// For the many sources a final gather or a link's samples see from afar.
inline constexpr double kQuadratureRatio = 0.1;
double pointToPolygonFormFactorFast(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon, const Vec3& polygonNormal);

// ∫ k(x, y) φ_c(y) dA_y over a planar convex polygon of 3 or 4 corners, for each corner c (the
// rest 0), where k is the point-to-point kernel above and φ_c the corner's interpolation weight,
// linear over each fan triangle (0, k, k + 1) as a face is drawn. So Σ_c w_c B_c is the
// irradiance at x from a polygon whose radiosity is interpolated from its corners' B_c, and
// Σ_c w_c is pointToPolygonFormFactor. In closed form but for one 1-D integral (Gauss–Legendre):
// per triangle its factor times φ_c at the kernel-weighted centroid, the first moment by
// boundary integrals in the polygon's plane (Chen & Arvo 2000); x may lie next to the polygon,
// as a room's corner does.
std::array<double, 4> cornerFormFactors(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> polygon,
                                        const Vec3& polygonNormal);

// The part of a convex polygon strictly above the plane through `point` with normal `normal`
// (Sutherland–Hodgman against one plane). Writes at most polygon.size() + 1 vertices to `out`
// and returns how many; fewer than 3 means nothing is above.
std::size_t clipAbovePlane(std::span<const Vec3> polygon, const Vec3& point, const Vec3& normal, Vec3* out);

// Lambert's contour sum for a polygon already clipped to the hemisphere above x.
double contourFormFactor(const Vec3& x, const Vec3& xNormal, std::span<const Vec3> clippedPolygon);

// Centre of the triangle's inscribed circle (where the point-to-point method samples its patches).
Vec3 incenter(const std::array<Vec3, 3>& triangle);

}  // namespace lambert
