// The Python module `lambert` (pybind11): load any scene the CLI loads, solve it with the CLI's
// settings by their names (engine/radiosity_settings.h: link_error=1e-3 is --link-error), move its
// lights, read per-vertex values as NumPy arrays and write the CLI's outputs. Errors are
// lambert.Error carrying the library's message; solves release the GIL. It includes installed
// headers only (the public API, lambert/lambert.h), as a program built against the package would.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "lambert/core/cancel.h"
#include "lambert/core/rgb.h"
#include "lambert/core/warning.h"
#include "lambert/engine/radiosity.h"
#include "lambert/engine/radiosity_settings.h"
#include "lambert/bake/lightmaps.h"
#include "lambert/core/photometric.h"
#include "lambert/design/illuminance.h"
#include "lambert/design/annual_daylight.h"
#include "lambert/design/calculation_grid.h"
#include "lambert/load/epw.h"
#include "lambert/bake/probes.h"
#include "lambert/io/exr.h"
#include "lambert/io/gltf_export.h"
#include "lambert/io/lightmap_export.h"
#include "lambert/io/png.h"
#include "lambert/io/vertices.h"
#include "lambert/render/scene_camera.h"
#include "lambert/render/solution_image.h"
#include "lambert/render/tonemap.h"
#include "lambert/load/scene_file.h"
#include "lambert/version.h"

namespace py = pybind11;
using namespace lambert;

namespace {

py::object& errorType() {
  static py::object type;
  return type;
}

py::object& warningType() {
  static py::object type;
  return type;
}

// The library's warnings (a face a loader dropped, a damaged cache, clipped colours), queued by
// its sink from any thread, and given to Python's warnings module as lambert.Warning when the
// call that raised them returns (with the GIL held).
std::mutex pendingMutex;
std::vector<std::string>& pendingWarnings() {
  static std::vector<std::string> pending;
  return pending;
}

void flushWarnings() {
  std::vector<std::string> messages;
  {
    std::lock_guard<std::mutex> lock(pendingMutex);
    messages.swap(pendingWarnings());
  }
  for (const std::string& message : messages)
    if (PyErr_WarnEx(warningType().ptr(), message.c_str(), 1) != 0) throw py::error_already_set();  // warnings as errors
}

[[noreturn]] void raise(const std::string& message) {
  flushWarnings();
  PyErr_SetString(errorType().ptr(), message.c_str());
  throw py::error_already_set();
}

// Runs work (a long library call) on a thread of its own while this one, without the GIL, looks
// every 50 ms for a signal Python has received (Ctrl-C, which only Python's main thread handles):
// on one it asks the library to cancel (core/cancel.h), waits the moment the work takes to stop,
// and raises what the signal's handler raised (KeyboardInterrupt). The work's own exceptions
// reach the caller as they are; a cancel another call asked for is a lambert.Error.
template <class Work>
auto interruptible(Work&& work) -> decltype(work()) {
  using Value = decltype(work());
  std::packaged_task<Value()> task(std::forward<Work>(work));
  std::future<Value> done = task.get_future();
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker(std::move(task));
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (interrupted) continue;
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        interrupted = true;
        requestCancel();
      }
    }
    worker.join();
  }
  if (interrupted) {
    clearCancel();
    try {
      (void)done.get();  // stopped (Cancelled), or done just before the request: either way dropped
    } catch (...) {
    }
    throw py::error_already_set();  // the handler's exception, set by PyErr_CheckSignals
  }
  try {
    return done.get();
  } catch (const Cancelled&) {
    raise("interrupted: another call in this process was interrupted (Ctrl-C), which stops every long call");
  }
}

template <typename T>
T orRaise(Result<T> result) {
  if (!result) raise(result.error().message);
  return std::move(*result);
}

void orRaise(const Status& status) {
  if (!status) raise(status.error().message);
}

// An (n, 3) float64 array that owns the vector it views: no copy.
py::array_t<double> rows3(std::vector<Rgb>&& values) {
  static_assert(sizeof(Rgb) == 3 * sizeof(double));
  auto* owned = new std::vector<Rgb>(std::move(values));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<Rgb>*>(p); });
  return py::array_t<double>({static_cast<py::ssize_t>(owned->size()), py::ssize_t{3}},
                             {static_cast<py::ssize_t>(sizeof(Rgb)), static_cast<py::ssize_t>(sizeof(double))},
                             reinterpret_cast<const double*>(owned->data()), free);
}

py::array_t<double> rows3(const std::vector<Vec3>& values) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  std::vector<Rgb> copy(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) copy[i] = {values[i].x, values[i].y, values[i].z};
  return rows3(std::move(copy));
}

// An (height, width, 3) float64 array that owns the image's pixels: no copy.
py::array_t<double> pixels(Image&& image) {
  const auto height = static_cast<py::ssize_t>(image.height), width = static_cast<py::ssize_t>(image.width);
  py::array_t<double> flat = rows3(std::move(image.pixels));
  return flat.reshape({height, width, py::ssize_t{3}});
}

