#include "options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <map>
#include <tuple>

#include "lambert/core/text.h"
#include "lambert/core/warning.h"
#include "lambert/io/exr.h"
#include "lambert/io/png.h"
#include "lambert/mesh/mesh.h"
#include "lambert/render/scene_camera.h"
#include "lambert/render/tonemap.h"
#include "lambert/scene/builtin.h"
#include "lambert/load/scene_file.h"
#include "lambert/version.h"

namespace lambert::cli {

namespace {

// A setting's range as the library checks it (engine/radiosity_settings.h), for CLI11, in the
// option's own type (so that a message reads "1 to 255", not "1.000000 to 255.000000").
template <typename T = double>
CLI::Range rangeOf(const char* setting) {
  const SettingRange range = solveSettingRange(setting);
  return CLI::Range(static_cast<T>(range.least), static_cast<T>(range.most));
}

}  // namespace

UniformMeshOptions uniformMeshOptions(const Scene& scene, const MeshCommandOptions& o) {
  return lambert::uniformMeshOptions(scene, o, [&](std::string_view name) { return o.given(std::string(name)); });
}

void addMeshOptions(CLI::App& cmd, MeshCommandOptions& o, PatchOptions role) {
  o.command = &cmd;
  cmd.add_option("--scene", o.scene, "Built-in scene name (see `lambert scenes`) or a scene file (.json, docs/scene-format.md)")->capture_default_str();
  // The default method never reads a patch count, so no default is shown as if it applied.
  const std::string patchesHelp =
      role == PatchOptions::FlatMethod
          ? "Flat method only, and giving it chooses --method flat: target patch count of the uniform mesh (default " +
                std::to_string(o.patches) + ", or the scene file's)"
          : "Target patch count of the uniform mesh the dense estimate is for (default " + std::to_string(o.patches) + ", or the scene file's)";
  auto* patches = cmd.add_option("--patches", o.patches, patchesHelp)->check(rangeOf<std::size_t>("--patches"));
  cmd.add_option("--max-edge", o.maxEdge,
                 role == PatchOptions::FlatMethod
                     ? "Flat method only, and giving it chooses --method flat: longest patch edge in scene units (instead of --patches)"
                     : "Longest patch edge in scene units (instead of --patches)")
      ->check(rangeOf("--max-edge"))
      ->excludes(patches);
  cmd.add_option("--seed", o.seed, "Random seed")->capture_default_str();
  cmd.add_option("--units", o.metresPerUnit, "Unit of an OBJ or PLY file's numbers: m, cm, mm, in or ft (default m)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, double>{{"m", 1}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}, {"ft", 0.3048}}));
  cmd.add_option("--crease-angle", o.creaseAngleDegrees,
                 "Mesh files: neighbouring faces whose normals differ by more are not smoothed (degrees)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd.add_option("--mgf-divisions", o.mgfDivisions, "MGF files: segments per full circle of sph, cyl, cone, ring and torus")
      ->check(CLI::Range(3, 1024))
      ->capture_default_str();
  cmd.add_option("--include-root", o.includeRoot,
                 "MGF files: refuse includes that resolve outside this folder (default: follow them wherever they lead)")
      ->check(CLI::ExistingDirectory);
  cmd.add_option("--sides", o.sides,
                 "Scene files and mesh files: every material one-sided or two-sided, whatever the file says (RenderPark "
                 "forces one side unless told -dont-force-onesided); file: as each material says")
      ->check(CLI::IsMember({"file", "one", "two"}))
      ->capture_default_str();
}

void addSolveOptions(CLI::App& cmd, SolvingOptions& o) {
  addMeshOptions(cmd, o, PatchOptions::FlatMethod);
  // The flat method's own options say so, and that giving one chooses it (radiosityOptions); their
  // defaults are in the text, not shown as the command's defaults, which the default method never reads.
  const std::string flat = "Flat method only, and giving it chooses --method flat: ";
  cmd.add_option("--formfactor", o.formFactor,
                 flat + "form-factor method: mc (area Monte Carlo, the default), point (point to point), hemicube (Cohen & Greenberg) or "
                        "hemisphere (ray-cast)")
      ->transform(CLI::CheckedTransformer(formFactorNames()));
  cmd.add_option("--hemicube-resolution", o.hemicubeResolution,
                 flat + "--formfactor hemicube's pixels along the top face, even (default " + std::to_string(o.hemicubeResolution) + ")")
      ->check(rangeOf<int>("--hemicube-resolution") & CLI::Validator([](std::string& v) { return std::stoi(v) % 2 == 0 ? "" : "must be even"; }, "EVEN"));
  cmd.add_option("--hemisphere-rays", o.hemisphereRays,
                 flat + "--formfactor hemisphere's rays per patch (default " + std::to_string(o.hemisphereRays) + ")")
      ->check(rangeOf<int>("--hemisphere-rays"));
  cmd.add_option("--samples", o.samples, flat + "--formfactor mc's sample pairs per patch pair (default " + std::to_string(o.samples) + ")")
      ->check(rangeOf<int>("--samples"));
  cmd.add_option("--light-samples", o.lightSamples, "Points per element the lights' direct light is averaged over")
      ->check(rangeOf<int>("--light-samples"))
      ->capture_default_str();
  cmd.add_option("--shadow-tolerance", o.shadowTolerance,
                 "Many lights: the share of a point's unoccluded direct light that may go without shadow rays (Ward's adaptive "
                 "shadow testing, docs/photometry.md); the error is at most this share. 0: every light a ray")
      ->check(rangeOf("--shadow-tolerance"))
      ->capture_default_str();
  cmd.add_option("--solver", o.solver,
                 "Solver: gs (Gauss-Seidel) or jacobi; the flat method also direct or shoot (progressive), and naming either "
                 "chooses --method flat")
      ->transform(CLI::CheckedTransformer(solverNames()))
      ->default_str(o.solver == SolverKind::Shooting ? "gs; shoot on the flat method" : "gs");
  cmd.add_option("--tolerance", o.tolerance, "Relative stopping tolerance of iterative solvers")
      ->check(rangeOf("--tolerance"))
      ->capture_default_str();
  cmd.add_option("--max-iterations", o.maxIterations, "Sweep limit (shots per patch for shoot)")
      ->check(rangeOf<int>("--max-iterations"))
      ->capture_default_str();
  cmd.add_option("--cache-dir", o.cacheDir, "Cache directory for form factors and hierarchical links (default $XDG_CACHE_HOME/lambert or ~/.cache/lambert)");
  cmd.add_flag("--no-cache", o.noCache, "Neither read nor write the form-factor or link cache");
  cmd.add_flag("--normalize-rows", o.normalizeRows,
               flat + "divide each row of F by its sum: hides estimation error, adds energy where light should escape");
  std::string flatOnly;
  for (const char* option : flatMethodSettings()) flatOnly += std::string(flatOnly.empty() ? "" : ", ") + option;
  cmd.add_option("--method", o.method,
                 "hierarchical (element trees under clusters, linked by the BF oracle; the default) or flat (a mesh with a dense "
                 "form-factor matrix); without --method, flat where a flat-only option is given (" + flatOnly +
                     "), --solver direct or shoot, or a patch count in the scene file")
      ->transform(CLI::CheckedTransformer(methodNames()))
      ->default_str("hierarchical");
  cmd.add_option("--link-error", o.linkError, "Hierarchical: the share of the scene's power one link may carry unrefined")
      ->check(rangeOf("--link-error"))
      ->capture_default_str();
  cmd.add_option("--min-area", o.minElementArea, "Hierarchical: smallest element area, scene units² (default: scene area × 1e-5)")
      ->check(rangeOf("--min-area"));
  cmd.add_option("--visibility-rays", o.visibilityRays, "Hierarchical: sample pairs per link (a ray each) estimating its visibility, and a cluster link's form factor")
      ->check(rangeOf<int>("--visibility-rays"))
      ->capture_default_str();
  cmd.add_flag("--no-clusters", o.noClusters, "Hierarchical: start from every pair of faces (HSA'91, O(n²) links) instead of clusters");
  cmd.add_option("--refine-passes", o.refinePasses, "Hierarchical: refine-then-solve passes of the first solve")
      ->check(rangeOf<int>("--refine-passes"))
      ->capture_default_str();
  // Sizes in bytes with an optional binary suffix: 512M, 8G, 1.5T.
  cmd.add_option("--memory-limit", o.memoryLimitBytes,
                 "Memory a solve may use, e.g. 8G or 512M (default: the machine's available memory); larger solves are refused")
      ->transform(CLI::AsSizeValue(false))
      ->check(rangeOf("--memory-limit"));
  cmd.add_flag("--adaptive", o.adaptive, flat + "an adaptive quad-tree mesh refined at spot and shadow edges");
  cmd.add_option("--base-edge", o.baseEdge, "With --adaptive only: longest edge of the coarsest cells, scene units (default: diagonal / 6)")
      ->check(rangeOf("--base-edge"));
  cmd.add_option("--max-level", o.maxLevel, "With --adaptive only: deepest refinement level (each halves a cell)")
      ->check(rangeOf<int>("--max-level"))
      ->capture_default_str();
  cmd.add_option("--gradient-threshold", o.gradientThreshold,
                 "With --adaptive only: split cells whose corners' radiosity spans more than this × the mean (0: off)")
      ->check(rangeOf("--gradient-threshold"))
      ->capture_default_str();
  cmd.add_option("--adapt-passes", o.adaptPasses, "With --adaptive only: refine-and-solve passes per solve (per frame in animate)")
      ->check(rangeOf<int>("--adapt-passes"))
      ->capture_default_str();
  cmd.add_flag("--json", o.json, "Print the stats as JSON instead of a table");
  cmd.add_flag("-q,--quiet", o.quiet, "Print nothing on success");
}

void addExportOptions(CLI::App& cmd, ExportCommandOptions& o) {
  o.command = &cmd;
  cmd.add_option("--export", o.glb, "Also write the solved scene as binary glTF (.glb) with the light baked into COLOR_0");
  cmd.add_option("--bake", o.bake,
                 "What COLOR_0 of --export holds: irradiance (H/pi, under the base colour) or radiance (final, over white)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, GltfBake>{{"irradiance", GltfBake::Irradiance}, {"radiance", GltfBake::Radiance}}))
      ->default_str("irradiance");
}

Status checkExportOptions(const ExportCommandOptions& o) {
  if (o.glb.empty()) return refuseGiven(o, {"--bake"}, "it says what --export bakes, and no --export FILE.glb is asked for");
  if (lowercaseExtension(o.glb) != ".glb") return Error{o.glb + ": --export writes binary glTF: give a .glb path"};
  return Ok{};
}

Status exportSolution(const ExportCommandOptions& o, const SolutionView& solution, double exposureStops) {
  if (o.glb.empty()) return Ok{};
  return writeGlb(o.glb, solution, {o.bake, exposureStops});
}

void addImageOptions(CLI::App& cmd, ImageCommandOptions& o) {
  o.command = &cmd;
  cmd.add_option("--width", o.image.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd.add_option("--height", o.image.height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd.add_option("--shading", o.image.shading, "gouraud (interpolated) or flat (one value per patch)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Shading>{{"gouraud", Shading::Gouraud}, {"flat", Shading::Flat}}))
      ->default_str("gouraud");
  cmd.add_option("--lighting", o.image.lighting,
                 "hybrid (lights' direct light per pixel, with shadow rays) or radiosity (all from the solution)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Lighting>{{"hybrid", Lighting::Hybrid}, {"radiosity", Lighting::Radiosity}}))
      ->default_str("hybrid");
  cmd.add_option("--supersample", o.image.supersample, "Samples per pixel along each axis")->check(CLI::Range(1, 8))->capture_default_str();
  cmd.add_option("--exposure", o.exposure, "Exposure in stops (radiance × 2^stops before sRGB)")
      ->default_str("the scene's, else automatic (log-average luminance to middle grey)");
}

void addCameraOptions(CLI::App& cmd, CameraCommandOptions& o) {
  o.command = &cmd;
  cmd.add_option("--eye", o.eye, "Camera position X,Y,Z in the scene file's own coordinates and unit (an MGF file's z-up metres)");
  cmd.add_option("--target", o.target, "Point X,Y,Z the camera looks at (with --eye), scene file coordinates");
  cmd.add_option("--up", o.up, "Camera up direction X,Y,Z in scene file coordinates (default: the file's up axis)");
  cmd.add_option("--fov", o.fovDegrees, "Vertical field of view in degrees (default: the scene camera's, else 40; 60 inside)")
      ->check(CLI::Range(0.0, 180.0));
}

namespace {

// "X,Y,Z" as three finite numbers, or an error naming the option.
Result<Vec3> parseTriple(const std::string& option, const std::string& text) {
  double v[3];
  std::size_t at = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t end = i < 2 ? text.find(',', at) : text.size();
    const std::string part = end == std::string::npos ? "" : text.substr(at, end - at);
    char* stop = nullptr;
    v[i] = part.empty() ? NAN : std::strtod(part.c_str(), &stop);
    if (part.empty() || stop != part.c_str() + part.size() || !std::isfinite(v[i]) || (i == 2 && text.find(',', at) != std::string::npos))
      return Error{option + " '" + text + "': expected X,Y,Z, three finite numbers separated by commas (e.g. " + option + " 0,1.5,-2)"};
    at = end + 1;
  }
  return Vec3{v[0], v[1], v[2]};
}

}  // namespace

Status chooseCamera(Scene& scene, const CameraCommandOptions& o, Stats& stats) {
  CameraRequest request;
  for (auto [option, text, slot] : {std::tuple{"--eye", &o.eye, &request.eye}, std::tuple{"--target", &o.target, &request.target},
                                    std::tuple{"--up", &o.up, &request.up}}) {
    if (!o.given(option)) continue;
    Result<Vec3> v = parseTriple(option, *text);
    if (!v) return v.error();
    *slot = *v;
  }
  if (o.given("--fov")) request.verticalFovDegrees = o.fovDegrees;
  Result<ChosenCamera> chosen = sceneCamera(scene, request);
  if (!chosen) return chosen.error();
  scene.camera = chosen->camera;
  scene.cameraGiven = true;
  auto triple = [](const Vec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "%.6g,%.6g,%.6g", v.x, v.y, v.z);
    return std::string(text);
  };
  const FileFrame& frame = scene.fileFrame;
  stats.add("camera", "camera from", std::string(cameraSourceName(chosen->source)));
  stats.add("camera_eye", "camera eye (file coordinates)", triple(frame.filePoint(scene.camera.eye)));
  stats.add("camera_target", "camera target (file coordinates)", triple(frame.filePoint(scene.camera.target)));
  stats.add("camera_up", "camera up (file coordinates)", triple(frame.filePoint(frame.offset + scene.camera.up)));
  stats.add("camera_fov", "camera vertical field of view", scene.camera.verticalFovDegrees, "degrees");
  return Ok{};
}

double imageExposureStops(const GivenOptions& given, double exposureOption, const Scene& scene, const Image& image, Stats& stats) {
  const double stops = given.given("--exposure") ? exposureOption : sceneExposureStops(scene, image);
  stats.add("exposure_stops", "exposure", stops, "stops");
  stats.add("exposure_source", "exposure from",
            std::string(given.given("--exposure") ? "--exposure" : scene.exposureStops ? "scene" : "automatic (log-average luminance)"));
  return stops;
}

namespace {
WarningCapture& keptWarnings() {
  static WarningCapture capture(WarningCapture::Forward::yes);
  return capture;
}
}  // namespace

void keepWarnings() { keptWarnings(); }

void printStats(const Stats& stats, bool json, bool quiet, const std::string& headline) {
  // Every command's figures say which library made them, so that saved JSON can be compared
  // across versions.
  Stats all;
  all.add("lambert_version", "lambert version", std::string(version()));
  all.append(stats);
  if (json) {
    nlohmann::ordered_json out = all.json();
    out["warnings"] = keptWarnings().messages();
    std::printf("%s\n", out.dump(2).c_str());
  } else if (!quiet) {
    std::printf("%s%s", headline.empty() ? "" : (headline + "\n").c_str(), all.table().c_str());
  }
}

Result<Scene> sceneFor(const MeshCommandOptions& o) {
  if (!isMeshFile(o.scene))
    if (Status s = refuseGiven(o, {"--crease-angle"}, "it is for mesh files (.obj, .ply, .gltf, .glb, .mgf), and '" + o.scene + "' is not one"); !s)
      return s.error();
  if (lowercaseExtension(o.scene) != ".mgf") {
    if (Status s = refuseGiven(o, {"--mgf-divisions"}, "it is for MGF files, and '" + o.scene + "' is not one (a scene file's meshes entry takes \"mgfDivisions\")"); !s)
      return s.error();
    if (Status s = refuseGiven(o, {"--include-root"}, "it confines the includes of MGF files, and '" + o.scene + "' is not one"); !s)
      return s.error();
  }
  const std::vector<std::string> builtins = builtinSceneNames();
  if (o.sides != "file" && std::find(builtins.begin(), builtins.end(), o.scene) != builtins.end())
    return Error{"--sides has no effect: '" + o.scene + "' is a built-in scene, whose sides are part of its definition (export it with "
                 "`lambert scenes --export DIR` to change them)"};
  LoadOptions load;
  if (o.sides != "file") load.twoSided = o.sides == "two";
  load.metresPerUnit = o.metresPerUnit;
  load.creaseAngleDegrees = o.creaseAngleDegrees;
  load.mgfDivisions = o.mgfDivisions;
  load.includeRoot = o.includeRoot;
  Result<Scene> scene = loadScene(o.scene, load);
  if (!scene) return scene.error();
  // Not an error (a scene may be lit later, in the viewer), but a black image surprises.
  if (scene->lights.empty() && !anyEmits(*scene))
    warning(o.scene + ": no light and no emitting surface: the solution is black, and nothing is solved (add a light, or a material that emits)");
  return std::move(*scene);
}

std::optional<Scene> findScene(const std::string& command, const MeshCommandOptions& o) {
  Result<Scene> scene = sceneFor(o);
  if (!scene) {
    fail(command, scene.error().message);
    return std::nullopt;
  }
  return std::move(*scene);
}

Status checkImagePath(const std::string& path, const GivenOptions& given) {
  const std::string extension = lowercaseExtension(path);
  if (extension == ".exr") return refuseGiven(given, {"--exposure"}, "an EXR holds linear radiance, with no tone mapping");
  if (extension != ".png") return Error{path + ": images are .png (tone mapped, 8-bit sRGB) or .exr (linear float radiance)"};
  return Ok{};
}

Status writeImageFile(const std::string& path, const Image& image, double exposureStops) {
  if (lowercaseExtension(path) == ".exr") return writeExr(path, image);
  return writePng(path, image.width, image.height, toSrgb8(image, exposureStops));
}

int fail(const std::string& command, const std::string& message) {
  std::fprintf(stderr, "lambert %s: %s\n", command.c_str(), message.c_str());
  return 2;
}

const std::initializer_list<const char*>& solveOnlyOptions() {
  static const std::initializer_list<const char*> options = {
      "--formfactor", "--samples", "--hemicube-resolution", "--hemisphere-rays", "--light-samples", "--shadow-tolerance", "--solver",
      "--tolerance", "--max-iterations", "--cache-dir", "--no-cache", "--normalize-rows", "--adaptive", "--base-edge",
      "--max-level", "--gradient-threshold", "--adapt-passes", "--method", "--link-error", "--min-area", "--visibility-rays",
      "--no-clusters", "--refine-passes"};
  return options;
}

Status refuseGiven(const GivenOptions& o, std::initializer_list<const char*> options, const std::string& why) {
  for (const char* option : options)
    if (o.given(option)) return Error{std::string(option) + " has no effect: " + why};
  return Ok{};
}

Result<RadiosityOptions> radiosityOptions(const Scene& scene, const SolvingOptions& o) {
  RadiositySettings settings = o;
  settings.showProgress = !o.quiet && !o.json;
  return lambert::radiosityOptions(scene, settings, [&](std::string_view name) { return o.given(std::string(name)); });
}

Result<Mesh> exportedVertexMesh(const Scene& scene, const SolvingOptions& o) {
  Result<RadiosityOptions> options = radiosityOptions(scene, o);
  if (!options) return options.error();
  // --no-cache is not refused: it asks for nothing to be read or written, which the uniform mesh needs.
  if (options->meshing == MeshStrategy::Uniform)
    if (Status s = refuseGiven(o, {"--formfactor", "--samples", "--hemicube-resolution", "--hemisphere-rays", "--normalize-rows",
                                   "--light-samples", "--shadow-tolerance", "--solver", "--tolerance", "--max-iterations", "--cache-dir", "--memory-limit"},
                               "the uniform mesh's vertices depend on --patches or --max-edge alone (--method flat chooses it)");
        !s)
      return s.error();
  return solutionVertexMesh(scene, std::move(*options));
}

Status checkImageOptions(const Scene& scene, const ImageCommandOptions& o) {
  if (scene.lights.empty())
    return refuseGiven(o, {"--lighting"}, "scene '" + scene.name + "' has no point, spot or directional lights to draw per pixel");
  return Ok{};
}

std::unique_ptr<Radiosity> makeEngine(const std::string& command, const Scene& scene, const SolvingOptions& o,
                                      std::shared_ptr<Communicator> communicator) {
  Result<RadiosityOptions> options = radiosityOptions(scene, o);
  if (!options) {
    fail(command, options.error().message);
    return nullptr;
  }
  options->communicator = std::move(communicator);
  Result<std::unique_ptr<Radiosity>> engine = Radiosity::create(scene, std::move(*options));
  if (!engine) {
    fail(command, engine.error().message);
    return nullptr;
  }
  return std::move(*engine);
}

}  // namespace lambert::cli
