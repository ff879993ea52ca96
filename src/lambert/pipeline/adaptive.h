#pragma once
// Radiosity on an adaptive quad-tree mesh for moving lights (seed 003). Each update:
//   1. adapts the mesh: a cell is split where a spot's cone edge or a shadow edge crosses it
//      (down to the deepest level), or where its corners' radiosity differs by more than a
//      threshold (one level per update); four sibling leaves are merged back where none of that
//      holds any more, so the mesh stays coarse away from the lights' detail;
//   2. assembles F for the active cells from the master table (new pairs computed, known ones
//      reused, never recomputed);
//   3. injects the lights' direct light and solves, warm-started from the last solution (new
//      cells start from their parent's radiosity, merged ones from their children's average).
// With a cache directory, the master table is read from disk at creation and written back by
// saveTable(), so a later run of the same scene and options computes no pair twice.
#include <memory>
#include <string>
#include <vector>

#include "lambert/core/error.h"
#include "lambert/formfactor/table.h"
#include "lambert/geometry/ray_caster.h"
#include "lambert/light/lights.h"
#include "lambert/mesh/quadtree.h"
#include "lambert/solve/solver.h"

namespace lambert {

struct AdaptiveOptions {
  QuadtreeOptions quadtree;
  FormFactorOptions formFactors;
  DirectLightOptions direct;
  bool refineAtSpotEdges = true;
  bool refineAtShadowEdges = true;
  // Split a leaf whose corner radiosities span more than this × the mean radiosity (luminance);
  // 0 turns the criterion off.
  double gradientThreshold = 0.5;
  bool normalizeRows = false;  // seed 003's row normalisation (see normalizeRows)
  double tolerance = 1e-6;     // Gauss–Seidel, per update
  // Where the master table's file (formfactor-table-<key>.lft, see formFactorTableKey) is read at
  // creation and written by saveTable(); empty: neither.
  std::string cacheDirectory;
};

// What became of the master table's file.
struct AdaptiveTableFile {
  std::string path;             // empty when caching is off
  bool loaded = false;          // a valid file was read at creation …
  std::size_t pairsInFile = 0;  // … holding this many pairs
  bool saved = false;           // saveTable() wrote it …
  std::size_t pairsSaved = 0;   // … with this many
  double loadSeconds = 0, saveSeconds = 0;
  // A file that was rejected, or could not be written; one line per problem, each
  // "<path>: <why>; <what was done about it>".
  std::string warning;
};

struct AdaptiveUpdate {
  int refined = 0;
  int coarsened = 0;
  std::size_t activeNodes = 0;
  std::size_t nodes = 0;             // ever created
  std::uint64_t pairsEstimated = 0;  // this update
  std::uint64_t pairsLoaded = 0;     // this update, from the table's file
  std::uint64_t pairsReused = 0;     // this update
  int iterations = 0;
  double adaptSeconds = 0, formFactorSeconds = 0, injectSeconds = 0, solveSeconds = 0;
};

class AdaptiveRadiosity {
 public:
  // Fails (naming the surface) when the scene has surfaces that are not quads. With
  // options.cacheDirectory, reads the master table's file there; a file that is missing starts
  // the table empty, and one that is damaged, stale or unreadable too, with a warning on stderr
  // (and in tableFile().warning), never a failure.
  static Result<std::unique_ptr<AdaptiveRadiosity>> create(const Scene& scene, const AdaptiveOptions& options);

  AdaptiveUpdate update(const std::vector<Light>& lights);

  const AdaptiveMesh& mesh() const { return mesh_; }
  const RayCaster& caster() const { return *caster_; }
  const FormFactorTable& table() const { return *table_; }
  const AdaptiveTableFile& tableFile() const { return tableFile_; }
  // Writes the master table (every pair known, loaded ones included) to tableFile().path, unless
  // that file already holds exactly these pairs; Ok, doing nothing, when caching is off. A file
  // that cannot be written is reported like a rejected one ("lambert: warning: <path>: <why>; …"
  // on stderr and in tableFile().warning) and returned as the Error; the solution is unaffected.
  Status saveTable();
  const RadiosityProblem& problem() const { return problem_; }
  // Per active node (mesh().activeNodes() order), W/m².
  const std::vector<Rgb>& radiosity() const { return radiosity_; }
  const std::vector<Rgb>& injected() const { return injected_; }
  std::vector<Rgb> indirectRadiosity() const;
  // Albedo of each patch of mesh().fineMesh(), for drawing direct light on it.
  std::vector<Rgb> fineAlbedo() const;

  // Whether a spot's cone edge crosses the cell (some of its corners lit and some not, or the
  // beam's axis landing inside it), and whether a light's shadow edge does.
  static bool crossesSpotEdge(const Light& light, const PatchCorners& corners, const Vec3& normal);
  bool crossesShadowEdge(const Light& light, const PatchCorners& corners, const Vec3& normal) const;

 private:
  AdaptiveRadiosity(const Scene& scene, AdaptiveMesh mesh, const AdaptiveOptions& options);
  bool mustSplit(std::uint32_t node, const std::vector<Light>& lights) const;
  void adapt(std::uint32_t node, const std::vector<Light>& lights, const std::vector<char>& steep, AdaptiveUpdate& update);
  void refineNode(std::uint32_t node, AdaptiveUpdate& update);
  void loadTable();
  void warnAboutTable(const std::string& line);

  Scene scene_;
  AdaptiveOptions options_;
  AdaptiveMesh mesh_;
  Mesh baseMesh_;  // the level-0 cells, for visibility
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<FormFactorTable> table_;
  AdaptiveTableFile tableFile_;
  std::uint64_t tableKey_ = 0;
  bool fileCurrent_ = false;         // the file holds exactly the table as it was when …
  std::uint64_t estimatedAtFile_ = 0;  // … pairsEstimated() was this
  double epsilon_ = 0;
  std::vector<Rgb> nodeRadiosity_;  // last known B per node id, to warm-start from
  std::vector<std::uint32_t> lastActive_;
  RadiosityProblem problem_;
  std::vector<Rgb> radiosity_;
  std::vector<Rgb> injected_;
};

}  // namespace lambert