// An array of T with the given shape over a vector it owns: no copy.
template <typename T>
py::array_t<T> owned(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* kept = new std::vector<T>(std::move(values));
  py::capsule free(kept, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, kept->data(), free);
}

Vec3 vec3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) raise(std::string(what) + " takes 3 numbers, not " + std::to_string(v.size()));
  return {v[0], v[1], v[2]};
}

// A light's RGB amount (intensity, irradiance): three finite numbers, none negative (a negative
// light would take light away, which no light does).
Rgb lightAmount(const std::vector<double>& v, const char* what) {
  const Vec3 c = vec3(v, what);
  for (const double x : {c.x, c.y, c.z})
    if (!std::isfinite(x) || x < 0) raise(std::string(what) + " takes finite numbers of at least 0, not " + std::to_string(x));
  return {c.x, c.y, c.z};
}

// Whether path ends with the extension (case-insensitive, with its dot).
bool endsWith(const std::string& path, const std::string& extension) {
  if (path.size() < extension.size()) return false;
  return std::equal(extension.begin(), extension.end(), path.end() - static_cast<std::ptrdiff_t>(extension.size()),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); });
}

// A keyword's value as the settings take it.
SettingValue settingValue(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<std::int64_t>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  raise(name + " takes a number, a bool or a string, not " + std::string(py::str(value.get_type().attr("__name__"))));
}

// The engine and what a Python caller reads of it.
class PyRadiosity {
 public:
  PyRadiosity(Scene scene, const py::kwargs& options) {
    RadiositySettings settings;
    std::vector<std::string> given;
    for (const auto& [key, value] : options) {
      std::string name = "--" + py::str(key).cast<std::string>();
      std::replace(name.begin(), name.end(), '_', '-');
      orRaise(setSolveSetting(settings, name, settingValue(name, value)));
      given.push_back(name);
    }
    RadiosityOptions chosen = orRaise(radiosityOptions(scene, settings, [&](std::string_view name) {
      return std::find(given.begin(), given.end(), name) != given.end();
    }));
    options_ = chosen;
    engine_ = orRaise(interruptible([&] { return Radiosity::create(std::move(scene), std::move(chosen)); }));
    flushWarnings();
  }

  // A solve stopped by Ctrl-C leaves the engine part-way (a half-refined hierarchy): the next
  // solve starts from a new engine of the same scene, settings and lights.
  py::dict solve(long long maxShots, int maxSweeps, double maxMilliseconds) {
    if (interrupted_) {
      const std::vector<Light> lights = engine_->solution().lights();
      engine_ = orRaise(interruptible([&] { return Radiosity::create(engine_->solution().scene(), options_); }));
      engine_->setLights(lights);
      interrupted_ = false;
    }
    Result<SolveReport> report = Error{""};
    try {
      report = interruptible([&] { return engine_->solve(SolveBudget{maxShots, maxSweeps, maxMilliseconds}); });
    } catch (...) {
      interrupted_ = true;
      solved_ = false;
      throw;
    }
    if (!report) raise(report.error().message);
    solved_ = true;
    flushWarnings();
    py::dict out;
    out["iterations"] = report->iterations;
    out["converged"] = report->converged;
    out["lights_injected"] = report->lightsInjected;
    out["unshot_fraction"] = report->unshotFraction;
    return out;
  }

  void setLights(const std::vector<Light>& lights) { engine_->setLights(lights); }
  std::vector<Light> lights() const { return engine_->solution().lights(); }
  Scene scene() const { return engine_->solution().scene(); }

