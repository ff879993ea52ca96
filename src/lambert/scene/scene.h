#pragma once
// A scene as plain data: what is there, what it is made of, what emits, and where the eye is.
// Geometry is in scene units (metresPerUnit converts them to metres, for power in watts).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lambert/core/rgb.h"
#include "lambert/core/vec3.h"

namespace lambert {

class SkyModel;  // light/sky.h
class Photometry;  // light/photometry.h

// A colour texture (albedo or emission), decoded to linear RGB (sRGB files are decoded on load),
// that multiplies a material's factor. Texture coordinate
// (0, 0) is the first pixel of the first row, (1, 1) the far corner of the last, as in glTF;
// coordinates outside [0, 1] repeat.
struct Texture {
  std::string path;  // where it was read from, for messages and export
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row by row, linear factors in [0, 1]
  double peak = 0;          // the largest channel of any pixel
  Rgb mean;                 // the mean pixel
  // The bilinearly filtered value at (u, v), repeating.
  Rgb sample(double u, double v) const;
};

struct Material {
  std::string name;
  Rgb albedo;  // diffuse reflectance ρ per channel, dimensionless, in [0, 1); times the texture
  // Faces of a two-sided material are solved as two surfaces back to back, each with its own
  // radiosity (Surface::twin); one-sided faces have a black, opaque back.
  bool twoSided = false;
  std::shared_ptr<const Texture> texture = nullptr;  // ρ = albedo × texture(u, v), averaged per patch
  // L_e = the surface's emittedRadiance × emissionTexture(u, v), averaged per patch (glTF's
  // emissiveTexture, MTL's map_Ke); none: emittedRadiance is uniform.
  std::shared_ptr<const Texture> emissionTexture = nullptr;
};

struct Uv {
  double u = 0, v = 0;
  bool operator==(const Uv&) const = default;
};

// A surface is one smooth region: one or more convex polygons (faces) over shared vertices, all of
// one material. Faces run counter-clockwise seen from the front, so a face's normal
// cross(v1 - v0, v2 - v0) points to the side that emits and reflects (the back is black and
// opaque). Faces that share an edge are meshed conforming across it and shaded smoothly across
// it; nothing is shared between surfaces, so nothing is ever averaged across a crease or a
// material boundary. A face need not be exactly planar: it is split into its triangle fan.
struct Surface {
  std::string name;
  std::vector<Vec3> vertices;
  int material = 0;
  Rgb emittedRadiance;  // L_e in W/(m²·sr), times the material's emissionTexture where it has one;
                        // emitted radiosity E = π·L_e in W/m²
  // Each face's vertex indices; empty: the one polygon of all the vertices in order (the
  // built-in scenes, and a scene file's inline polygons).
  std::vector<std::vector<std::uint32_t>> faces = {};
  // Texture coordinates per face corner, parallel to surfaceFaces(); empty when untextured.
  // (Per corner, not per vertex: a UV seam runs through a smooth region without splitting it.)
  std::vector<std::vector<Uv>> faceUvs = {};
  // Lightmap coordinates per face corner, parallel to surfaceFaces() (glTF's TEXCOORD_1, a scene
  // file's second set); empty when the file gives none (mesh/lightmap_uvs.h).
  std::vector<std::vector<Uv>> faceLightmapUvs = {};
  // The surface lying back to back on this one (its faces reversed) when its material is
  // two-sided, else -1. A ray or a camera that meets the back of either meets the other's front.
  int twin = -1;
};

// The maintenance factor of an electric light (CIE 97:2005, EN 12464-1 §4.9): the share of its
// new light a design counts on at the end of its maintenance cycle, MF = LLMF × LSF × LMF × RSMF.
// Each factor lies in (0, 1]. As lighting programs do, the whole product scales the light's
// output, the room-surface factor included (CIE 97 would darken the surfaces by it instead; the
// difference is a second-order term of the reflected light), so that every illuminance computed
// is the maintained one.
struct Maintenance {
  double lampLumen = 1;     // LLMF: the lamps' lumen maintenance
  double lampSurvival = 1;  // LSF: the lamps' survival (spot replacement: 1)
  double luminaire = 1;     // LMF: the luminaire's dirt depreciation
  double roomSurface = 1;   // RSMF: the room surfaces' dirt depreciation
  double factor() const { return lampLumen * lampSurvival * luminaire * roomSurface; }
  bool operator==(const Maintenance&) const = default;
};

// A light without area: its light enters the radiosity solution as the direct
// irradiance it gives each patch (Keller's instant radiosity injection), and is drawn per pixel.
enum class LightKind {
  Point,        // radiant intensity I in every direction
  Spot,         // I along its axis, fading to zero at the cone's edge
  Directional,  // parallel light (a sun): irradiance E⊥ on a surface facing it, from infinitely far
  Sky,          // a sky dome at infinity (light/sky.h): radiance L(ω) above the horizon, entering
                // through whatever openings the scene's geometry leaves
  Luminaire,    // a measured luminaire: intensity from its goniometric distribution (light/photometry.h)
};

// How a luminaire's light leaves it (docs/photometry.md, "Luminaires").
enum class LuminaireModel {
  FarField,  // a point source at its photometric centre: exact beyond about 5 luminaire sizes
  Opening,   // its luminous opening as a grid of point sources sharing the intensity: the near field
};

// The default direction count of a sky light's irradiance estimate (light/sky.h skyIlluminance):
// chosen so that a window seen from inside a room gives under 1% error (docs/photometry.md, "Daylight").
inline constexpr int kDefaultSkyDirections = 4096;
// How far a sky's estimate follows an opening's edges (light/sky.h skyIlluminance): Traced (a
// calculation point's sky: the edges followed into the cells beyond and their sub-cells refined)
// or Cells (a patch's sky in the solve: the cells on an edge resampled once, no further; 35% fewer
// rays there, and a daylit office's solve 60% faster, where a patch's reflected light forgives the
// 1.6% that the façade window's worst work-plane point shows at 4096 directions).
enum class SkyEdges { Cells, Traced };

struct Light {
  std::string name;
  LightKind kind = LightKind::Point;
  Vec3 position;                // point, spot, luminaire: scene units (luminaire: photometric centre)
  Vec3 direction{0, -1, 0};     // spot: cone axis; directional: the way the light travels;
                                // luminaire: its aim, the photometric nadir γ = 0 (default straight down)
  // Point, spot: radiant intensity I in W/sr (spot: on its axis). Luminaire: colour × multiplier (white:
  // 1 per channel); it sends I [W/sr] = candela × intensity / 683 lm/W per channel, so that the lux
  // of its irradiance (683 × Rec. 709 luminance) is the photometric illuminance.
  Rgb intensity;
  Rgb irradiance;               // directional: E⊥ in W/m² on a surface facing the light
  double coneAngleDegrees = 30; // spot: half-angle of the cone, where the light reaches zero
  double falloffDegrees = 5;    // spot: width of the smooth edge inside the cone (the seed's "focus")
  Vec3 angularVelocity;         // rad/s about the world x, y, z axes: turns `direction` over time
  std::shared_ptr<const SkyModel> sky;       // sky: its luminance distribution and scale
  int skyDirections = kDefaultSkyDirections;  // sky: directions per irradiance estimate
  // Luminaire: the candela distribution (shared by every light of one file), its Spin in degrees,
  // the turn of its C = 0 half plane about the aim (counter-clockwise seen from behind the
  // luminaire, as C runs) from where the IES LM-72 aim-point angles of `direction` put it
  // (light/lights.h luminaireFrame: along +x for a downlight, on the upper side of a tilted aim's
  // vertical plane), how its light leaves it, and the grid of its opening per side (Opening model).
  std::shared_ptr<const Photometry> photometry = nullptr;
  double rotationDegrees = 0;
  LuminaireModel luminaireModel = LuminaireModel::FarField;
  int openingSamplesPerSide = 4;
  // Point, spot, luminaire: its maintenance factor, already folded into `intensity` (whose
  // values, and every illuminance from them, are maintained values); kept for reports and for
  // writing the scene back.
  Maintenance maintenance;

