#pragma once
// Options shared by the subcommands that solve and draw a scene, registered on each of them from
// one place, so that every command spells and defaults every option the same way, and turned
// into the library's option structs. An option that the chosen path would not use is refused.
#include <initializer_list>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "lambert/core/communicator.h"
#include "lambert/core/error.h"
#include "lambert/core/image.h"
#include "lambert/core/stats.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/radiosity_settings.h"
#include "lambert/io/gltf_export.h"
#include "lambert/render/solution_image.h"
#include "lambert/scene/scene.h"

namespace lambert::cli {

// Remembers the command its options were registered on, to tell which ones the user gave.
struct GivenOptions {
  const CLI::App* command = nullptr;
  bool given(const std::string& option) const { return command && command->count(option) > 0; }
};

// Which scene, meshed how finely, and the solve's settings (engine/radiosity_settings.h: the
// library's RadiositySettings, the same names and defaults the Python module takes): all that
// `reference` and `info` need to find the solution's vertices, and what the solving commands read.
struct MeshCommandOptions : GivenOptions, RadiositySettings {
  std::string scene = "cornell";
  double metresPerUnit = 0;       // --units for OBJ files; 0: metres
  double creaseAngleDegrees = 20; // --crease-angle for mesh files
  int mgfDivisions = 16;          // --mgf-divisions for MGF files
  std::string includeRoot;        // --include-root: MGF includes confined to this folder
  std::string sides = "file";     // --sides: file (what each material says), one or two
};

struct SolvingOptions : MeshCommandOptions {
  bool json = false;
  bool quiet = false;
};

struct ImageCommandOptions : GivenOptions {
  SolutionImageOptions image;
  double exposure = 0;
};

// --eye, --target, --up, --fov: the camera, in the scene file's own frame and unit
// (render/scene_camera.h), each "X,Y,Z" or degrees.
struct CameraCommandOptions : GivenOptions {
  std::string eye, target, up;
  double fovDegrees = 0;
};

// --export FILE.glb and --bake: the solved scene for Blender and engines (io/gltf_export.h).
struct ExportCommandOptions : GivenOptions {
  std::string glb;
  GltfBake bake = GltfBake::Irradiance;
};

// What --patches and --max-edge are for: sizing the flat method's mesh (giving one chooses the
// flat method), or the dense estimate of `info`.
enum class PatchOptions { FlatMethod, DenseEstimate };
void addMeshOptions(CLI::App& command, MeshCommandOptions& options, PatchOptions role);
void addExportOptions(CLI::App& command, ExportCommandOptions& options);
// Refuses a path that is not .glb, and --bake without --export.
Status checkExportOptions(const ExportCommandOptions& options);
// Writes the .glb when one is asked for (Ok otherwise); COLOR_0 scaled by 2^exposureStops.
Status exportSolution(const ExportCommandOptions& options, const SolutionView& solution, double exposureStops);
void addSolveOptions(CLI::App& command, SolvingOptions& options);
void addImageOptions(CLI::App& command, ImageCommandOptions& options);
void addCameraOptions(CLI::App& command, CameraCommandOptions& options);

// Sets scene.camera to the camera to draw from: --eye/--target/--up/--fov over the scene's own
// camera, or the library's default view where the scene has none (render/scene_camera.h). An
// error for a value that is not a camera.
// Where it came from and where it is (file coordinates) go into the stats.
Status chooseCamera(Scene& scene, const CameraCommandOptions& options, Stats& stats);

// The exposure (stops) an image is written at: --exposure where given, else the scene's own, else
// automatic from the image (render/tonemap.h); how it was chosen goes into the stats.
double imageExposureStops(const GivenOptions& given, double exposureOption, const Scene& scene, const Image& image, Stats& stats);

// The options that only a solve reads (form factors, lights, solver, cache, meshing), for
// commands that may take their solution from a file instead.
const std::initializer_list<const char*>& solveOnlyOptions();

// An error naming the first of `options` that was given, "<option> has no effect: <why>".
Status refuseGiven(const GivenOptions& given, std::initializer_list<const char*> options, const std::string& why);

// The library's options for a solve, or an error naming a given option the solve would not use
// (a method's own setting under another method, adaptive settings on a uniform mesh, …).
Result<RadiosityOptions> radiosityOptions(const Scene& scene, const SolvingOptions& options);
// The vertices `solve` with these options exports (solutionVertexMesh), for the commands that
// trace the reference there without solving themselves (`reference --export-vertices`, `compare
// --radiosity-vertices`). The options are checked as a solve checks them, and with the flat
// method's uniform mesh, whose vertices depend on its size alone, the options that would not
// move them are refused.
Result<Mesh> exportedVertexMesh(const Scene& scene, const SolvingOptions& options);
// The same check for the image options (--lighting on a scene without lights).
Status checkImageOptions(const Scene& scene, const ImageCommandOptions& options);

// The engine for a scene and options: errors (refused options, impossible combinations) are
// printed as "lambert <command>: <why>" and give nothing.
// communicator: a distributed solve's (RadiosityOptions::communicator), else null.
std::unique_ptr<Radiosity> makeEngine(const std::string& command, const Scene& scene, const SolvingOptions& options,
                                      std::shared_ptr<Communicator> communicator = nullptr);

// Images are written by their extension: .png (tone mapped: exposure, sRGB, 8 bits) or .exr
// (linear float radiance, as rendered). checkImagePath refuses other extensions, and --exposure
// with an EXR (it holds radiance, not a display image), before any work is done.
Status checkImagePath(const std::string& path, const GivenOptions& given);
Status writeImageFile(const std::string& path, const Image& image, double exposureStops);

// Starts keeping every warning (each still goes to stderr as it comes), for printStats' JSON.
// main calls it first, before any command runs.
void keepWarnings();

// Prints a command's figures, led by the library's version (lambert_version): JSON with --json,
// with every warning reported so far under "warnings" (what was dropped or clamped, for a script
// to check), else the headline (if any) and a table, unless --quiet.
void printStats(const Stats& stats, bool json, bool quiet, const std::string& headline = "");

// The uniform mesh --patches / --max-edge ask for, or else the scene file's defaults.
UniformMeshOptions uniformMeshOptions(const Scene& scene, const MeshCommandOptions& o);

// The built-in scene or scene file that --scene names, read with --units and --crease-angle;
// else nothing, with the reason on stderr.
std::optional<Scene> findScene(const std::string& command, const MeshCommandOptions& options);
// The same, the error returned instead of printed.
Result<Scene> sceneFor(const MeshCommandOptions& options);

// Prints "lambert <command>: <message>" on stderr and returns exit code 2 (bad input).
int fail(const std::string& command, const std::string& message);

}  // namespace lambert::cli