  py::array_t<double> vertexPositions() const { return rows3(engine_->solution().vertexMesh().positions); }
  // The final gather at every vertex, the GIL released while it runs (seconds on large scenes;
  // the solution keeps it, so a second call returns at once).
  py::array_t<double> vertexRadiance() const {
    requireSolved("vertex_radiance");
    std::vector<Rgb> values = interruptible([&] { return engine_->solution().vertexRadiance(); });
    flushWarnings();
    return rows3(std::move(values));
  }
  py::array_t<double> vertexValues(const std::string& quantity) const {
    static const std::vector<std::pair<std::string, VertexQuantity>> names{
        {"radiosity", VertexQuantity::Radiosity}, {"indirect_radiosity", VertexQuantity::IndirectRadiosity}, {"irradiance", VertexQuantity::Irradiance}};
    for (const auto& [name, q] : names)
      if (name == quantity) {
        requireSolved("vertex_values");
        std::vector<Rgb> values = interruptible([&] { return engine_->solution().vertexValues(q); });
        flushWarnings();
        return rows3(std::move(values));
      }
    raise("vertex_values takes radiosity, indirect_radiosity or irradiance, not " + quantity);
  }
  // Per element of the solution's mesh (the hierarchy's leaves, or the flat method's patches).
  py::array_t<double> elementValues(const std::string& quantity) const {
    const SolutionView& view = engine_->solution();
    if (quantity == "radiosity") {
      requireSolved("element_values('radiosity')");
      return rows3(std::vector<Rgb>(view.radiosity()));
    }
    if (quantity == "injected") return rows3(std::vector<Rgb>(view.injected()));
    if (quantity == "emitted") return rows3(std::vector<Rgb>(view.emitted()));
    if (quantity == "albedo") return rows3(std::vector<Rgb>(view.albedo()));
    raise("element_values takes radiosity, injected, emitted or albedo, not " + quantity);
  }
  py::dict elements() const {
    const Mesh& mesh = engine_->solution().mesh();
    std::vector<Vec3> centroids, normals;
    std::vector<double> areas, openFractions;
    std::vector<std::uint32_t> surfaces;
    for (const Patch& p : mesh.patches) {
      centroids.push_back(p.centroid), normals.push_back(p.normal), areas.push_back(p.area), surfaces.push_back(p.surface);
      openFractions.push_back(p.openFraction);
    }
    py::dict out;
    out["centroid"] = rows3(centroids);
    out["normal"] = rows3(normals);
    out["area"] = owned(std::move(areas), {static_cast<py::ssize_t>(mesh.numPatches())});
    out["surface"] = owned(std::move(surfaces), {static_cast<py::ssize_t>(mesh.numPatches())});
    out["open_fraction"] = owned(std::move(openFractions), {static_cast<py::ssize_t>(mesh.numPatches())});
    return out;
  }

  // Illuminance at points (x, y, z, nx, ny, nz rows, scene frame and units), as `--points`:
  // an (n, 3) array of E_direct, E_indirect and E in lux.
  py::array_t<double> illuminance(const py::array_t<double, py::array::c_style | py::array::forcecast>& points, int indirectRays) const {
    if (points.ndim() != 2 || points.shape(1) != 6) raise("illuminance takes an (n, 6) array of x, y, z, nx, ny, nz");
    requireSolved("illuminance");
    std::vector<CalculationPoint> at(static_cast<std::size_t>(points.shape(0)));
    const auto rows = points.unchecked<2>();
    for (std::size_t i = 0; i < at.size(); ++i)
      at[i] = {{rows(i, 0), rows(i, 1), rows(i, 2)}, {rows(i, 3), rows(i, 4), rows(i, 5)}};
    IlluminanceOptions options;
    options.indirectRays = indirectRays;
    Result<std::vector<PointIrradiance>> measured = interruptible([&] {
      const IlluminanceMeter meter(engine_->solution(), options);
      return meter.measure(at);
    });
    if (!measured) raise(measured.error().message);
    std::vector<Rgb> lux;
    for (const PointIrradiance& e : *measured)
      lux.push_back({illuminanceLux(e.direct), illuminanceLux(e.indirect), illuminanceLux(e.total())});
    flushWarnings();
    return rows3(std::move(lux));
  }

  py::array_t<std::uint32_t> triangles() const {
    const Mesh& mesh = engine_->solution().vertexMesh();
    std::vector<std::uint32_t> indices;
    for (const Patch& p : mesh.patches)
      for (std::uint32_t k = 1; k + 1 < p.numCorners; ++k) indices.insert(indices.end(), {p.vertices[0], p.vertices[k], p.vertices[k + 1]});
    py::array_t<std::uint32_t> out({static_cast<py::ssize_t>(indices.size() / 3), py::ssize_t{3}});
    std::copy(indices.begin(), indices.end(), out.mutable_data());
    return out;
  }
  py::array_t<std::uint32_t> triangleSurfaces() const {
    const Mesh& mesh = engine_->solution().vertexMesh();
    std::vector<std::uint32_t> surfaces;
    for (const Patch& p : mesh.patches)
      for (std::uint32_t k = 1; k + 1 < p.numCorners; ++k) surfaces.push_back(p.surface);
    const auto count = static_cast<py::ssize_t>(surfaces.size());
    return owned(std::move(surfaces), {count});
  }

