#pragma once
// The uniform mesh inside the engine: every surface bisected along its longest edges to a
// patch count or an edge length, patches' open fractions measured, and the dense form-factor
// matrix computed once by any method (or read from the .lff cache).
#include "lambert/method/method.h"
#include "lambert/method/options.h"
#include "lambert/method/solve_call.h"
#include "lambert/mesh/vertex_radiosity.h"

namespace lambert {

class UniformMethod final : public Method {
 public:
  // Meshes the scene and computes (or loads) the form factors; an Error, before the matrix is
  // allocated, when it would not fit in the memory the options allow.
  static Result<std::unique_ptr<UniformMethod>> create(const Scene& scene, const RadiosityOptions& options);

  const Mesh& elements() const override { return mesh_; }
  const RayCaster& caster() const override { return *caster_; }
  std::shared_ptr<const Transport> transport() const override { return transport_; }
  Result<bool> refine(const std::vector<Light>&, std::vector<Rgb>&, SolveReport&) override { return false; }
  const Mesh& vertexMesh() const override { return mesh_; }
  std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const override;
  void addStats(Stats& stats) const override { stats.append(stats_); }
  UniformMethod(const Scene& scene, Mesh mesh, double maxEdge, double meshSeconds, const RadiosityOptions& options);
  Status saveCache() override { return Ok{}; }  // the matrix was saved when it was computed

 private:
  Mesh mesh_;
  std::unique_ptr<RayCaster> caster_;
  std::shared_ptr<const Transport> transport_;  // a DenseTransport
  std::unique_ptr<VertexInterpolation> interpolation_;  // the mesh never changes: weights made once
  Stats stats_;
};

}  // namespace lambert
