// The path-traced reference at the vertices of any vertex file: lambert's own (`solve
// --export-vertices`) or another renderer's (RenderPark's, converted by bench/default_method_bench.py),
// so that every solution is measured against the same estimator at its own points.
//
//   vertex_reference --scene cornell --vertices IN.csv --samples 32768 --seed 1 -o OUT.csv [--irradiance] [--sides one]
//
// --irradiance writes the irradiance E (W/m², what a light meter lying on the surface reads) instead
// of the outgoing radiance: bench/accuracy_bench.py holds lambert's meter (`--points`) against it.
// Each vertex is moved onto the nearest point of the tracer's own triangles (every scene face as a
// fan) whose normal agrees with the file's (within 60°); that triangle gives its surface (albedo,
// emission) and normal. A twisted quad's fan (the Cornell box's red wall is 3 mm out of plane)
// lies up to about a millimetre from points another renderer puts on its bilinear surface, so a
// vertex is accepted up to 2e-3 of the scene's diagonal away; one farther from every such triangle
// is refused with its line, as its surface would be a guess. Like
// ReferenceRenderer::vertexRadiance, the point is then moved 1e-4 of the diagonal toward the
// triangle's centroid, into its own surface, so that it is not evaluated exactly on an edge shared
// with a perpendicular surface, where the irradiance jumps; it is shaded with the file's normal (a
// smooth surface's vertex normal, as the solution's vertex values are). The estimate is
// ReferenceRenderer::outgoingRadiance with stream = the vertex's index: deterministic per (seed,
// index), whatever the thread count. OUT has IN's positions and normals with the reference's
// radiance, written atomically (writeVertices), so `lambert compare --radiosity-vertices IN
// --reference-vertices OUT` pairs them vertex by vertex.
//
// --mixed FILE writes, one per line, the indices of the vertices whose albedo is not one value:
// on a textured face (the tracer takes the texture's mean over the face, a solution its mean over
// each element), or as near on faces of different albedo or emission (a board drawn in its wall's
// plane): a vertex value there is a blend (or the face a renderer happens to show).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_common.h"
#include "lambert/core/atomic_file.h"
#include "lambert/core/parallel.h"
#include "lambert/core/timer.h"
#include "lambert/geometry/coverage.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/io/vertices.h"
#include "lambert/light/emission.h"
#include "lambert/mesh/mesh.h"
#include "lambert/reference/reference.h"
#include "lambert/load/scene_file.h"

using namespace lambert;

namespace {

// One triangle of a scene face's fan: non-planar faces (the Cornell box's red wall is twisted by
// 3 mm) are measured against the triangles the tracer itself intersects.
struct Triangle {
  Vec3 a, b, c, normal, centroid;
  std::uint32_t surface = 0, patch = 0;
};

// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closestPoint(const Vec3& p, const Triangle& t) {
  const Vec3 ab = t.b - t.a, ac = t.c - t.a, ap = p - t.a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return t.a;
  const Vec3 bp = p - t.b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return t.b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return t.a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - t.c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return t.c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return t.a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return t.b + (t.c - t.b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denominator = 1 / (va + vb + vc);
  return t.a + ab * (vb * denominator) + ac * (vc * denominator);
}

}  // namespace

