#include "lambert/render/scene_camera.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "lambert/geometry/ray_caster.h"
#include "lambert/mesh/mesh.h"

namespace lambert {
namespace {

constexpr int kGrid = 8;             // candidate points per axis of the bounds
constexpr int kRays = 128;           // directions cast from each
constexpr int kMaxEscaping = 6;      // an enclosed point: at most this many rays (5%) reach infinity
constexpr double kMaxBackShare = 0.05;  // … and at most this share meet the back of a one-sided face
constexpr double kMinEnclosedShare = 0.1;  // a closed scene: at least this share of the points enclosed
constexpr int kAzimuths = 64;        // horizontal view directions tried from the chosen point
constexpr int kFanColumns = 9, kFanRows = 7;  // rays over the picture of each, 4:3
constexpr double kInsideFovDegrees = 60;

// kRays directions spread evenly over the sphere (a spherical Fibonacci lattice), the same for
// every scene, so the choice is deterministic.
std::vector<Vec3> sphereDirections() {
  std::vector<Vec3> d;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < kRays; ++i) {
    const double z = 1 - (2 * i + 1.0) / kRays, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = golden * i;
    d.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return d;
}

// Distance to the nearest front face along a ray; infinity where the ray escapes or meets a back.
double freeDistance(const RayCaster& caster, const Vec3& origin, const Vec3& direction) {
  const std::optional<RayHit> hit = caster.intersect(Ray{origin, direction, 0, INFINITY});
  return hit && hit->frontFace ? hit->t : INFINITY;
}

// How far a ray from a point inside the box [lo, hi] runs before it leaves it.
double boundsExit(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& direction) {
  double t = INFINITY;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = axis == 0 ? origin.x : axis == 1 ? origin.y : origin.z;
    const double d = axis == 0 ? direction.x : axis == 1 ? direction.y : direction.z;
    const double l = axis == 0 ? lo.x : axis == 1 ? lo.y : lo.z, h = axis == 0 ? hi.x : axis == 1 ? hi.y : hi.z;
    if (d > 0) t = std::min(t, (h - o) / d);
    if (d < 0) t = std::min(t, (l - o) / d);
  }
  return std::isfinite(t) ? std::max(t, 0.0) : 0.0;
}

// Which way is up for the default view: the file's up axis, unless the emitters' mean normal (by
// area; ceiling lights face down) lies within 30° of another axis of the file's frame pointing
// down, as in MGF files written y-up. Back twins are left out (they would cancel their fronts).
Vec3 viewUp(const Scene& scene) {
  const Vec3 fileUp = normalize(scene.fileFrame.sceneDirection(scene.fileFrame.up));
  Vec3 facing;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    if (surface.emittedRadiance.maxComponent() <= 0 || (surface.twin >= 0 && static_cast<std::size_t>(surface.twin) < s)) continue;
    facing = facing + surfaceNormal(surface) * surfaceArea(surface);
  }
  if (!(length(facing) > 0)) return fileUp;
  const Vec3 down = normalize(facing);
  for (const Vec3& axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
    for (double sign : {1.0, -1.0}) {
      const Vec3 up = normalize(scene.fileFrame.sceneDirection(axis * sign));
      if (dot(down, -up) > std::cos(30 * kPi / 180)) return up;
    }
  return fileUp;
}

}  // namespace