  // The CLI's --json figures; its yes/no answers (converged, …) as Python's True and False, as
  // solve() gives them.
  py::dict stats() const {
    py::dict out;
    const Stats stats = engine_->stats();
    for (const Stats::Entry& e : stats.entries())
      std::visit([&](const auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::string>) {
          if (v == "yes" || v == "no") {
            out[py::str(e.key)] = py::bool_(v == "yes");
            return;
          }
        }
        out[py::str(e.key)] = v;
      }, e.value);
    return out;
  }

  void writeGlb(const std::string& path, const std::string& bake, double exposureStops) const {
    GltfExportOptions options;
    if (bake == "irradiance") options.bake = GltfBake::Irradiance;
    else if (bake == "radiance") options.bake = GltfBake::Radiance;
    else raise("bake takes irradiance or radiance, not " + bake);
    if (!endsWith(path, ".glb")) raise("write_glb: " + path + ": it writes binary glTF; give a path ending in .glb");
    requireSolved("write_glb");
    options.exposureStops = exposureStops;
    orRaise(interruptible([&] { return lambert::writeGlb(path, engine_->solution(), options); }));
    flushWarnings();
  }
  void writeVertices(const std::string& path) const {
    requireSolved("write_vertices");
    orRaise(interruptible([&] { return lambert::writeVertices(path, vertexSamples(engine_->solution())); }));
    flushWarnings();
  }

  // The solution drawn from the scene's camera (else lambert's default view): radiance per pixel,
  // written as .png (tone mapped at `exposure` stops, or the scene's / automatic) or .exr (linear)
  // where a path is given.
  py::array_t<double> render(const std::string& path, int width, int height, std::optional<double> exposure,
                             std::optional<std::vector<double>> eye, std::optional<std::vector<double>> target,
                             std::optional<std::vector<double>> up, std::optional<double> fov) const {
    if (width < 1 || width > 16384 || height < 1 || height > 16384) raise("render: width and height must lie in [1, 16384]");
    if (!path.empty() && !endsWith(path, ".png") && !endsWith(path, ".exr"))
      raise("render: " + path + ": images are .png (tone mapped, 8-bit sRGB) or .exr (linear float radiance)");
    requireSolved("render");
    const SolutionView& view = engine_->solution();
    SolutionImageOptions options;
    options.width = width, options.height = height;
    // The camera asked for, in the scene's frame as every array here (the library's request is in
    // the file's frame, as the CLI's --eye: an MGF file's z-up).
    if (eye.has_value() != target.has_value()) raise("render: eye and target are given together");
    const FileFrame& frame = view.scene().fileFrame;
    CameraRequest request;
    if (eye) request.eye = frame.filePoint(vec3(*eye, "eye")), request.target = frame.filePoint(vec3(*target, "target"));
    if (up) request.up = frame.filePoint(frame.offset + vec3(*up, "up")) - frame.filePoint(frame.offset);
    if (fov) request.verticalFovDegrees = *fov;
    options.camera = orRaise(sceneCamera(view.scene(), request)).camera;
    Image image = interruptible([&] { return renderSolution(view, options); });
    if (endsWith(path, ".exr")) {
      orRaise(writeExr(path, image));
    } else if (!path.empty()) {
      const double stops = exposure ? *exposure : sceneExposureStops(view.scene(), image);
      orRaise(writePng(path, image.width, image.height, toSrgb8(image, stops)));
    }
    flushWarnings();
    return pixels(std::move(image));
  }

  // Lightmaps of the solution (hierarchical method): per atlas the irradiance E, W/m², as an
  // (size, size, 3) array and which texels a face covers; written with the scene's mesh as a .glb
  // with its RGBM lightmaps and their EXR files (as `lambert solve --lightmaps --export`) where a path is given.
  py::dict bakeLightmaps(const std::string& glbPath, double texelSize, int atlasSize, int padding, int step, double tolerance) const {
    LightmapBakeOptions options;
    if (!(texelSize >= 0)) raise("bake_lightmaps: texel_size must be 0 (automatic) or positive metres");
    options.uvs.texelSize = texelSize / engine_->solution().scene().metresPerUnit;  // metres, as --texel-size
    options.uvs.atlasSize = atlasSize;
    options.uvs.paddingTexels = padding;
    options.sampling.coarsestStep = step;
    options.sampling.tolerance = tolerance;
    if (!(tolerance >= 0 && tolerance <= 1)) raise("bake_lightmaps: tolerance must lie in [0, 1]");
    if (!glbPath.empty() && !endsWith(glbPath, ".glb"))
      raise("bake_lightmaps: " + glbPath + ": it writes the scene with its lightmaps as binary glTF (with .exr and RGBM .png "
            "atlases beside it); give a path ending in .glb");
    requireSolved("bake_lightmaps");
    options.showProgress = false;
    Result<BakedLightmaps> baked = interruptible([&] { return lambert::bakeLightmaps(engine_->solution(), options); });
    if (!baked) raise(baked.error().message);
    if (!glbPath.empty())
      orRaise(interruptible([&] { return writeLightmaps(glbPath, engine_->solution().scene(), *baked); }));
    py::list irradiance, covered;
    for (Image& atlas : baked->irradiance) irradiance.append(pixels(std::move(atlas)));
    for (std::vector<std::uint8_t>& mask : baked->covered) {
      const auto side = static_cast<py::ssize_t>(std::llround(std::sqrt(static_cast<double>(mask.size()))));
      covered.append(owned(std::move(mask), {side, side}));
    }
    py::dict out;
    out["irradiance"] = irradiance;
    out["covered"] = covered;
    out["texels_baked"] = baked->texelsBaked;
    out["texels_gathered"] = baked->texelsGathered;
    flushWarnings();
    return out;
  }

  // An L2 spherical-harmonic irradiance volume over the scene's box: coefficients as a
  // (nz, ny, nx, 9, 3) float32 array (W/m²), valid as (nz, ny, nx) bool, origin and spacing in
  // scene units; written as lambert's probe file where a path is given.
  py::dict bakeProbes(const std::string& path, double spacing, int raysPerProbe) const {
    requireSolved("bake_probes");
    ProbeOptions options;
    options.spacing = spacing;
    options.raysPerProbe = raysPerProbe;
    options.showProgress = false;
    Result<ProbeVolume> volume = interruptible([&] { return lambert::bakeProbes(engine_->solution(), options); });
    if (!volume) raise(volume.error().message);
    if (!path.empty()) orRaise(writeProbes(path, *volume));
    const auto [nx, ny, nz] = volume->dims;
    const std::vector<py::ssize_t> grid{static_cast<py::ssize_t>(nz), static_cast<py::ssize_t>(ny), static_cast<py::ssize_t>(nx)};
    py::dict out;
    out["origin"] = std::vector<double>{volume->origin.x, volume->origin.y, volume->origin.z};
    out["spacing"] = volume->spacing;
    out["valid"] = owned(std::move(volume->valid), grid).attr("astype")("bool");
    out["coefficients"] = owned(std::move(volume->coefficients), {grid[0], grid[1], grid[2], py::ssize_t{kShCoefficients}, py::ssize_t{3}});
    flushWarnings();
    return out;
  }

 private:
  // Every output reads a solution: before the first solve() there is none, and the outputs would
  // be black or zero with nothing said.
  void requireSolved(const std::string& what) const {
    if (!solved_) raise(what + ": nothing is solved yet; call solve() first");
  }

  std::unique_ptr<Radiosity> engine_;
  bool solved_ = false;
  bool interrupted_ = false;    // the last solve was stopped by Ctrl-C
  RadiosityOptions options_;    // what the engine was made with, to make it again
};

}  // namespace

