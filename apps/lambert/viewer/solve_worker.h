#pragma once
// The viewer's radiosity thread: it owns the engine (engine/radiosity.h), brings the solution up
// to date in small budgets so the picture can follow it frame by frame (progressive
// refinement's display), re-solves warm whenever the lights change, and publishes each state as a
// Snapshot the drawing thread uploads. The engine is only ever touched on this thread.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "lambert/bake/lightmap_updates.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/bake/probes.h"
#include "lambert/core/stats.h"
#include "lambert/engine/radiosity.h"

namespace lambert::viewer {

// Lights the shader draws per pixel; the visibility of each is traced at the mesh corners.
constexpr int kMaxPixelLights = 16;

// One corner of a drawn triangle, as the shader reads it (floats, interleaved).
struct DrawVertex {
  float position[3];
  float normal[3];          // the element's, unit
  float albedo[3];          // ρ of the element
  float indirect[3];        // B less the lights' direct light ρ·E_direct (emitters' light stays), W/m²
  float emitted[3];         // the surface's own emission E, W/m²
  float twinned;            // 1: the element's back is its twin's front (not drawn)
  float visibility[kMaxPixelLights];  // 1 where the light is visible from this corner, else 0
};

// What one update produced, ready to draw: triangles (unindexed), patch edges, and the figures
// the panels show. Immutable once published.
struct Snapshot {
  std::uint64_t version = 0;
  bool flat = false;                  // per-element values (flat shading) or vertex values (Gouraud)
  bool preview = false;               // the scene's faces before the first solution: no light yet
  std::vector<DrawVertex> triangles;  // 3 per triangle; quads as two
  // xyz pairs, the elements' outlines; shared by the snapshots of one mesh
  std::shared_ptr<const std::vector<float>> edges;
  std::vector<Light> lights;          // the lights this solution is for (drawn per pixel)
  Rgb ambient;                        // progressive refinement's ambient term, W/m²
  double maxRadiosity = 0;            // 99th percentile of B's luminance, W/m² (false colour)
  double unshotFraction = 0;          // shoot: unshot power left
  bool converged = false;
  bool settled = false;               // converged, and the vertex values are the final ones
  std::size_t elements = 0;
  long long iterations = 0;           // shots or sweeps so far for these lights
  // The automatic exposure in stops (render/tonemap.h) of a small software image of this
  // solution from the scene's camera: the policy `lambert render` applies to its picture.
  double autoExposureStops = 0;
};

// The scene's faces as they are before any solve (albedo, emitters in their emission), so the
// viewer shows the geometry at once while the engine meshes and computes form factors.
std::shared_ptr<const Snapshot> previewSnapshot(const Scene& scene);

// Seconds on the steady clock, the one time base of the viewer's threads.
double steadyClockSeconds();

// The lights over time: the scene's lights as edited, each turned by its angular velocity for the
// animation's time (light/lights.h: lightAtTime). While playing, time runs with the clock from
// when it was set, so the radiosity thread moves the lights at its own rate, not the frames'.
struct LightAnimation {
  std::vector<Light> base;
  bool playing = false;
  double seconds = 0;  // animation time at `setAt`
  double setAt = 0;    // steadyClockSeconds() when set

