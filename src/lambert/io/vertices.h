#pragma once
// Per-vertex export of a solution, for comparing against a reference or another renderer: each
// vertex's position (scene units), the unit normal of its surface, and its outgoing radiance
// L = B/π in W/(m²·sr), linear RGB. CSV (header x,y,z,nx,ny,nz,r,g,b) or ASCII PLY (the same as
// float properties, plus 8-bit sRGB red/green/blue for viewers).
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/core/rgb.h"
#include "lambert/method/solution.h"
#include "lambert/mesh/mesh.h"

namespace lambert {

struct VertexSample {
  Vec3 position;
  Vec3 normal;
  Rgb radiance;  // W/(m²·sr)
};

// Every vertex of mesh with its surface's normal (area-weighted over its patches) and radiance.
std::vector<VertexSample> vertexSamples(const Mesh& mesh, const std::vector<Rgb>& vertexRadiance);
// Every vertex of a solution's vertex mesh with its outgoing radiance.
std::vector<VertexSample> vertexSamples(const SolutionView& solution);

// Chooses the format by extension (.csv or .ply); written atomically.
Status writeVertices(const std::string& path, const std::vector<VertexSample>& vertices);
// Reads what writeVertices wrote; errors name the file and line.
Result<std::vector<VertexSample>> readVertices(const std::string& path);

}  // namespace lambert