PYBIND11_MODULE(lambert, m) {
  m.doc() = "lambert: diffuse global illumination by radiosity (docs/python.md).";
  errorType() = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "lambert.Error", "An error from lambert: its message names the file, the place and how to proceed.", PyExc_RuntimeError, nullptr));
  m.attr("Error") = errorType();
  warningType() = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "lambert.Warning", "A problem lambert recovered from (a face a loader dropped, a damaged cache, clipped colours).",
      PyExc_UserWarning, nullptr));
  m.attr("Warning") = warningType();
  setWarningSink([](const std::string& message) {
    std::lock_guard<std::mutex> lock(pendingMutex);
    pendingWarnings().push_back(message);
  });
  m.attr("__version__") = LAMBERT_VERSION_STRING;

  py::enum_<LightKind>(m, "LightKind",
                       "What a Light is: POINT and SPOT (intensity, W/sr), DIRECTIONAL (a sun: irradiance, W/m² on a surface "
                       "facing it), SKY and LUMINAIRE (from scene files: a CIE sky, an IES or EULUMDAT luminaire).")
      .value("POINT", LightKind::Point)
      .value("SPOT", LightKind::Spot)
      .value("DIRECTIONAL", LightKind::Directional)
      .value("SKY", LightKind::Sky)
      .value("LUMINAIRE", LightKind::Luminaire);

  const Light defaults;
  py::class_<Light>(m, "Light",
                    "A light of a scene, in the scene's frame and units (as the file's loader gives them, y up: an MGF "
                    "file's (x, y, z) as (x, z, −y), docs/scene-format.md). POINT and SPOT: position, intensity "
                    "(W/sr per RGB channel; a spot's on its axis), a spot's direction, cone_angle_degrees (half-angle) and "
                    "falloff_degrees; DIRECTIONAL (a sun): direction (the way the light travels) and irradiance (W/m² per "
                    "channel on a surface facing it). Amounts must be finite and not negative.")
      .def(py::init([](LightKind kind, const std::vector<double>& position, const std::vector<double>& intensity,
                       const std::vector<double>& direction, double cone, double falloff, const std::vector<double>& irradiance) {
             Light l;
             l.kind = kind;
             l.position = vec3(position, "position");
             l.intensity = lightAmount(intensity, "intensity");
             l.direction = vec3(direction, "direction");
             if (!(length(l.direction) > 0)) raise("direction must not be (0, 0, 0)");
             l.direction = normalize(l.direction);
             if (!(cone > 0 && cone <= 90)) raise("cone_angle_degrees must lie in (0, 90]");
             if (!(falloff >= 0 && falloff <= cone)) raise("falloff_degrees must lie in [0, cone_angle_degrees]");
             l.coneAngleDegrees = cone;
             l.falloffDegrees = falloff;
             l.irradiance = lightAmount(irradiance, "irradiance");
             return l;
           }),
           py::arg("kind") = LightKind::Point, py::arg("position") = std::vector<double>{0, 0, 0},
           py::arg("intensity") = std::vector<double>{1, 1, 1},
           py::arg("direction") = std::vector<double>{defaults.direction.x, defaults.direction.y, defaults.direction.z},
           py::arg("cone_angle_degrees") = defaults.coneAngleDegrees, py::arg("falloff_degrees") = defaults.falloffDegrees,
           py::arg("irradiance") = std::vector<double>{0, 0, 0})
      .def_readwrite("name", &Light::name)
      .def_readwrite("kind", &Light::kind)
      .def_property("position", [](const Light& l) { return std::vector<double>{l.position.x, l.position.y, l.position.z}; },
                    [](Light& l, const std::vector<double>& v) { l.position = vec3(v, "position"); }, "scene units")
      .def_property("direction", [](const Light& l) { return std::vector<double>{l.direction.x, l.direction.y, l.direction.z}; },
                    [](Light& l, const std::vector<double>& v) { l.direction = vec3(v, "direction"); })
      .def_property("intensity", [](const Light& l) { return std::vector<double>{l.intensity.r, l.intensity.g, l.intensity.b}; },
                    [](Light& l, const std::vector<double>& v) { l.intensity = lightAmount(v, "intensity"); },
                    "W/sr per channel (point, spot)")
      .def_property("irradiance", [](const Light& l) { return std::vector<double>{l.irradiance.r, l.irradiance.g, l.irradiance.b}; },
                    [](Light& l, const std::vector<double>& v) { l.irradiance = lightAmount(v, "irradiance"); },
                    "W/m² per channel on a surface facing the light (directional: a sun's strength)")
      .def_readwrite("cone_angle_degrees", &Light::coneAngleDegrees)
      .def_readwrite("falloff_degrees", &Light::falloffDegrees)
      .def("__repr__", [](const Light& l) {
        return "<lambert.Light " + l.name + " at (" + std::to_string(l.position.x) + ", " + std::to_string(l.position.y) + ", " +
               std::to_string(l.position.z) + ")>";
      });

  py::class_<Scene>(m, "Scene", "A scene: its surfaces, materials, lights and camera, in its own units.")
      .def_readonly("name", &Scene::name)
      .def_readonly("metres_per_unit", &Scene::metresPerUnit)
      .def_property_readonly("surface_count", [](const Scene& s) { return s.surfaces.size(); })
      .def_property_readonly(
          "surface_names", [](const Scene& s) {
            std::vector<std::string> names;
            for (const Surface& surface : s.surfaces) names.push_back(surface.name);
            return names;
          },
          "Each surface's name (the file's object or group), in the order elements()['surface'] and triangle_surfaces() "
          "number them.")
      .def_property_readonly(
          "material_names", [](const Scene& s) {
            std::vector<std::string> names;
            for (const Material& material : s.materials) names.push_back(material.name);
            return names;
          },
          "Each material's name, as the file gives it.")
      .def_property_readonly(
          "surface_materials", [](const Scene& s) {
            std::vector<std::uint32_t> materials;
            for (const Surface& surface : s.surfaces) materials.push_back(static_cast<std::uint32_t>(surface.material));
            const auto count = static_cast<py::ssize_t>(materials.size());
            return owned(std::move(materials), {count});
          },
          "(surfaces,) uint32: each surface's material, an index into material_names; with elements()['surface'] or "
          "triangle_surfaces(), the material of every element or triangle.")
      .def_property_readonly(
          "material_albedo", [](const Scene& s) {
            std::vector<Rgb> albedo;
            for (const Material& material : s.materials) albedo.push_back(material.albedo);
            return rows3(std::move(albedo));
          },
          "(materials, 3) float64: each material's diffuse reflectance ρ (before its texture, if any).")
      .def_property(
          "lights", [](const Scene& s) { return py::tuple(py::cast(s.lights)); },
          [](Scene& s, const std::vector<Light>& lights) { s.lights = lights; },
          "The scene's lights, a tuple (a copy): assign a sequence to change them, e.g. scene.lights = [*scene.lights, light]. "
          "An engine made from the scene keeps its own: Radiosity.set_lights() moves those.");

  m.def(
      "load_scene",
      [](const std::string& nameOrPath, double units, double creaseAngle, std::optional<bool> twoSided, int mgfDivisions) {
        LoadOptions options;
        options.metresPerUnit = units;
        options.creaseAngleDegrees = creaseAngle;
        options.twoSided = twoSided;
        options.mgfDivisions = mgfDivisions;
        Scene scene = orRaise(loadScene(nameOrPath, options));
        flushWarnings();
        return scene;
      },
      py::arg("name_or_path"), py::arg("units") = 0.0, py::arg("crease_angle") = 20.0, py::arg("two_sided") = py::none(),
      py::arg("mgf_divisions") = 16,
      "A built-in scene by name ('cornell', …) or a scene file (.json, .gltf/.glb, .obj, .ply, .mgf), as `lambert solve --scene` "
      "loads it. units: metres per unit of an OBJ/PLY file (0: metres).");
  m.def(
      "annual_daylight",
      [](const Scene& scene, const std::string& weatherPath, double workPlane, double spacing, int skySubdivisions,
         int directSkySubdivisions, int sunSubdivisions, const std::string& cacheDir) {
        WeatherData weather = orRaise(readEpw(weatherPath));
        WorkPlaneSpec plane;
        plane.heightMetres = workPlane;
        plane.spacingMetres = spacing;
        const CalculationGrid grid = orRaise(workPlaneGrid(scene, plane));
        AnnualDaylightOptions options;
        for (const Light& light : scene.lights)
          if (light.kind == LightKind::Sky && light.sky) options.coefficients.north = light.sky->north();
        options.coefficients.skySubdivisions = skySubdivisions;
        options.coefficients.directSkySubdivisions = directSkySubdivisions;
        options.coefficients.sunSubdivisions = sunSubdivisions;
        options.cacheDirectory = cacheDir;
        AnnualDaylight year;
        {
          py::gil_scoped_release release;
          year = orRaise(annualDaylight(scene, grid.points, weather, options, RadiosityOptions{}));
        }
        const DaylightMetrics metrics = orRaise(daylightMetrics(year.illuminance));
        flushWarnings();
        const std::size_t n = grid.points.size(), hours = year.illuminance.hours.size();
        // sensors × hours, from the hour-major rows.
        auto bySensor = [&](const std::vector<float>& hourMajor) {
          std::vector<float> out(n * hours);
          for (std::size_t h = 0; h < hours; ++h)
            for (std::size_t s = 0; s < n; ++s) out[s * hours + h] = hourMajor[h * n + s];
          return owned(std::move(out), {static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(hours)});
        };
        std::vector<Vec3> positions;
        for (const CalculationPoint& p : grid.points) positions.push_back(p.position);
        std::vector<std::int32_t> when;
        for (const DaylightHourInfo& h : year.illuminance.hours) when.insert(when.end(), {h.month, h.day, h.hour});
        std::vector<double> da, udi, sunlit;
        for (const SensorDaylight& s : metrics.sensors) da.push_back(s.daylightAutonomy), udi.push_back(s.udiUseful), sunlit.push_back(s.sunlitHours);
        py::dict out;
        out["points"] = rows3(positions);
        out["hours"] = owned(std::move(when), {static_cast<py::ssize_t>(hours), py::ssize_t{3}});
        out["lux"] = bySensor(year.illuminance.totalLux);
        out["direct_sun_lux"] = bySensor(year.illuminance.directSunLux);
        out["sda_percent"] = metrics.spatialDaylightAutonomy;
        out["ase_percent"] = metrics.annualSunlightExposure;
        out["occupied_hours"] = metrics.occupiedHours;
        out["daylight_autonomy"] = owned(std::move(da), {static_cast<py::ssize_t>(n)});
        out["udi_useful"] = owned(std::move(udi), {static_cast<py::ssize_t>(n)});
        out["sunlit_hours"] = owned(std::move(sunlit), {static_cast<py::ssize_t>(n)});
        out["coefficient_seconds"] = year.coefficientSeconds;
        out["coefficients_from_cache"] = year.coefficientsFromCache;
        return out;
      },
      py::arg("scene"), py::arg("weather"), py::arg("work_plane") = 0.8, py::arg("spacing") = 0.6, py::arg("sky_subdivisions") = 1,
      py::arg("direct_sky_subdivisions") = 4, py::arg("sun_subdivisions") = 4, py::arg("cache_dir") = "",
      "A year of daylight from an EPW weather file, as `lambert daylight`: a dict of 'points' (n, 3), 'hours' (h, 3: month, day, "
      "hour ending), 'lux' and 'direct_sun_lux' (n, h) float32 (sensors × hours), 'sda_percent', 'ase_percent', "
      "'occupied_hours', per sensor 'daylight_autonomy', 'udi_useful' (% of occupied hours) and 'sunlit_hours', and "
      "'coefficient_seconds'. The scene's lights are left out; its sky's north is used.");
  m.def("setting_names", [] {
    std::vector<std::string> names;
    for (std::string n : solveSettingNames()) {
      n = n.substr(2);
      std::replace(n.begin(), n.end(), '-', '_');
      names.push_back(n);
    }
    return names;
  }, "The keyword names Radiosity takes: the CLI's solve options, '-' spelt '_'.");

  py::class_<PyRadiosity>(m, "Radiosity",
                          "A radiosity solve of a scene. Keywords are the CLI's solve options with '_' for '-' (link_error=1e-3, "
                          "method='flat', patches=2000, solver='gs', tolerance=1e-6, …; lambert.setting_names()); the defaults are the "
                          "CLI's. A keyword the chosen method would not read raises lambert.Error.")
      .def(py::init<Scene, const py::kwargs&>(), py::arg("scene"))
      .def("solve", &PyRadiosity::solve, py::arg("max_shots") = 0, py::arg("max_sweeps") = 0, py::arg("max_ms") = 0.0,
           "Solve to the tolerance, or within a budget (sweeps for gs/jacobi, shots for shoot, milliseconds for all). The GIL is "
           "released while it runs. Returns a dict: iterations, converged, lights_injected, unshot_fraction.")
      .def("set_lights", &PyRadiosity::setLights, py::arg("lights"),
           "Replace the lights; the next solve() traces only those that changed and starts warm.")
      .def_property_readonly("lights", &PyRadiosity::lights)
      .def_property_readonly("scene", &PyRadiosity::scene,
                             "A copy of the scene as solved, with the lights as set_lights() left them: its surface_names and "
                             "surface_materials are what elements()['surface'] and triangle_surfaces() index (a two-sided "
                             "face's back is a surface of its own, named '… (back)').")
      .def("vertex_positions", &PyRadiosity::vertexPositions, "(n, 3) float64: the exported mesh's vertices, scene units.")
      .def("vertex_radiance", &PyRadiosity::vertexRadiance, "(n, 3) float64: outgoing radiance L = B/π per vertex, W/(m²·sr).")
      .def("vertex_values", &PyRadiosity::vertexValues, py::arg("quantity"),
           "(n, 3) float64 per vertex, W/m²: 'radiosity', 'indirect_radiosity' or 'irradiance'.")
      .def("element_values", &PyRadiosity::elementValues, py::arg("quantity"),
           "(n, 3) float64 per element of the solution's mesh: 'radiosity' B and 'injected' ρ·E_direct and 'emitted' (W/m²), "
           "or 'albedo' ρ.")
      .def("elements", &PyRadiosity::elements,
           "The solution's elements: a dict of 'centroid' and 'normal' ((n, 3)), 'area' (scene units²), 'surface' (the "
           "scene surface each lies on) and 'open_fraction' (the share not covered by other geometry; 0 inside a closed object).")
      .def("illuminance", &PyRadiosity::illuminance, py::arg("points"), py::arg("indirect_rays") = 256,
           "Illuminance at points, as `lambert solve --points`: points an (n, 6) array of x, y, z, nx, ny, nz (scene frame "
           "and units); returns (n, 3) E_direct, E_indirect, E in lux (docs/photometry.md).")
      .def("triangles", &PyRadiosity::triangles, "(m, 3) uint32: the exported mesh's triangles, indices into vertex_positions().")
      .def("triangle_surfaces", &PyRadiosity::triangleSurfaces,
           "(m,) uint32: the scene surface each of triangles() lies on (as elements()['surface']).")
      .def("stats", &PyRadiosity::stats, "The figures `lambert solve --json` prints, as a dict.")
      .def("write_glb", &PyRadiosity::writeGlb, py::arg("path"), py::arg("bake") = "irradiance", py::arg("exposure") = 0.0,
           "Write the solved scene as binary glTF with the light in COLOR_0, as `lambert solve --export`.")
      .def("write_vertices", &PyRadiosity::writeVertices, py::arg("path"),
           "Write every vertex: position, normal, radiance (.csv or .ply), as `lambert solve --export-vertices`.")
      .def("render", &PyRadiosity::render, py::arg("path") = "", py::arg("width") = 512, py::arg("height") = 512,
           py::arg("exposure") = py::none(), py::arg("eye") = py::none(), py::arg("target") = py::none(), py::arg("up") = py::none(),
           py::arg("fov") = py::none(),
           "Draw the solution from eye toward target (given together, in the scene's frame and units as vertex_positions(); "
           "up and fov, the vertical field of view in degrees, optional), else from the scene's camera, else lambert's "
           "default view: an (height, width, 3) float64 array of "
           "radiance, W/(m²·sr); written as .png (tone mapped at `exposure` stops, else the scene's or automatic) or .exr "
           "(linear) where a path is given, as `lambert render`.")
      .def("bake_lightmaps", &PyRadiosity::bakeLightmaps, py::arg("path") = "", py::arg("texel_size") = 0.0,
           py::arg("size") = 1024, py::arg("padding") = 2, py::arg("step") = AdaptiveTexelOptions{}.coarsestStep,
           py::arg("tolerance") = AdaptiveTexelOptions{}.tolerance,
           "Lightmaps (hierarchical method): a dict with 'irradiance' (per atlas an (size, size, 3) float64 array of E, "
           "W/m²), 'covered' (per atlas a uint8 mask of the texels a face covers), 'texels_baked' and 'texels_gathered' "
           "(the rest interpolated); with a .glb path, written as `lambert solve --lightmaps --export` writes them. texel_size "
           "in metres (0: automatic), size, padding and step in texels, as --texel-size, --lightmap-size, --lightmap-padding, "
           "--lightmap-step and --lightmap-tolerance (step 1 gathers every texel).")
      .def("bake_probes", &PyRadiosity::bakeProbes, py::arg("path") = "", py::arg("spacing") = 0.0, py::arg("rays_per_probe") = 512,
           "An L2 SH irradiance volume: a dict with 'coefficients' ((nz, ny, nx, 9, 3) float32, W/m²), 'valid' "
           "((nz, ny, nx) bool), 'origin' and 'spacing' (scene units); written as lambert's probe file where a path is given "
           "(as `--probes`).");
}
