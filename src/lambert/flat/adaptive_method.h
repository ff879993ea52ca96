#pragma once
// The adaptive quad-tree inside the engine (quad-tree subdivision at light and shadow edges). Each refine():
//   1. adapts the mesh: a cell is split where a spot's cone edge or a shadow edge crosses it
//      (down to the deepest level), or where its corners' radiosity differs by more than a
//      threshold (one level per refine); four sibling leaves are merged back where none of that
//      holds any more, so the mesh stays coarse away from the lights' detail;
//   2. assembles F for the active cells from the master table (new pairs computed, known ones
//      reused, never recomputed);
//   3. hands the engine a warm start: new cells start from their parent's radiosity, merged ones
//      from their children's area-weighted average.
// With a cache directory the master table is read from disk at creation and written back by
// saveCache(), so a later run of the same scene and options computes no pair twice.
#include <memory>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/method/method.h"
#include "lambert/method/options.h"
#include "lambert/method/solve_call.h"
#include "lambert/flat/table.h"
#include "lambert/light/lights.h"
#include "lambert/flat/quadtree.h"

namespace lambert {

// What became of the master table's file.
struct AdaptiveTableFile {
  std::string path;             // empty when caching is off
  bool loaded = false;          // a valid file was read at creation …
  std::size_t pairsInFile = 0;  // … holding this many pairs
  bool saved = false;           // saveCache() wrote it …
  std::size_t pairsSaved = 0;   // … with this many
  double loadSeconds = 0, saveSeconds = 0;
};

class AdaptiveMethod final : public Method {
 public:
  // Fails (naming the surface) when the scene has surfaces that are not quads, or (naming the
  // method) when the form-factor method estimates whole rows. With options.cacheDirectory, reads
  // the master table's file there; a missing file starts the table empty, and a damaged, stale
  // or unreadable one too, with a warning(), never a failure.
  static Result<std::unique_ptr<AdaptiveMethod>> create(const Scene& scene, const RadiosityOptions& options);

  const Mesh& elements() const override { return activeMesh_; }
  const RayCaster& caster() const override { return *caster_; }
  std::shared_ptr<const Transport> transport() const override { return transport_; }
  Result<bool> refine(const std::vector<Light>& lights, std::vector<Rgb>& radiosity, SolveReport& report) override;
  const Mesh& vertexMesh() const override { return mesh_.fineMesh(); }
  std::vector<Rgb> vertexValues(const std::vector<Rgb>& perElement) const override;
  void addStats(Stats& stats) const override;
  // Writes the master table (every pair known, loaded ones included) unless the file already
  // holds exactly these pairs. A file that cannot be written is a warning() and the Error.
  Status saveCache() override;

  const AdaptiveMesh& mesh() const { return mesh_; }
  const FormFactorTable& table() const { return *table_; }
  const AdaptiveTableFile& tableFile() const { return tableFile_; }

  // Whether a spot's cone edge crosses the cell (some of its corners lit and some not, or the
  // beam's axis landing inside it), and whether a light's shadow edge does.
  static bool crossesSpotEdge(const Light& light, const PatchCorners& corners, const Vec3& normal);
  bool crossesShadowEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) const;

 private:
  AdaptiveMethod(const Scene& scene, AdaptiveMesh mesh, const RadiosityOptions& options);
  bool mustSplit(std::uint32_t node, const std::vector<Light>& lights) const;
  void adapt(std::uint32_t node, const std::vector<Light>& lights, const std::vector<char>& steep, SolveReport& report);
  void refineNode(std::uint32_t node, SolveReport& report);
  std::vector<char> steepLeaves(const std::vector<Rgb>& radiosity) const;
  void loadTable();

  const Scene& scene_;  // the engine's, which owns this strategy
  AdaptiveMeshOptions options_;
  double memoryLimitBytes_ = 0;  // RadiosityOptions::memoryLimitBytes
  FormFactorOptions formFactorOptions_;
  bool normalizeRows_;
  std::size_t rowsBounded_ = 0;  // rows of the last matrix that flat/table.h's boundRowSums scaled
  std::string cacheDirectory_;
  AdaptiveMesh mesh_;
  Mesh baseMesh_;  // the level-0 cells, for visibility
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<FormFactorTable> table_;
  AdaptiveTableFile tableFile_;
  std::uint64_t tableKey_ = 0;
  bool fileCurrent_ = false;           // the file holds exactly the table as it was when …
  std::uint64_t estimatedAtFile_ = 0;  // … pairsEstimated() was this
  double epsilon_ = 0;
  std::vector<Rgb> nodeRadiosity_;  // last known B per node id, to warm-start from
  std::vector<std::uint32_t> lastActive_;
  Mesh activeMesh_;
  std::shared_ptr<const Transport> transport_;  // a DenseTransport over activeMesh_
};

}  // namespace lambert