  bool operator==(const Light&) const = default;
};

struct Camera {
  Vec3 eye;
  Vec3 target;           // a point the camera looks at
  Vec3 up{0, 1, 0};
  double verticalFovDegrees = 40;
};

// What a scene file suggests for solving it, taken where the command line does not say.
struct SuggestedSettings {
  std::size_t patches = 0;     // uniform mesh: target patch count; 0: the program's default
  double maxEdgeLength = 0;    // uniform mesh: longest patch edge in scene units (instead of patches)
  std::string solver;          // "direct", "gs", "jacobi" or "shoot"; empty: the program's default
  double tolerance = 0;        // iterative solvers' relative tolerance; 0: the program's default
};

// The coordinates a scene's file writes, and where the loader put them: an MGF file is z-up and
// lambert is y-up, so its loader turns every point it reads. A camera or a point given in the
// file's own terms (`--eye`, `lambert info`'s bounds) goes through this frame, so that it lands
// where the file means it.
struct FileFrame {
  // File point p lies at scene point offset + axes[0]·p.x + axes[1]·p.y + axes[2]·p.z (an
  // invertible linear map: a rotation times a scale).
  Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 offset;
  Vec3 up{0, 1, 0};  // the file's up direction, in file coordinates

  Vec3 sceneDirection(const Vec3& fileDirection) const {
    return axes[0] * fileDirection.x + axes[1] * fileDirection.y + axes[2] * fileDirection.z;
  }
  Vec3 scenePoint(const Vec3& filePoint) const { return offset + sceneDirection(filePoint); }
  // The file point at a scene point (the inverse map, by Cramer's rule).
  Vec3 filePoint(const Vec3& scenePoint) const;
};

struct Scene {
  std::string name;
  std::vector<Material> materials;
  std::vector<Surface> surfaces;
  std::vector<Light> lights;
  Camera camera;
  // Whether `camera` was given (by the scene file, the glTF, the built-in scene), rather than the
  // outside view the loader computed from the bounds (cameraViewingScene); a camera that is not
  // given is chosen by defaultCamera (render/scene_camera.h).
  bool cameraGiven = false;
  // Exposure in stops that images of the scene are taken at (radiance × 2^stops before sRGB);
  // empty: automatic, from each image (render/tonemap.h). The built-in scenes are calibrated to 0.
  std::optional<double> exposureStops;
  double metresPerUnit = 1;  // 0.001 for a scene in millimetres
  FileFrame fileFrame;       // identity except for loaders that turn or scale what they read
  SuggestedSettings defaults;
};

// The surface's faces as vertex-index lists (the single polygon when Surface::faces is empty).
std::vector<std::vector<std::uint32_t>> surfaceFaces(const Surface& surface);
// One of them, without building the rest.
std::vector<std::uint32_t> surfaceFace(const Surface& surface, std::size_t index);
// The corner positions of one face.
std::vector<Vec3> facePositions(const Surface& surface, const std::vector<std::uint32_t>& face);
// Unit normal of a polygon by Newell's method (robust for slightly non-planar ones); of a
// surface, its area-weighted mean over the faces.
Vec3 polygonNormal(const std::vector<Vec3>& polygon);
// Newell's vector: the normal times twice the area (robust for non-planar polygons too).
Vec3 polygonAreaVector(const std::vector<Vec3>& polygon);
// The diagonal of a polygon's bounding box: the scale its tolerances are taken from.
double polygonExtent(const std::vector<Vec3>& polygon);
// The first corner (index) at which the polygon, seen along `normal`, turns the wrong way, or
// polygon.size() when it is convex: every turn the same way, and once around (a pentagram turns
// one way too; it gives 0).
std::size_t firstConcaveCorner(const std::vector<Vec3>& polygon, const Vec3& normal);
Vec3 surfaceNormal(const Surface& surface);
// Area of a surface in scene units², as the sum of its faces' fan triangles.
double surfaceArea(const Surface& surface);

// Gives every surface of a two-sided material that has no twin yet its twin: a copy with every
// face reversed (first corner kept, so both are fanned into the same triangles), named
// "<name> (back)", appended to scene.surfaces. Every loader calls this last.
void addTwins(Scene& scene);

// Whether any surface emits (its material's emitted radiance above zero in some channel).
bool anyEmits(const Scene& scene);

// The axis-aligned bounding box of every surface vertex, scene units.
struct Bounds {
  Vec3 lo, hi;
};
Bounds sceneBounds(const Scene& scene);

// A camera that sees the whole scene, for files that have none: from in front (−z) of its
// bounding box, 1.5 diagonals away, looking at its centre, 40° vertical field of view.
Camera cameraViewingScene(const Scene& scene);

}  // namespace lambert