  double secondsAt(double clock) const { return playing ? seconds + (clock - setAt) : seconds; }
  std::vector<Light> lightsAt(double clock) const;
  bool operator==(const LightAnimation&) const = default;
};

struct UpdateBudget {
  SolveBudget solve;             // per update, so the picture follows the solve
  // While the lights move, updates start at most this often (0: back to back), leaving the cores
  // to the drawing between them; a display shows no more than its frame rate anyway.
  double maxUpdatesPerSecond = 90;
};

// What the worker bakes from each settled solution: lightmaps over the scene's own faces
// (bake/lightmaps.h; the hierarchical method only, which gathers at points) and a probe volume
// (bake/probes.h). Either can be switched off and on while the viewer runs.
struct BakeSettings {
  bool lightmaps = false;
  LightmapUvOptions uvs;  // the atlases (the viewer's default is smaller than solve's: see view_command.cpp)
  bool probes = false;
  ProbeOptions probeOptions;  // spacing, rays per probe
};

// Lightmaps baked for one set of lights, ready to draw. Immutable once published.
struct LightmapFrame {
  std::uint64_t version = 0;
  std::vector<Light> lights;           // the lights they were baked for
  std::shared_ptr<const LightmapUvs> uvs;  // shared by every frame: the faces' layout never changes
  std::vector<Image> irradiance;       // per atlas: E in W/m² per texel, top row first
  double seconds = 0;                  // baking (or updating) them
};

// A probe volume baked for one set of lights.
struct ProbeFrame {
  std::uint64_t version = 0;
  std::vector<Light> lights;
  ProbeVolume volume;
};

struct WorkerFigures {
  long long updates = 0;         // solve calls that published a snapshot
  double solveSeconds = 0;       // in Radiosity::solve (inject + solve), summed
  double snapshotSeconds = 0;    // vertex values, shadow visibility and draw arrays, summed
  double maxUpdateSeconds = 0;   // the longest solve + snapshot
  long long lightUpdates = 0;    // updates that began with new lights
  double lightUpdateSeconds = 0; // their solve + snapshot, summed
  long long lightmapBakes = 0;   // lightmap frames published (the first bake and every refresh)
  double lightmapSeconds = 0;    // their baking, summed
  long long probeBakes = 0;
  double probeSeconds = 0;
};

class SolveWorker {
 public:
  // Starts the thread: it creates the engine (mesh, BVH, form factors) and solves.
  SolveWorker(Scene scene, RadiosityOptions options, UpdateBudget budget, bool flat, BakeSettings bake = {});
  ~SolveWorker();  // stops and joins
  SolveWorker(const SolveWorker&) = delete;
  SolveWorker& operator=(const SolveWorker&) = delete;

  // The lights to solve for from now on (any thread); the worker takes the latest.
  void setAnimation(LightAnimation animation);
  // Per-element (flat) or per-vertex (Gouraud) values in the next snapshot.
  void setFlat(bool flat);
  // Bake lightmaps, probes, from the next settled solution on (off: no more bakes; the last
  // frames stay available).
  void setBaking(bool lightmaps, bool probes);
  // The newest lightmaps and probes, or null before the first bake.
  std::shared_ptr<const LightmapFrame> latestLightmaps() const;
  std::shared_ptr<const ProbeFrame> latestProbes() const;
  // What the worker is baking now ("" when nothing), for the panel.
  std::string baking() const;

  // The newest snapshot, or null before the first solve step.
  std::shared_ptr<const Snapshot> latest() const;
  // Engine creation or a solve failed: the message, else empty.
  std::string error() const;
  bool ready() const { return ready_.load(); }  // the engine exists
  double secondsSinceStart() const;

  // Stops the thread (waiting for the step in progress) and gives the engine's stats and the
  // worker's figures. Only once.
  Stats finish(WorkerFigures& figures);

 private:
  void run();
  void publish(const Radiosity& engine, const SolveReport& report, bool meshStale, bool visibilityStale, bool gathered);
  // Whether a settled solution for the engine's lights still lacks the lightmaps or probes asked
  // for (under mutex_).
  bool bakeDue() const;
  // Bakes what bakeDue says is missing and publishes it. False on an error (in error_).
  bool bake();
  // The one place where lightmaps follow a new solution: the first a bake over the fixed UVs,
  // then updates from the weights it recorded.
  Result<std::vector<Image>> refreshLightmaps(const SolutionView& view);

  Scene scene_;
  RadiosityOptions options_;
  UpdateBudget budget_;
  std::unique_ptr<Radiosity> engine_;
  double startTime_ = 0;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  LightAnimation animation_;
  bool flat_ = false;
  bool flatChanged_ = false;
  std::shared_ptr<const Snapshot> latest_;
  std::string error_;
  WorkerFigures figures_;
  std::atomic<bool> ready_{false};
  BakeSettings bake_;
  std::shared_ptr<const LightmapUvs> uvs_;  // made at the first bake
  std::unique_ptr<LightmapUpdater> updater_;  // made with the first bake
  std::shared_ptr<const LightmapFrame> lightmaps_;
  std::shared_ptr<const ProbeFrame> probes_;
  std::string baking_;
  std::uint64_t bakeVersion_ = 0;

  // Worker-thread state kept while the drawn mesh stays the same: its corners, outlines and
  // per-vertex emission, and (while the lights stay too) each light's visibility at each corner.
  struct Corner {
    std::uint32_t patch, vertex;
  };
  std::vector<Corner> corners_;
  std::shared_ptr<const std::vector<float>> edges_;
  std::vector<Rgb> emitted_;
  std::vector<float> visibility_;
  long long iterationsForLights_ = 0;
  double autoExposureStops_ = 0;
  double autoExposureAt_ = -1;  // steadyClockSeconds() when it was last measured
  std::uint64_t version_ = 0;
  std::thread thread_;
};

}  // namespace lambert::viewer