int main(int argc, char** argv) {
  std::string sceneName = "cornell", input, output;
  int samples = 32768;
  std::uint64_t seed = 1;
  bool irradiance = false;
  std::string sides = "file", mixedOut;
  CLI::App app{"vertex_reference: the path-traced outgoing radiance at the vertices of a vertex file"};
  app.add_option("--scene", sceneName, "Built-in scene name or scene file")->capture_default_str();
  app.add_option("--vertices", input, "Vertex file (.csv or .ply, lambert's vertex format) whose points are traced")->required();
  app.add_option("--samples", samples, "Hemisphere samples per vertex")->check(CLI::Range(1, 1 << 24))->capture_default_str();
  app.add_option("--seed", seed, "Random seed (another seed gives an independent estimate)")->capture_default_str();
  bench::addSidesOption(app, sides);
  app.add_flag("--irradiance", irradiance,
               "Write the irradiance E in W/m2 (what a light meter on the surface reads; lux = 683 x its luminance) "
               "in the radiance columns instead of the outgoing radiance L");
  app.add_option("-o,--output", output, "Vertex file to write (.csv or .ply)")->required();
  app.add_option("--mixed", mixedOut, "Also write the indices of the vertices lying as near on faces of different albedo (one a line)");
  bench::parseOrExit(app, argc, argv);

  Result<Scene> scene = bench::loadSceneWithSides(sceneName, sides);
  if (!scene) {
    std::fprintf(stderr, "vertex_reference: %s\n", scene.error().message.c_str());
    return 2;
  }
  Result<std::vector<VertexSample>> vertices = readVertices(input);
  if (!vertices) {
    std::fprintf(stderr, "vertex_reference: %s\n", vertices.error().message.c_str());
    return 2;
  }
  const double diagonal = sceneDiagonal(*scene);
  // The tracer's own geometry: every face as a triangle fan.
  const Mesh geometry = subdivideScene(*scene, 2 * diagonal);
  std::vector<Triangle> triangles;
  for (std::size_t p = 0; p < geometry.numPatches(); ++p) {
    const PatchCorners c = geometry.corners(p);
    for (std::size_t k = 1; k + 1 < c.size(); ++k)
      triangles.push_back({c[0], c[k], c[k + 1], geometry.patches[p].normal, (c[0] + c[k] + c[k + 1]) / 3.0, geometry.patches[p].surface,
                           static_cast<std::uint32_t>(p)});
  }

  // Each vertex's point on the nearest triangle that faces its normal, or a refusal naming the
  // first vertex that lies on none: its surface (albedo, emission) would be a guess.
  const double tolerance = 2e-3 * diagonal, nudge = 1e-4 * diagonal;
  std::vector<std::size_t> triangleOf(vertices->size());
  std::vector<Vec3> points(vertices->size());
  std::vector<char> mixed(vertices->size(), 0);
  const std::vector<Rgb> albedo = patchAlbedo(*scene, geometry), emitted = emittedRadiosity(*scene, geometry);
  for (std::size_t v = 0; v < vertices->size(); ++v) {
    const VertexSample& vertex = (*vertices)[v];
    double best = INFINITY;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (dot(triangles[t].normal, vertex.normal) < 0.5) continue;
      const Vec3 q = closestPoint(vertex.position, triangles[t]);
      if (const double d = length(q - vertex.position); d < best) best = d, triangleOf[v] = t, points[v] = q;
    }
    if (!(best <= tolerance)) {
      std::fprintf(stderr,
                   "vertex_reference: %s: vertex %zu (data line %zu) at (%g, %g, %g) lies on no face of '%s' that faces its normal "
                   "(nearest %g, tolerance %g scene units): give the scene the vertices were solved on\n",
                   input.c_str(), v, v + 1, vertex.position.x, vertex.position.y, vertex.position.z, sceneName.c_str(), best,
                   tolerance);
      return 2;
    }
    // Another face as near, of another albedo or emission: a checker's next square, a board drawn
    // in its wall's plane.
    const std::uint32_t mine = triangles[triangleOf[v]].patch;
    // A textured face's albedo varies within it, and the tracer takes its mean over the face.
    const Surface& surface = scene->surfaces[triangles[triangleOf[v]].surface];
    mixed[v] = scene->materials[static_cast<std::size_t>(surface.material)].texture != nullptr;
    for (std::size_t t = 0; t < triangles.size() && !mixed[v]; ++t) {
      const std::uint32_t other = triangles[t].patch;
      if (dot(triangles[t].normal, vertex.normal) < 0.5 || (albedo[other] == albedo[mine] && emitted[other] == emitted[mine])) continue;
      mixed[v] = length(closestPoint(vertex.position, triangles[t]) - vertex.position) <= best + 1e-6 * diagonal;
    }
    const Vec3 inward = triangles[triangleOf[v]].centroid - points[v];
    if (length(inward) > nudge) points[v] = points[v] + normalize(inward) * nudge;
  }
  // A vertex at the foot of an object standing on its surface (the floor at a block's corner) may
  // be moved under the object, where it is dark: such a point is moved the same distance in the
  // first of 16 directions round the vertex, starting from the centroid's, that leaves it open.
  // The solution's value is for the open side (lambert moves its own vertices toward the open
  // leaves, mesh/vertex_radiosity.h), and two of the Cornell box's floor vertices, traced under a
  // block, were 43% of the squared error.
  {
    const std::unique_ptr<RayCaster> caster = makeEmbreeRayCaster(geometry);
    const double epsilon = rayEpsilon(geometry);
    parallelFor(0, points.size(), [&](std::size_t v) {
      const Triangle& t = triangles[triangleOf[v]];
      if (!isCovered(*caster, points[v], t.normal, epsilon)) return;
      const Vec3 origin = closestPoint((*vertices)[v].position, t);
      Vec3 u = points[v] - origin, w;
      if (length(u) > 0) {
        u = normalize(u);
        w = cross(t.normal, u);
      } else {
        orthonormalBasis(t.normal, u, w);
      }
      for (int k = 1; k < 16; ++k) {
        const double angle = 2 * kPi * k / 16;
        const Vec3 candidate = origin + (u * std::cos(angle) + w * std::sin(angle)) * nudge;
        if (!isCovered(*caster, candidate, t.normal, epsilon)) {
          points[v] = candidate;
          return;
        }
      }
    });
  }

  ReferenceOptions options;
  options.vertexSamples = samples;
  options.seed = seed;
  options.showProgress = false;
  ReferenceRenderer tracer(*scene, geometry, options);
  Timer timer;
  std::vector<VertexSample> result = *vertices;
  // Shaded with the file's normal (a smooth surface's vertex normal, as lambert's vertex values
  // and a renderer's smooth shading use it) on the triangle's point and surface.
  parallelFor(0, result.size(), [&](std::size_t v) {
    const Triangle& t = triangles[triangleOf[v]];
    const Vec3 n = normalize((*vertices)[v].normal);
    result[v].radiance = irradiance ? tracer.irradianceAt(points[v], n, t.surface, v) : tracer.outgoingRadiance(points[v], n, t.surface, v);
  });
  if (!mixedOut.empty()) {
    std::string lines;
    for (std::size_t v = 0; v < mixed.size(); ++v)
      if (mixed[v]) lines += std::to_string(v) + "\n";
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(lines.data());
    if (Status written = writeFileAtomically(mixedOut, std::span<const std::uint8_t>(bytes, lines.size())); !written) {
      std::fprintf(stderr, "vertex_reference: %s\n", written.error().message.c_str());
      return 1;
    }
  }
  if (Status written = writeVertices(output, result); !written) {
    std::fprintf(stderr, "vertex_reference: %s\n", written.error().message.c_str());
    return 1;
  }
  std::printf("{\"vertices\": %zu, \"samples\": %d, \"seed\": %llu, \"seconds\": %.3f, \"rays\": %llu}\n", result.size(), samples,
              static_cast<unsigned long long>(seed), timer.seconds(), static_cast<unsigned long long>(tracer.raysCast()));
  return 0;
}