ChosenCamera defaultCamera(const Scene& scene) {
  ChosenCamera chosen{cameraViewingScene(scene), CameraSource::Outside};
  if (scene.surfaces.empty()) return chosen;
  const auto [lo, hi] = sceneBounds(scene);
  const double diagonal = length(hi - lo);
  if (!(diagonal > 0) || !std::isfinite(diagonal)) return chosen;
  // Outside: from in front (−z), raised 25° above the horizon, so that a floor and what stands on
  // it are seen from above rather than edge-on.
  const Vec3 up = viewUp(scene);
  Vec3 front = Vec3{0, 0, -1} - up * dot(Vec3{0, 0, -1}, up);
  front = length(front) > 1e-6 ? normalize(front) : normalize(Vec3{1, 0, 0} - up * dot(Vec3{1, 0, 0}, up));
  const double elevation = 25 * kPi / 180;
  chosen.camera.eye = chosen.camera.target + (front * std::cos(elevation) + up * std::sin(elevation)) * (1.5 * diagonal);
  chosen.camera.up = up;
  const Mesh mesh = subdivideScene(scene, 2 * diagonal);
  const std::unique_ptr<RayCaster> caster = makeEmbreeRayCaster(mesh);
  const std::vector<Vec3> directions = sphereDirections();

  // The enclosed candidate with the longest mean free path.
  std::optional<Vec3> best;
  double bestFreePath = 0;
  int enclosed = 0;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j)
      for (int k = 0; k < kGrid; ++k) {
        const Vec3 f{(i + 0.5) / kGrid, (j + 0.5) / kGrid, (k + 0.5) / kGrid};
        const Vec3 p{lo.x + (hi.x - lo.x) * f.x, lo.y + (hi.y - lo.y) * f.y, lo.z + (hi.z - lo.z) * f.z};
        int escaping = 0, back = 0, front = 0;
        double distance = 0;
        for (const Vec3& d : directions) {
          const std::optional<RayHit> hit = caster->intersect(Ray{p, d, 0, INFINITY});
          if (!hit) {
            ++escaping;
          } else if (!hit->frontFace) {
            ++back;
          } else {
            ++front;
            distance += hit->t;
          }
          if (back > kMaxBackShare * kRays) break;
        }
        if (back > kMaxBackShare * kRays || front == 0) continue;  // behind a wall, or in a solid
        if (escaping > kMaxEscaping) continue;
        ++enclosed;
        const double freePath = distance / front;
        if (freePath > bestFreePath) bestFreePath = freePath, best = p;
      }
  // Pockets inside closed objects (a two-sided sphere) in an open scene do not make it closed.
  if (!best || enclosed < kMinEnclosedShare * kGrid * kGrid * kGrid) return chosen;

  Vec3 eye = *best;
  const double down = freeDistance(*caster, eye, -up), above = freeDistance(*caster, eye, up);
  if (std::isfinite(down) && std::isfinite(above)) eye = eye + up * (0.55 * (down + above) - down);

  // The longest horizontal line of sight through the eye, among those whose view (a fan of rays
  // over the picture, from the eye set back along the line) meets the most front faces: look
  // along it from near its far end.
  Vec3 side, ahead;
  orthonormalBasis(up, side, ahead);
  const double tanHalf = std::tan(kInsideFovDegrees * kPi / 360);
  double bestSeen = -1, longest = -1, forward = 0;
  Vec3 look = ahead, bestEye = eye;
  for (int a = 0; a < kAzimuths; ++a) {
    const double angle = 2 * kPi * a / kAzimuths;
    const Vec3 d = side * std::cos(angle) + ahead * std::sin(angle);
    const double plus = freeDistance(*caster, eye, d);
    if (!std::isfinite(plus)) continue;  // looking out through an opening
    // Behind the eye an opening (a box open on one side): back to the scene's bounds.
    double minus = freeDistance(*caster, eye, -d);
    if (!std::isfinite(minus)) minus = boundsExit(lo, hi, eye, -d);
    const Vec3 from = eye - d * (0.8 * minus);
    const Vec3 right = normalize(cross(d, up));
    int seen = 0;
    for (int i = 0; i < kFanColumns; ++i)
      for (int j = 0; j < kFanRows; ++j) {
        const double x = (2.0 * i / (kFanColumns - 1) - 1) * tanHalf * 4 / 3, y = (2.0 * j / (kFanRows - 1) - 1) * tanHalf;
        seen += std::isfinite(freeDistance(*caster, from, d + right * x + up * y));
      }
    const double share = static_cast<double>(seen) / (kFanColumns * kFanRows);
    // A view that sees more faces (less background through openings) wins; among views alike,
    // the longer line.
    if (share > bestSeen || (share == bestSeen && plus + minus > longest)) {
      bestSeen = share;
      longest = plus + minus;
      look = d;
      forward = plus;
      bestEye = from;
    }
  }
  eye = bestEye;
  chosen.camera.eye = eye;
  chosen.camera.target = eye + look * std::max(forward, 1e-3 * diagonal);
  chosen.camera.up = up;
  chosen.camera.verticalFovDegrees = kInsideFovDegrees;
  chosen.source = CameraSource::Inside;
  return chosen;
}

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

const char* cameraSourceName(CameraSource source) {
  switch (source) {
    case CameraSource::Request: return "--eye/--target";
    case CameraSource::Scene: return "scene";
    case CameraSource::Inside: return "default, inside (closed scene)";
    case CameraSource::Outside: return "default, outside (open scene)";
  }
  return "";
}

Result<ChosenCamera> sceneCamera(const Scene& scene, const CameraRequest& request) {
  if (request.eye.has_value() != request.target.has_value())
    return Error{request.eye ? "--eye needs --target: give the point the camera looks at (scene file coordinates)"
                             : "--target needs --eye: give where the camera stands (scene file coordinates)"};
  for (const auto& [name, value] : {std::pair{"--eye", request.eye}, std::pair{"--target", request.target}, std::pair{"--up", request.up}})
    if (value && !finite(*value)) return Error{std::string(name) + " must be three finite numbers X,Y,Z"};
  if (request.verticalFovDegrees && !(*request.verticalFovDegrees > 0 && *request.verticalFovDegrees < 180))
    return Error{"--fov must be a vertical field of view between 0 and 180 degrees"};

  ChosenCamera chosen{{}, CameraSource::Request};
  Camera& camera = chosen.camera;
  if (request.eye) {
    camera.eye = scene.fileFrame.scenePoint(*request.eye);
    camera.target = scene.fileFrame.scenePoint(*request.target);
    camera.up = normalize(scene.fileFrame.sceneDirection(scene.fileFrame.up));
    camera.verticalFovDegrees = scene.cameraGiven ? scene.camera.verticalFovDegrees : Camera{}.verticalFovDegrees;
  } else {
    chosen = scene.cameraGiven ? ChosenCamera{scene.camera, CameraSource::Scene} : defaultCamera(scene);
  }
  if (request.up) {
    if (!(length(*request.up) > 0)) return Error{"--up must not be zero"};
    camera.up = normalize(scene.fileFrame.sceneDirection(*request.up));
  }
  if (request.verticalFovDegrees) camera.verticalFovDegrees = *request.verticalFovDegrees;
  const Vec3 view = camera.target - camera.eye;
  if (!(length(view) > 1e-12 * std::max(1.0, length(camera.eye))))
    return Error{"--target must differ from --eye (the camera looks from the eye towards the target)"};
  if (!(length(cross(normalize(view), camera.up)) > 1e-9))
    return Error{"--up must not be parallel to the view direction from --eye to --target: give another --up X,Y,Z"};
  return chosen;
}

}  // namespace lambert
